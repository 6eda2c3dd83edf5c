/* dbinput.c - queries of geosep.Database by input vertex id (a database
 * built from a repaired Mesh, or with geosep build --repair: doc/repair.md):
 * input_distance, input_field, input_aliases, n_input_vertices. Each input
 * vertex answers the least distance over the vertices it became. Ids are
 * checked before any call into the library; batches run without the GIL. */
#include "geosep_py.h"

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

PyObject *gspy_db_input_distance(PyObject *self_obj, PyObject *args)
{
    PyObject *x, *y;
    if (!PyArg_UnpackTuple(args, "input_distance", 2, 2, &x, &y)) return NULL;
    return gspy_db_pairs((gspy_Database *)self_obj, x, y, 1);
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
