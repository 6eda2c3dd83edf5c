/* dbquery.c - the queries of geosep.Database: vertex pairs with numpy
 * broadcasting, all pairs of two id lists, fields, and distances between
 * surface points. Ids are checked before any call into the library; the
 * GIL is released around every batch (the database is immutable). */
#include "geosep_py.h"

#include <string.h>

#define CHUNK 65536 /* pairs per call of gs_db_distances */

/* n pairs from pairs[] into out[], without the GIL: vertex ids, or input
 * vertex ids (gs_db_input_distances). */
static int query_pairs(const gs_db *db, int input, const uint32_t *pairs, size_t n, double *out)
{
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = input ? gs_db_input_distances(db, pairs, n, out, &err) : gs_db_distances(db, pairs, n, out, &err);
    Py_END_ALLOW_THREADS
    if (rc) gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    return rc ? -1 : 0;
}

const char gspy_db_distance_doc[] =
    "distance($self, x, y, /)\n--\n\n"
    "Approximate geodesic distance between vertices x and y. Two ints give a\n"
    "float; arrays of ids (any shape) broadcast against each other as numpy\n"
    "does and give a float64 array of the broadcast shape. +inf for pairs that\n"
    "are not connected. IndexError for an id out of range, ValueError for\n"
    "non-integer ids or shapes that do not broadcast. Batches run without the\n"
    "GIL.";

PyObject *gspy_db_pairs(gspy_Database *self, PyObject *x, PyObject *y, int input)
{
    uint32_t a, b, limit = input ? gs_db_num_input_vertices(self->db) : self->n_vertices;
    const char *kind = input ? "input vertex id" : "vertex id";
    if (gspy_is_int_scalar(x) && gspy_is_int_scalar(y)) { /* the fast path: one pair */
        if (gspy_index(x, limit, kind, &a) < 0 || gspy_index(y, limit, kind, &b) < 0) return NULL;
        return PyFloat_FromDouble(input ? gs_db_input_distance(self->db, a, b) : gs_db_distance(self->db, a, b));
    }
    PyObject *result = NULL, *out = NULL;
    PyArrayMultiIterObject *it = NULL;
    uint32_t *pairs = NULL;
    PyArrayObject *ax = gspy_int_array(x, "x"), *ay = ax ? gspy_int_array(y, "y") : NULL;
    if (!ay || gspy_check_array_ids(ax, limit, kind, "x") < 0 || gspy_check_array_ids(ay, limit, kind, "y") < 0) goto done;
    it = (PyArrayMultiIterObject *)PyArray_MultiIterNew(2, (PyObject *)ax, (PyObject *)ay);
    if (!it) goto done; /* ValueError: shapes that do not broadcast */
    out = PyArray_SimpleNew(it->nd, it->dimensions, NPY_DOUBLE);
    pairs = PyMem_New(uint32_t, 2 * CHUNK);
    if (!out || !pairs) {
        if (out) PyErr_NoMemory();
        goto done;
    }
    double *d = PyArray_DATA((PyArrayObject *)out);
    npy_intp size = it->size, done = 0; /* the iterator walks the broadcast shape in C order */
    while (done < size) {
        npy_intp k = 0;
        for (; k < CHUNK && PyArray_MultiIter_NOTDONE(it); k++) {
            pairs[2 * k] = (uint32_t) * (const int64_t *)PyArray_MultiIter_DATA(it, 0);
            pairs[2 * k + 1] = (uint32_t) * (const int64_t *)PyArray_MultiIter_DATA(it, 1);
            PyArray_MultiIter_NEXT(it);
        }
        if (query_pairs(self->db, input, pairs, (size_t)k, d + done) < 0) goto done;
        done += k;
    }
    if (it->nd == 0) { /* two 0-d arrays: a float, as numpy's ufuncs answer */
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

PyObject *gspy_db_distance(PyObject *self_obj, PyObject *args)
{
    PyObject *x, *y;
    if (!PyArg_UnpackTuple(args, "distance", 2, 2, &x, &y)) return NULL;
    return gspy_db_pairs((gspy_Database *)self_obj, x, y, 0);
}

/* A 1-D array of ids as uint32, checked; *n receives the count. */
static uint32_t *id_list(PyObject *obj, uint32_t limit, const char *name, npy_intp *n)
{
    PyArrayObject *a = gspy_int_array(obj, name);
    if (!a) return NULL;
    uint32_t *ids = NULL;
    if (PyArray_NDIM(a) != 1) {
        PyErr_Format(PyExc_ValueError, "%s must be a 1-D sequence of vertex ids, got %d dimensions", name,
                     PyArray_NDIM(a));
    } else if (gspy_check_array_ids(a, limit, "vertex id", name) == 0) {
        *n = PyArray_SIZE(a);
        ids = PyMem_New(uint32_t, (size_t)*n + 1);
        if (!ids) PyErr_NoMemory();
        const int64_t *v = PyArray_DATA(a);
        for (npy_intp i = 0; ids && i < *n; i++) ids[i] = (uint32_t)v[i];
    }
    Py_DECREF(a);
    return ids;
}

const char gspy_db_pairwise_doc[] =
    "pairwise($self, /, src, dst=None)\n--\n\n"
    "Returns a (len(src), len(dst)) float64 array:\n"
    "the distances between every vertex of src and every vertex of dst (1-D\n"
    "sequences of vertex ids; dst defaults to src): out[i, j] = d(src[i],\n"
    "dst[j]). Runs without the GIL.";

PyObject *gspy_db_pairwise(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"src", "dst", NULL};
    PyObject *src_obj, *dst_obj = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:pairwise", kw, &src_obj, &dst_obj)) return NULL;
    npy_intp ns = 0, nd = 0;
    uint32_t *s = id_list(src_obj, self->n_vertices, "src", &ns), *t = NULL, *pairs = NULL;
    if (!s) return NULL;
    PyObject *out = NULL;
    if (dst_obj == Py_None) {
        nd = ns;
    } else if (!(t = id_list(dst_obj, self->n_vertices, "dst", &nd))) {
        goto done;
    }
    const uint32_t *dst = t ? t : s;
    npy_intp dims[2] = {ns, nd};
    out = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!out || !(pairs = PyMem_New(uint32_t, 2 * CHUNK))) {
        if (out) PyErr_NoMemory();
        Py_CLEAR(out);
        goto done;
    }
    double *d = PyArray_DATA((PyArrayObject *)out);
    size_t total = (size_t)ns * (size_t)nd, done = 0;
    gs_error err = {0};
    int rc = GS_OK;
    Py_BEGIN_ALLOW_THREADS
    while (done < total && rc == GS_OK) {
        size_t k = total - done < CHUNK ? total - done : CHUNK;
        for (size_t i = 0; i < k; i++) {
            size_t flat = done + i;
            pairs[2 * i] = s[flat / (size_t)nd];
            pairs[2 * i + 1] = dst[flat % (size_t)nd];
        }
        rc = gs_db_distances(self->db, pairs, k, d + done, &err);
        done += k;
    }
    Py_END_ALLOW_THREADS
    if (rc) {
        Py_CLEAR(out);
        gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    }
done:
    PyMem_Free(s);
    PyMem_Free(t);
    PyMem_Free(pairs);
    return out;
}

const char gspy_db_field_doc[] =
    "field($self, x, /, threads=1)\n--\n\n"
    "Returns an (n_vertices,) float64 array:\n"
    "the distances from vertex x to every vertex (+inf where unreachable), the\n"
    "same values as distance(x, y) for each y. threads: how many threads share\n"
    "the targets (0 = all cores, at most 1024; the answers are the same for any\n"
    "count; a negative or larger count raises ValueError). Runs without the GIL.";

PyObject *gspy_db_field(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"", "threads", NULL};
    PyObject *x_obj, *t_obj = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|$O:field", kw, &x_obj, &t_obj)) return NULL;
    uint32_t x, threads;
    if (gspy_opt_u32(t_obj, 1, "threads", &threads) < 0) return NULL;
    if (gspy_index(x_obj, self->n_vertices, "vertex id", &x) < 0) return NULL;
    npy_intp dims[1] = {self->n_vertices};
    PyObject *out = PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!out) return NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_field_threads(self->db, x, PyArray_DATA((PyArrayObject *)out), threads, &err);
    Py_END_ALLOW_THREADS
    if (rc) {
        Py_DECREF(out);
        return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    }
    return out;
}

/* ---- surface points ------------------------------------------------------ */

const gs_mesh *gspy_db_mesh(gspy_Database *self, PyObject *mesh_obj, const char *method)
{
    if (mesh_obj == Py_None) mesh_obj = self->mesh;
    if (!mesh_obj) {
        PyErr_Format(PyExc_TypeError, "%s needs mesh=: the Mesh the database was built from (a database stores "
                                      "positions, not faces)", method);
        return NULL;
    }
    if (!PyObject_TypeCheck(mesh_obj, &gspy_MeshType)) {
        PyErr_Format(PyExc_TypeError, "mesh must be a geosep.Mesh, got %s", Py_TYPE(mesh_obj)->tp_name);
        return NULL;
    }
    const gs_mesh *m = ((gspy_Mesh *)mesh_obj)->mesh;
    if (mesh_obj == self->mesh || mesh_obj == self->checked) return m;
    gs_error err = {0};
    if (gs_db_check_mesh(self->db, m, &err)) {
        PyErr_SetString(PyExc_ValueError, err.message);
        return NULL;
    }
    Py_XSETREF(self->checked, Py_NewRef(mesh_obj)); /* immutable: no need to compare it again */
    return m;
}

/* One side of the point pairs: faces (a scalar or (k,)) and weights ((3,)
 * or (k, 3)). *k receives the count, -1 for a single point. */
typedef struct {
    PyArrayObject *faces, *bary;
    npy_intp k;
} point_set;

static int point_set_get(PyObject *face_obj, PyObject *bary_obj, uint32_t n_faces, const char *fname,
                         const char *bname, point_set *ps)
{
    ps->faces = gspy_int_array(face_obj, fname);
    if (!ps->faces) return -1;
    PyArrayObject *b = (PyArrayObject *)PyArray_FROM_O(bary_obj);
    if (!b) return -1;
    int single = PyArray_NDIM(ps->faces) == 0;
    int ok = (PyArray_ISFLOAT(b) || PyArray_ISINTEGER(b)) && PyArray_NDIM(ps->faces) <= 1 &&
             PyArray_NDIM(b) == (single ? 1 : 2) && PyArray_DIM(b, PyArray_NDIM(b) - 1) == 3 &&
             (single || PyArray_DIM(b, 0) == PyArray_DIM(ps->faces, 0));
    if (!ok) {
        PyObject *fs = PyObject_GetAttrString((PyObject *)ps->faces, "shape");
        PyObject *bs = PyObject_GetAttrString((PyObject *)b, "shape");
        if (fs && bs)
            PyErr_Format(PyExc_ValueError,
                         "%s and %s must be a face id and 3 barycentric weights, or (k,) face ids and (k, 3) "
                         "weights; got shapes %R and %R (dtype %S)",
                         fname, bname, fs, bs, (PyObject *)PyArray_DESCR(b));
        Py_XDECREF(fs);
        Py_XDECREF(bs);
        Py_DECREF(b);
        return -1;
    }
    ps->bary = (PyArrayObject *)PyArray_FromArray(b, PyArray_DescrFromType(NPY_DOUBLE),
                                                  NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
    Py_DECREF(b);
    if (!ps->bary) return -1;
    ps->k = single ? -1 : PyArray_DIM(ps->faces, 0);
    return gspy_check_array_ids(ps->faces, n_faces, "face id", fname);
}

const char gspy_db_point_distance_doc[] =
    "point_distance($self, /, face_a, bary_a, face_b, bary_b, *, mesh=None)\n--\n\n"
    "Returns a float (one pair) or a (k,) float64 array.\n\n"
    "Approximate geodesic distance between surface points, each given by a face\n"
    "of mesh and barycentric weights (>= 0, summing to 1) of its three corners\n"
    "in the mesh's order. face_a: (k,) face ids, bary_a: (k, 3) weights (or one\n"
    "face id and 3 weights: one point, which is then paired with every point of\n"
    "the other side); likewise face_b, bary_b. mesh: the Mesh the database was\n"
    "built from (default: that mesh, when built in this process; a database\n"
    "stores positions, not faces). A vertex v is any face of v with weight 1\n"
    "at v: the answer is then distance(v, w) exactly. Invalid weights raise\n"
    "ValueError with the library's message, a face id out of range IndexError.";

PyObject *gspy_db_point_distance(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"face_a", "bary_a", "face_b", "bary_b", "mesh", NULL};
    PyObject *fa, *ba, *fb, *bb, *mesh_obj = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OOOO|$O:point_distance", kw, &fa, &ba, &fb, &bb, &mesh_obj))
        return NULL;
    const gs_mesh *m = gspy_db_mesh(self, mesh_obj, "point_distance");
    if (!m) return NULL;
    uint32_t n_faces = gs_mesh_num_faces(m);
    point_set A = {0}, B = {0};
    PyObject *result = NULL, *out = NULL;
    gs_surface_point *pts = NULL;
    if (point_set_get(fa, ba, n_faces, "face_a", "bary_a", &A) < 0 ||
        point_set_get(fb, bb, n_faces, "face_b", "bary_b", &B) < 0)
        goto done;
    if (A.k >= 0 && B.k >= 0 && A.k != B.k) {
        PyErr_Format(PyExc_ValueError, "face_a has %zd points and face_b %zd: give as many, or one point on a side",
                     (Py_ssize_t)A.k, (Py_ssize_t)B.k);
        goto done;
    }
    npy_intp k = A.k >= 0 ? A.k : B.k >= 0 ? B.k : 1;
    npy_intp dims[1] = {k};
    out = PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!out || !(pts = PyMem_New(gs_surface_point, 2 * (size_t)k + 1))) {
        if (out) PyErr_NoMemory();
        goto done;
    }
    const int64_t *f[2] = {PyArray_DATA(A.faces), PyArray_DATA(B.faces)};
    const double *w[2] = {PyArray_DATA(A.bary), PyArray_DATA(B.bary)};
    int many[2] = {A.k >= 0, B.k >= 0};
    gs_error err = {0};
    int rc = GS_OK;
    Py_BEGIN_ALLOW_THREADS
    for (npy_intp i = 0; i < k && rc == GS_OK; i++)
        for (int s = 0; s < 2 && rc == GS_OK; s++) {
            npy_intp j = many[s] ? i : 0;
            rc = gs_surface_point_from_face(m, (uint32_t)f[s][j], w[s][3 * j], w[s][3 * j + 1], w[s][3 * j + 2],
                                            &pts[2 * i + s], &err);
        }
    if (rc == GS_OK) rc = gs_db_point_distances(self->db, pts, (size_t)k, PyArray_DATA((PyArrayObject *)out), &err);
    Py_END_ALLOW_THREADS
    if (rc) {
        gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    } else if (A.k < 0 && B.k < 0) {
        result = PyFloat_FromDouble(*(double *)PyArray_DATA((PyArrayObject *)out));
    } else {
        result = Py_NewRef(out);
    }
done:
    PyMem_Free(pts);
    Py_XDECREF(out);
    Py_XDECREF(A.faces);
    Py_XDECREF(A.bary);
    Py_XDECREF(B.faces);
    Py_XDECREF(B.bary);
    return result;
}

const char gspy_db_farthest_point_sampling_doc[] =
    "farthest_point_sampling($self, /, k, seed=0)\n--\n\n"
    "Returns a (k,) int64 array of vertex ids:\n"
    "farthest-point sampling by the database's distances. The first sample is\n"
    "seed; each next one is the vertex farthest from the samples so far (a\n"
    "vertex of a component without a sample yet counts as infinitely far, so\n"
    "every component is sampled first); ties go to the lowest id; vertices used\n"
    "by no face are never chosen. Costs a field() per component, then a\n"
    "within() per sample (of its distance to the samples before). ValueError if\n"
    "k exceeds the vertices used by faces or seed is used by no face, IndexError\n"
    "for a seed out of range. Runs without the GIL.";

PyObject *gspy_db_farthest_point_sampling(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"k", "seed", NULL};
    PyObject *k_obj, *seed_obj = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:farthest_point_sampling", kw, &k_obj, &seed_obj)) return NULL;
    Py_ssize_t k = PyNumber_AsSsize_t(k_obj, PyExc_OverflowError);
    if (k == -1 && PyErr_Occurred()) return NULL;
    if (k < 0 || (uint64_t)k > self->n_vertices) {
        PyErr_Format(PyExc_ValueError, "k = %zd: must be between 0 and the %u vertices", k, self->n_vertices);
        return NULL;
    }
    uint32_t seed = 0;
    if (seed_obj && gspy_index(seed_obj, self->n_vertices, "seed vertex", &seed) < 0) return NULL;
    uint32_t *ids = PyMem_New(uint32_t, (size_t)k + 1);
    if (!ids) return PyErr_NoMemory();
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_farthest_point_sampling(self->db, (uint32_t)k, seed, ids, &err);
    Py_END_ALLOW_THREADS
    PyObject *out = NULL;
    if (rc == GS_EARG) {
        const char *p = strstr(err.message, ": ");
        PyErr_SetString(PyExc_ValueError, p ? p + 2 : err.message);
    } else if (rc) {
        gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    } else {
        npy_intp dims[1] = {k};
        out = PyArray_SimpleNew(1, dims, NPY_INT64);
        if (out) {
            int64_t *o = PyArray_DATA((PyArrayObject *)out);
            for (Py_ssize_t i = 0; i < k; i++) o[i] = ids[i];
        }
    }
    PyMem_Free(ids);
    return out;
}
