/* dbwithin.c - neighbourhoods of geosep.Database: within (every vertex
 * within a radius), nearest (the k nearest among candidates) and
 * radius_matrix (CSR arrays for many sources). Ids are checked before any
 * call into the library; the GIL is released around each call (the
 * database is immutable). */
#include "geosep_py.h"

#include <math.h>
#include <string.h>

/* The radius: a real number >= 0 (inf allowed). -1 with ValueError. */
static int get_radius(PyObject *obj, double *r)
{
    double v = PyFloat_AsDouble(obj);
    if (v == -1.0 && PyErr_Occurred()) return -1;
    if (!(v >= 0.0)) {
        PyErr_Format(PyExc_ValueError, "radius %R: must be a number >= 0 (inf: every connected vertex)", obj);
        return -1;
    }
    *r = v;
    return 0;
}

/* A 1-D list of vertex ids as uint32 (PyMem_Free), checked. */
static uint32_t *ids_1d(PyObject *obj, uint32_t limit, const char *name, npy_intp *n)
{
    PyArrayObject *a = gspy_int_array(obj, name);
    if (!a) return NULL;
    uint32_t *ids = NULL;
    if (PyArray_NDIM(a) != 1) {
        PyErr_Format(PyExc_ValueError, "%s must be a 1-D sequence of vertex ids, got %d dimensions", name,
                     PyArray_NDIM(a));
        Py_DECREF(a);
        return NULL;
    }
    *n = PyArray_SIZE(a);
    const int64_t *v = PyArray_DATA(a);
    for (npy_intp i = 0; i < *n; i++)
        if (v[i] < 0 || (uint64_t)v[i] >= limit) {
            PyErr_Format(PyExc_IndexError, "vertex id %lld (%s, index %zd) is out of range [0, %u)", (long long)v[i],
                         name, (Py_ssize_t)i, limit);
            Py_DECREF(a);
            return NULL;
        }
    ids = PyMem_New(uint32_t, (size_t)*n + 1);
    if (!ids) PyErr_NoMemory();
    for (npy_intp i = 0; ids && i < *n; i++) ids[i] = (uint32_t)v[i];
    Py_DECREF(a);
    return ids;
}

/* (ids int64, distances float64) from a result; NULL with an exception. */
static PyObject *pair_of_arrays(const gs_neighbors *nb)
{
    npy_intp dims[1] = {(npy_intp)nb->n};
    PyObject *ids = PyArray_SimpleNew(1, dims, NPY_INT64), *d = PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!ids || !d) {
        Py_XDECREF(ids);
        Py_XDECREF(d);
        return NULL;
    }
    int64_t *o = PyArray_DATA((PyArrayObject *)ids);
    for (size_t i = 0; i < nb->n; i++) o[i] = nb->ids[i];
    if (nb->n) memcpy(PyArray_DATA((PyArrayObject *)d), nb->dist, nb->n * sizeof *nb->dist);
    return Py_BuildValue("(NN)", ids, d);
}

const char gspy_db_within_doc[] =
    "within($self, x, r, /)\n--\n\n"
    "Returns (ids, distances): every vertex whose database distance from\n"
    "vertex x is at most r, by increasing distance (ties: lower id first), as\n"
    "an int64 and a float64 array. x itself comes first at 0; r = inf lists\n"
    "every vertex connected to x. Exactly the vertices of field(x) <= r, with\n"
    "the same distances; whole parts of the database's tree are skipped by\n"
    "stored lower bounds, so a small radius costs a small part of a field\n"
    "(the first call on a database computes those bounds, about the time of\n"
    "one field). IndexError for x out of range, ValueError for a\n"
    "negative or NaN r. Runs without the GIL.";

PyObject *gspy_db_within(PyObject *self_obj, PyObject *args)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    PyObject *x_obj, *r_obj;
    if (!PyArg_UnpackTuple(args, "within", 2, 2, &x_obj, &r_obj)) return NULL;
    uint32_t x;
    double r;
    if (gspy_index(x_obj, self->n_vertices, "vertex id", &x) < 0 || get_radius(r_obj, &r) < 0) return NULL;
    gs_neighbors *nb = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_within(self->db, x, r, &nb, &err);
    Py_END_ALLOW_THREADS
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    PyObject *out = pair_of_arrays(nb);
    gs_neighbors_free(nb);
    return out;
}

const char gspy_db_nearest_doc[] =
    "nearest($self, x, candidates, k, /)\n--\n\n"
    "Returns (ids, distances): the k vertices among candidates (a 1-D\n"
    "sequence of vertex ids; a repeated id counts once) nearest to vertex x by\n"
    "the database's distances, by increasing distance (ties: lower id first),\n"
    "as an int64 and a float64 array of min(k, distinct candidates) entries;\n"
    "candidates not connected to x come last at inf. Candidates are answered\n"
    "in increasing order of stored lower bounds until the bound exceeds the\n"
    "k-th distance found, so far candidates cost little. IndexError for an id\n"
    "out of range, ValueError for a negative k. Runs without the GIL.";

PyObject *gspy_db_nearest(PyObject *self_obj, PyObject *args)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    PyObject *x_obj, *c_obj, *k_obj;
    if (!PyArg_UnpackTuple(args, "nearest", 3, 3, &x_obj, &c_obj, &k_obj)) return NULL;
    uint32_t x;
    if (gspy_index(x_obj, self->n_vertices, "vertex id", &x) < 0) return NULL;
    Py_ssize_t k = PyNumber_AsSsize_t(k_obj, PyExc_OverflowError);
    if (k == -1 && PyErr_Occurred()) return NULL;
    if (k < 0) {
        PyErr_Format(PyExc_ValueError, "k = %zd: must be >= 0", k);
        return NULL;
    }
    npy_intp nc = 0;
    uint32_t *c = ids_1d(c_obj, self->n_vertices, "candidates", &nc);
    if (!c) return NULL;
    gs_neighbors *nb = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_nearest(self->db, x, c, (size_t)nc, (size_t)k, &nb, &err);
    Py_END_ALLOW_THREADS
    PyMem_Free(c);
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    PyObject *out = pair_of_arrays(nb);
    gs_neighbors_free(nb);
    return out;
}

const char gspy_db_radius_matrix_doc[] =
    "radius_matrix($self, sources, r, /, threads=0)\n--\n\n"
    "Returns (indptr, indices, data): the sparse matrix, in compressed sparse\n"
    "rows, of the distances from each source (a 1-D sequence of vertex ids)\n"
    "to every vertex within r of it: row i holds within(sources[i], r) by\n"
    "increasing vertex id. indptr is int64 (len(sources) + 1), indices int64\n"
    "vertex ids and data float64 distances; scipy.sparse.csr_matrix((data,\n"
    "indices, indptr), shape=(len(sources), n_vertices)) makes the matrix\n"
    "(its zeros: a source's own entry is stored, at 0). threads: 0 = the\n"
    "library's default, at most 1024; the result does not depend on it.\n"
    "IndexError for an id out of range, ValueError for a negative or NaN r or\n"
    "a thread count out of range. Runs without the GIL.";

PyObject *gspy_db_radius_matrix(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"sources", "r", "threads", NULL};
    PyObject *s_obj, *r_obj, *t_obj = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OO|$O:radius_matrix", kw, &s_obj, &r_obj, &t_obj))
        return NULL;
    uint32_t threads;
    if (gspy_opt_u32(t_obj, 0, "threads", &threads) < 0) return NULL;
    double r;
    if (get_radius(r_obj, &r) < 0) return NULL;
    npy_intp ns = 0;
    uint32_t *src = ids_1d(s_obj, self->n_vertices, "sources", &ns);
    if (!src) return NULL;
    if ((uint64_t)ns > UINT32_MAX) {
        PyMem_Free(src);
        PyErr_SetString(PyExc_ValueError, "radius_matrix: more than 2^32 - 1 sources");
        return NULL;
    }
    gs_csr *m = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_radius_matrix(self->db, src, (uint32_t)ns, r, threads, &m, &err);
    Py_END_ALLOW_THREADS
    PyMem_Free(src);
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    npy_intp dp[1] = {(npy_intp)m->n_rows + 1}, dn[1] = {(npy_intp)m->nnz};
    PyObject *indptr = PyArray_SimpleNew(1, dp, NPY_INT64), *indices = PyArray_SimpleNew(1, dn, NPY_INT64),
             *data = PyArray_SimpleNew(1, dn, NPY_DOUBLE), *out = NULL;
    if (indptr && indices && data) {
        int64_t *p = PyArray_DATA((PyArrayObject *)indptr), *q = PyArray_DATA((PyArrayObject *)indices);
        for (npy_intp i = 0; i < dp[0]; i++) p[i] = (int64_t)m->indptr[i];
        for (npy_intp i = 0; i < dn[0]; i++) q[i] = m->indices[i];
        if (m->nnz) memcpy(PyArray_DATA((PyArrayObject *)data), m->data, m->nnz * sizeof *m->data);
        out = Py_BuildValue("(NNN)", indptr, indices, data);
        indptr = indices = data = NULL;
    }
    Py_XDECREF(indptr);
    Py_XDECREF(indices);
    Py_XDECREF(data);
    gs_csr_free(m);
    return out;
}
