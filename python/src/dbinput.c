/* dbinput.c - queries of geosep.Database by input vertex id (a database
 * built from a repaired Mesh, or with geosep build --repair: doc/repair.md):
 * input_distance, input_field, input_aliases, n_input_vertices. Each input
 * vertex answers the least distance over the vertices it became. Ids are
 * checked before any call into the library; batches run without the GIL. */
#include "geosep_py.h"

#define CHUNK 65536 /* pairs per call of gs_db_input_distances */

const char gspy_db_input_distance_doc[] =
    "input_distance($self, x, y, /)\n--\n\n"
    "Distance between input vertices x and y: the ids of the mesh before\n"
    "repair (Mesh(..., repair=True) or Mesh.load(..., repair=True), then\n"
    "Database.build; geosep build --repair). Each answers the least distance\n"
    "over the vertices it became (a split vertex: itself and its copies; a\n"
    "welded one: the vertex it was welded into); 0 for x == y. Without a\n"
    "repair, input ids are the vertex ids and this is distance(). Two ints\n"
    "give a float; arrays broadcast as numpy does (a float64 array). IndexError\n"
    "for an id >= n_input_vertices. Batches run without the GIL.";

static int check_ids(PyArrayObject *a, uint32_t limit, const char *name)
{
    const int64_t *ids = PyArray_DATA(a);
    npy_intp n = PyArray_SIZE(a);
    for (npy_intp i = 0; i < n; i++)
        if (ids[i] < 0 || (uint64_t)ids[i] >= limit) {
            PyErr_Format(PyExc_IndexError, "input vertex id %lld (%s, flat index %zd) is out of range [0, %u)",
                         (long long)ids[i], name, (Py_ssize_t)i, limit);
            return -1;
        }
    return 0;
}

PyObject *gspy_db_input_distance(PyObject *self_obj, PyObject *args)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    PyObject *x, *y;
    if (!PyArg_UnpackTuple(args, "input_distance", 2, 2, &x, &y)) return NULL;
    uint32_t n = gs_db_num_input_vertices(self->db), a, b;
    if (gspy_is_int_scalar(x) && gspy_is_int_scalar(y)) {
        if (gspy_index(x, n, "input vertex id", &a) < 0 || gspy_index(y, n, "input vertex id", &b) < 0) return NULL;
        return PyFloat_FromDouble(gs_db_input_distance(self->db, a, b));
    }
    PyObject *result = NULL, *out = NULL;
    PyArrayMultiIterObject *it = NULL;
    uint32_t *pairs = NULL;
    PyArrayObject *ax = gspy_int_array(x, "x"), *ay = ax ? gspy_int_array(y, "y") : NULL;
    if (!ay || check_ids(ax, n, "x") < 0 || check_ids(ay, n, "y") < 0) goto done;
    it = (PyArrayMultiIterObject *)PyArray_MultiIterNew(2, (PyObject *)ax, (PyObject *)ay);
    if (!it) goto done; /* ValueError: shapes that do not broadcast */
    out = PyArray_SimpleNew(it->nd, it->dimensions, NPY_DOUBLE);
    pairs = PyMem_New(uint32_t, 2 * CHUNK);
    if (!out || !pairs) {
        if (out) PyErr_NoMemory();
        goto done;
    }
    double *d = PyArray_DATA((PyArrayObject *)out);
    npy_intp size = it->size, done = 0;
    while (done < size) {
        npy_intp k = 0;
        for (; k < CHUNK && PyArray_MultiIter_NOTDONE(it); k++) {
            pairs[2 * k] = (uint32_t) * (const int64_t *)PyArray_MultiIter_DATA(it, 0);
            pairs[2 * k + 1] = (uint32_t) * (const int64_t *)PyArray_MultiIter_DATA(it, 1);
            PyArray_MultiIter_NEXT(it);
        }
        gs_error err = {0};
        int rc;
        Py_BEGIN_ALLOW_THREADS
        rc = gs_db_input_distances(self->db, pairs, (size_t)k, d + done, &err);
        Py_END_ALLOW_THREADS
        if (rc) {
            gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
            goto done;
        }
        done += k;
    }
    if (it->nd == 0) {
        result = PyFloat_FromDouble(d[0]);
    } else {
        result = out;
        out = NULL;
    }
done:
    PyMem_Free(pairs);
    Py_XDECREF(out);
    Py_XDECREF((PyObject *)it);
    Py_XDECREF(ax);
    Py_XDECREF(ay);
    return result;
}

const char gspy_db_input_field_doc[] =
    "input_field($self, x, /)\n--\n\n"
    "Returns an (n_input_vertices,) float64 array:\n"
    "input_distance(x, v) for every input vertex v (+inf where unreachable).\n"
    "Runs without the GIL.";

PyObject *gspy_db_input_field(PyObject *self_obj, PyObject *arg)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    uint32_t n = gs_db_num_input_vertices(self->db), x;
    if (gspy_index(arg, n, "input vertex id", &x) < 0) return NULL;
    npy_intp dims[1] = {n};
    PyObject *out = PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!out) return NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_input_field(self->db, x, PyArray_DATA((PyArrayObject *)out), &err);
    Py_END_ALLOW_THREADS
    if (rc) {
        Py_DECREF(out);
        return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    }
    return out;
}

const char gspy_db_input_aliases_doc[] =
    "input_aliases($self, v, /)\n--\n\n"
    "Returns a (k,) uint32 array:\n"
    "the vertices input vertex v became (the first the one it became, then\n"
    "increasing), as the database stores them; [v] without a repair.";

PyObject *gspy_db_input_aliases(PyObject *self_obj, PyObject *arg)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    uint32_t v;
    if (gspy_index(arg, gs_db_num_input_vertices(self->db), "input vertex id", &v) < 0) return NULL;
    npy_intp dims[1] = {gs_db_input_aliases(self->db, v, NULL, 0)};
    PyObject *out = PyArray_SimpleNew(1, dims, NPY_UINT32);
    if (!out) return NULL;
    gs_db_input_aliases(self->db, v, PyArray_DATA((PyArrayObject *)out), (uint32_t)dims[0]);
    return out;
}

PyObject *gspy_db_get_n_input_vertices(PyObject *self_obj, void *closure)
{
    (void)closure;
    return PyLong_FromUnsignedLong(gs_db_num_input_vertices(((gspy_Database *)self_obj)->db));
}
