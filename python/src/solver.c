/* solver.c - distance fields on a mesh: geosep.Solver (a reusable
 * gs_solver over the whole mesh, guarded by a lock since it has scratch
 * space) and the one-shot geosep.distance_field. */
#include "geosep_py.h"

/* Create the whole-mesh patch and a solver on it, without the GIL. */
static int make_solver(const gs_mesh *mesh, gs_method method, const gs_solver_options *opt, gs_patch **patch,
                       gs_solver **solver)
{
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_patch_create(mesh, NULL, 0, patch, &err);
    if (rc == GS_OK) rc = gs_solver_create_ex(*patch, method, opt, solver, &err);
    Py_END_ALLOW_THREADS
    if (rc) {
        gs_patch_free(*patch);
        *patch = NULL;
        gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
        return -1;
    }
    return 0;
}

/* Solve into a new (n,) float64 array; the caller holds the solver's lock
 * (or owns the solver) and the GIL. */
static PyObject *solve(gs_solver *solver, uint32_t n, const gs_source *src, uint32_t n_src, double max_distance,
                       PyThread_type_lock lock)
{
    npy_intp dims[1] = {n};
    PyObject *out = PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!out) return NULL;
    double *dist = PyArray_DATA((PyArrayObject *)out);
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    if (lock) PyThread_acquire_lock(lock, WAIT_LOCK);
    rc = gs_solver_solve(solver, src, n_src, max_distance, dist, &err);
    if (lock) PyThread_release_lock(lock);
    Py_END_ALLOW_THREADS
    if (rc) {
        Py_DECREF(out);
        return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    }
    return out;
}

/* ---- geosep.Solver ------------------------------------------------------ */

static PyObject *solver_new(PyTypeObject *type, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"mesh", "method", "heat_time", "heat_refine", "fmm_start", "dgg_eps", NULL};
    PyObject *mesh, *method_obj = NULL, *heat_time = NULL, *heat_refine = NULL, *fmm_start = NULL, *dgg_eps = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!|O$OOOO:Solver", kw, &gspy_MeshType, &mesh, &method_obj,
                                     &heat_time, &heat_refine, &fmm_start, &dgg_eps))
        return NULL;
    gs_method method;
    gs_solver_options opt;
    if (gspy_method(method_obj, &method) < 0 || gspy_solver_options(heat_time, heat_refine, fmm_start, dgg_eps, &opt) < 0)
        return NULL;
    gspy_Solver *self = (gspy_Solver *)type->tp_alloc(type, 0);
    if (!self) return NULL;
    self->mesh = Py_NewRef(mesh);
    self->method = method;
    self->options = opt;
    self->lock = PyThread_allocate_lock();
    if (!self->lock) {
        Py_DECREF(self);
        return PyErr_NoMemory();
    }
    if (make_solver(((gspy_Mesh *)mesh)->mesh, method, &opt, &self->patch, &self->solver) < 0) {
        Py_DECREF(self);
        return NULL;
    }
    return (PyObject *)self;
}

static void solver_dealloc(gspy_Solver *self)
{
    gs_solver_free(self->solver);
    gs_patch_free(self->patch);
    if (self->lock) PyThread_free_lock(self->lock);
    Py_XDECREF(self->mesh);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject *solver_field(gspy_Solver *self, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"sources", "max_distance", NULL};
    PyObject *sources, *maxd_obj = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:field", kw, &sources, &maxd_obj)) return NULL;
    double maxd;
    if (gspy_max_distance(maxd_obj, &maxd) < 0) return NULL;
    uint32_t n = gs_patch_num_vertices(self->patch), n_src = 0;
    gs_source *src = gspy_sources(sources, n, &n_src);
    if (!src) return NULL;
    PyObject *out = solve(self->solver, n, src, n_src, maxd, self->lock);
    PyMem_Free(src);
    return out;
}


/* ---- paths ---------------------------------------------------------------- */

/* One end of a path: a vertex id, or (face, (b0, b1, b2)). 0, or -1 with
 * TypeError / IndexError / ValueError set. */
int gspy_path_end(PyObject *obj, const gs_mesh *m, const char *name, gs_source *out)
{
    uint32_t v;
    if (gspy_is_int_scalar(obj)) {
        if (gspy_index(obj, gs_mesh_num_vertices(m), "vertex id", &v) < 0) return -1;
        *out = gs_source_vertex(v);
        return 0;
    }
    PyObject *seq = PySequence_Check(obj) ? PySequence_Fast(obj, "") : NULL;
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be a vertex id or a surface point (face, (b0, b1, b2))", name);
        return -1;
    }
    uint32_t f;
    int rc = gspy_index(PySequence_Fast_GET_ITEM(seq, 0), gs_mesh_num_faces(m), "face id", &f);
    PyArrayObject *b = NULL;
    if (rc == 0) {
        b = (PyArrayObject *)PyArray_FROMANY(PySequence_Fast_GET_ITEM(seq, 1), NPY_DOUBLE, 1, 1, NPY_ARRAY_CARRAY);
        if (!b || PyArray_SIZE(b) != 3) {
            if (b) PyErr_Format(PyExc_ValueError, "%s: the weights must be 3 numbers", name);
            rc = -1;
        } else {
            const double *w = PyArray_DATA(b);
            *out = gs_source_point(f, w[0], w[1], w[2]);
        }
    }
    Py_XDECREF(b);
    Py_DECREF(seq);
    return rc;
}

/* The path as numpy arrays: (k, 3) xyz, or (xyz, faces (k,), bary (k, 3)). */
PyObject *gspy_path_arrays(const gs_path *p, int with_faces)
{
    npy_intp k = gs_path_num_points(p), d2[2] = {k, 3}, d1[1] = {k};
    PyObject *xyz = PyArray_SimpleNew(2, d2, NPY_DOUBLE);
    if (!xyz) return NULL;
    if (k) memcpy(PyArray_DATA((PyArrayObject *)xyz), gs_path_xyz(p), (size_t)k * 3 * sizeof(double));
    if (!with_faces) return xyz;
    PyObject *faces = PyArray_SimpleNew(1, d1, NPY_INT64), *bary = PyArray_SimpleNew(2, d2, NPY_DOUBLE);
    if (!faces || !bary) {
        Py_DECREF(xyz);
        Py_XDECREF(faces);
        Py_XDECREF(bary);
        return NULL;
    }
    int64_t *fo = PyArray_DATA((PyArrayObject *)faces);
    for (npy_intp i = 0; i < k; ++i) fo[i] = gs_path_faces(p)[i];
    if (k) memcpy(PyArray_DATA((PyArrayObject *)bary), gs_path_bary(p), (size_t)k * 3 * sizeof(double));
    return Py_BuildValue("(NNN)", xyz, faces, bary);
}

/* Solve and trace without the GIL (lock: the solver's, or NULL). */
static PyObject *find_path(gs_solver *solver, const gs_source *x, const gs_source *y, int with_faces,
                           PyThread_type_lock lock)
{
    gs_error err = {0};
    gs_path *p = NULL;
    int rc;
    Py_BEGIN_ALLOW_THREADS
    if (lock) PyThread_acquire_lock(lock, WAIT_LOCK);
    rc = gs_solver_path(solver, x, y, &p, &err);
    if (lock) PyThread_release_lock(lock);
    Py_END_ALLOW_THREADS
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    PyObject *out = gspy_path_arrays(p, with_faces);
    gs_path_free(p);
    return out;
}

#define PATH_DOC_BODY                                                                  \
    "The exact shortest path on the mesh from x to y, each a vertex id or a\n"          \
    "surface point (face, (b0, b1, b2)) with weights >= 0 summing to 1: a\n"            \
    "(k, 3) float64 array of points from x to y (x, every crossing with an\n"           \
    "edge, every vertex passed through, y), straight inside every face; its\n"          \
    "length (np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) is the exact\n"          \
    "geodesic distance. x == y gives one point; a y that x cannot reach\n"              \
    "(another component) a (0, 3) array. return_faces=True: a tuple (points,\n"         \
    "faces, bary) with faces (k,) int64, a face holding the segment to the next\n"      \
    "point (the last point: from the previous one), and bary (k, 3) the\n"              \
    "point's weights in it. Costs one exact field from x. IndexError for an id\n"       \
    "out of range, ValueError for weights that are negative or do not sum to 1.\n"

static PyObject *solver_path(gspy_Solver *self, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"x", "y", "return_faces", NULL};
    PyObject *xo, *yo;
    int with_faces = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OO|$p:path", kw, &xo, &yo, &with_faces)) return NULL;
    if (self->method != GS_METHOD_EXACT) {
        PyErr_Format(PyExc_ValueError, "path needs the exact method (this Solver is %s)",
                     gs_method_name(self->method));
        return NULL;
    }
    const gs_mesh *m = ((gspy_Mesh *)self->mesh)->mesh;
    gs_source x, y;
    if (gspy_path_end(xo, m, "x", &x) < 0 || gspy_path_end(yo, m, "y", &y) < 0) return NULL;
    return find_path(self->solver, &x, &y, with_faces, self->lock);
}

static PyObject *solver_get_mesh(gspy_Solver *self, void *Py_UNUSED(closure)) { return Py_NewRef(self->mesh); }

static PyObject *solver_get_method(gspy_Solver *self, void *Py_UNUSED(closure))
{
    return PyUnicode_FromString(gs_method_name(self->method));
}

static PyObject *solver_repr(gspy_Solver *self)
{
    return PyUnicode_FromFormat("<geosep.Solver method=%s on %R>", gs_method_name(self->method), self->mesh);
}

static PyGetSetDef solver_getset[] = {
    {"mesh", (getter)solver_get_mesh, NULL, "The Mesh this solver measures on.", NULL},
    {"method", (getter)solver_get_method, NULL, "The method's name (\"exact\", \"graph\", \"fmm\", \"heat\" or \"dgg\").",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyMethodDef solver_methods[] = {
    {"field", (PyCFunction)(void (*)(void))solver_field, METH_VARARGS | METH_KEYWORDS,
     "field($self, /, sources, max_distance=None)\n--\n\n"
     "Returns an (n_vertices,) float64 array:\n"
     "the geodesic distance from the nearest of the sources (a vertex id or a\n"
     "sequence of them) to every vertex; +inf where unreachable (another\n"
     "component, an unreferenced vertex). max_distance > 0 stops early: every\n"
     "vertex within it is exact, the others may be +inf or any larger value.\n"
     "IndexError for an id out of range. The GIL is released while solving."},
    {"path", (PyCFunction)(void (*)(void))solver_path, METH_VARARGS | METH_KEYWORDS,
     "path($self, /, x, y, *, return_faces=False)\n--\n\n" PATH_DOC_BODY
     "Only for method \"exact\" (ValueError otherwise). The GIL is released\n"
     "while solving."},
    {NULL, NULL, 0, NULL}};

PyTypeObject gspy_SolverType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "geosep.Solver",
    .tp_basicsize = sizeof(gspy_Solver),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Solver(mesh, method='exact', *, heat_time=None, heat_refine=None, fmm_start=None, dgg_eps=None)\n--\n\n"
              "A reusable distance-field solver on a Mesh: it allocates its memory (and,\n"
              "for \"heat\", factors its matrices) once, then solves any number of\n"
              "fields with field(). Methods: \"exact\" (exact polyhedral distances,\n"
              "window propagation), \"fmm\" (fast marching), \"heat\" (the heat method),\n"
              "\"graph\" (Dijkstra on the edges: an upper bound), \"dgg\" (discrete\n"
              "geodesic graph: built once here from local exact runs, then each field\n"
              "is a Dijkstra on it; an upper bound within ~0.01% mean). Options (None: the\n"
              "library's defaults): heat_time (t = heat_time * h^2, default 1),\n"
              "heat_refine (solve on the mesh subdivided 0..3 times, or \"auto\"),\n"
              "fmm_start (vertices within this many mean edge lengths of the sources\n"
              "get exact distances, default 4), dgg_eps (dgg's target relative error,\n"
              "1e-5 to 0.5, default 0.001: it sets the radius of the local runs).\n\n"
              "A Solver has scratch space: calls from several threads are safe but run\n"
              "one at a time (a lock guards it). For parallel fields, use one Solver\n"
              "per thread.",
    .tp_new = solver_new,
    .tp_dealloc = (destructor)solver_dealloc,
    .tp_repr = (reprfunc)solver_repr,
    .tp_methods = solver_methods,
    .tp_getset = solver_getset,
};

int gspy_solver_init_type(PyObject *module)
{
    if (PyType_Ready(&gspy_SolverType) < 0) return -1;
    return PyModule_AddObjectRef(module, "Solver", (PyObject *)&gspy_SolverType);
}

/* ---- geosep.distance_field ---------------------------------------------- */

const char gspy_distance_field_doc[] =
    "distance_field(mesh, sources, method='exact', max_distance=None, *, heat_time=None, heat_refine=None, "
    "fmm_start=None, dgg_eps=None)\n--\n\n"
    "Returns an (n_vertices,) float64 array:\n"
    "the geodesic distance from the nearest of the sources (a vertex id or a\n"
    "sequence of them) to every vertex of mesh; +inf where unreachable. The\n"
    "one-shot form of Solver(mesh, method, ...).field(sources, max_distance);\n"
    "use a Solver for many fields on one mesh.";

PyObject *gspy_distance_field(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"mesh", "sources", "method", "max_distance", "heat_time", "heat_refine", "fmm_start", "dgg_eps",
                         NULL};
    PyObject *mesh, *sources, *method_obj = NULL, *maxd_obj = Py_None, *heat_time = NULL, *heat_refine = NULL,
                                *fmm_start = NULL, *dgg_eps = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!O|OO$OOOO:distance_field", kw, &gspy_MeshType, &mesh, &sources,
                                     &method_obj, &maxd_obj, &heat_time, &heat_refine, &fmm_start, &dgg_eps))
        return NULL;
    gs_method method;
    gs_solver_options opt;
    double maxd;
    if (gspy_method(method_obj, &method) < 0 || gspy_solver_options(heat_time, heat_refine, fmm_start, dgg_eps, &opt) < 0 ||
        gspy_max_distance(maxd_obj, &maxd) < 0)
        return NULL;
    const gs_mesh *m = ((gspy_Mesh *)mesh)->mesh;
    uint32_t n = gs_mesh_num_vertices(m), n_src = 0;
    gs_source *src = gspy_sources(sources, n, &n_src);
    if (!src) return NULL;
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    PyObject *out = NULL;
    if (make_solver(m, method, &opt, &patch, &solver) == 0) out = solve(solver, n, src, n_src, maxd, NULL);
    gs_solver_free(solver);
    gs_patch_free(patch);
    PyMem_Free(src);
    return out;
}

/* ---- geosep.geodesic_path ------------------------------------------------ */

const char gspy_geodesic_path_doc[] =
    "geodesic_path(mesh, x, y, *, return_faces=False)\n--\n\n" PATH_DOC_BODY
    "The one-shot form of Solver(mesh, \"exact\").path(x, y); use a Solver for\n"
    "many paths on one mesh (it keeps its memory).";

PyObject *gspy_geodesic_path(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"mesh", "x", "y", "return_faces", NULL};
    PyObject *mesh, *xo, *yo;
    int with_faces = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!OO|$p:geodesic_path", kw, &gspy_MeshType, &mesh, &xo, &yo,
                                     &with_faces))
        return NULL;
    const gs_mesh *m = ((gspy_Mesh *)mesh)->mesh;
    gs_source x, y;
    if (gspy_path_end(xo, m, "x", &x) < 0 || gspy_path_end(yo, m, "y", &y) < 0) return NULL;
    gs_solver_options opt;
    gs_solver_options_default(&opt);
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    PyObject *out = NULL;
    if (make_solver(m, GS_METHOD_EXACT, &opt, &patch, &solver) == 0) out = find_path(solver, &x, &y, with_faces, NULL);
    gs_solver_free(solver);
    gs_patch_free(patch);
    return out;
}
