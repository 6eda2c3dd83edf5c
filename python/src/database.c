/* database.c - geosep.Database: building (with a progress bar on stderr),
 * saving, opening and describing a query database (gs_db). The queries are
 * in dbquery.c. */
#include "geosep_py.h"

#include <errno.h>
#include <string.h>
#include <time.h>

/* ---- progress ----------------------------------------------------------- */

/* State of a build's progress report. The library calls back from the
 * building thread (this one, without the GIL): it is retaken only when the
 * shown percentage or the stage changes. */
typedef struct {
    PyObject *callback;  /* a callable(stage, fraction), or NULL: the bar */
    PyObject *exc_type, *exc, *exc_tb; /* the first exception the callback raised */
    char stage[16];      /* the stage shown on the current line           */
    int percent;         /* the percentage shown                          */
    double t_stage;      /* when the stage began (monotonic seconds)      */
} progress_state;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Keep the exception being raised in p (the first one only), to be raised
 * when the build returns; nothing more is drawn or called after it. */
static void keep_exception(progress_state *p)
{
    if (p->exc_type) {
        PyErr_Clear();
        return;
    }
#if PY_VERSION_HEX >= 0x030C0000 /* PyErr_Fetch is deprecated from 3.12 */
    p->exc = PyErr_GetRaisedException();
    p->exc_type = p->exc ? Py_NewRef((PyObject *)Py_TYPE(p->exc)) : Py_NewRef(PyExc_SystemError);
#else
    PyErr_Fetch(&p->exc_type, &p->exc, &p->exc_tb);
    if (!p->exc_type) p->exc_type = Py_NewRef(PyExc_SystemError);
#endif
}

/* Write through sys.stderr, so that it follows redirection (pytest,
 * Jupyter). A broken stderr (an Exception) must not break the build: it is
 * cleared. Anything else is a signal handler that ran during the write (a
 * KeyboardInterrupt from Ctrl-C): kept, and raised when the build returns. */
static void write_stderr(progress_state *p, const char *text)
{
    if (p->exc_type) return;
    PyObject *err = PySys_GetObject("stderr"); /* borrowed */
    if (!err || err == Py_None) return;
    PyObject *r = PyObject_CallMethod(err, "write", "s", text);
    if (r) {
        Py_DECREF(r);
        r = PyObject_CallMethod(err, "flush", NULL);
        Py_XDECREF(r);
    }
    if (!PyErr_Occurred()) return;
    if (PyErr_ExceptionMatches(PyExc_Exception)) PyErr_Clear();
    else keep_exception(p);
}

static void show_bar(progress_state *p, double fraction)
{
    char line[128], bar[31];
    int w = 30, k = (int)(fraction * w + 1e-9);
    for (int i = 0; i < w; i++) bar[i] = i < k ? '#' : ' ';
    bar[w] = 0;
    PyOS_snprintf(line, sizeof line, "\r%-7s [%s] %3d%% %6.1f s", p->stage, bar, p->percent, now() - p->t_stage);
    write_stderr(p, line);
}

static void on_progress(void *user, const char *stage, double fraction)
{
    progress_state *p = user;
    if (!(fraction >= 0)) fraction = 0;
    if (fraction > 1) fraction = 1;
    int percent = (int)(fraction * 100 + 1e-9);
    int new_stage = strncmp(p->stage, stage, sizeof p->stage - 1) != 0;
    if (!new_stage && percent == p->percent) return; /* nothing to redraw: keep the GIL released */
    PyGILState_STATE g = PyGILState_Ensure();
    if (p->callback) {
        if (!p->exc_type) {
            PyObject *r = PyObject_CallFunction(p->callback, "sd", stage, fraction);
            if (r) Py_DECREF(r);
            else keep_exception(p);
        }
    } else if (new_stage && p->stage[0]) { /* the previous stage is done: one line per stage */
        if (p->percent < 100) {
            p->percent = 100;
            show_bar(p, 1.0);
        }
        write_stderr(p, "\n");
    }
    if (new_stage) {
        PyOS_snprintf(p->stage, sizeof p->stage, "%s", stage);
        p->t_stage = now();
    }
    p->percent = percent;
    if (!p->callback) show_bar(p, fraction);
    PyGILState_Release(g);
}

/* ---- building ----------------------------------------------------------- */

static PyObject *stats_dict(const gs_build_stats *s)
{
    return Py_BuildValue("{s:d,s:d,s:d,s:d,s:K,s:K,s:d,s:K,s:d,s:K,s:d}", "seconds_tree", s->seconds_tree,
                         "seconds_fields", s->seconds_fields, "seconds_fits", s->seconds_fits, "seconds_total",
                         s->seconds_total, "n_fields", (unsigned long long)s->n_fields, "n_functions",
                         (unsigned long long)s->n_functions, "mean_degree", s->mean_degree, "n_over_tol",
                         (unsigned long long)s->n_over_tol, "mean_fit_error", s->mean_fit_error, "n_near_pairs",
                         (unsigned long long)s->n_near_pairs, "seconds_near", s->seconds_near);
}

static PyObject *wrap_db(PyTypeObject *type, gs_db *db, PyObject *mesh)
{
    gspy_Database *self = (gspy_Database *)type->tp_alloc(type, 0);
    if (!self) {
        gs_db_free(db);
        return NULL;
    }
    self->db = db;
    gs_db_info info;
    gs_error err = {0};
    int rc = gs_db_get_info(db, &info, &err);
    if (rc) {
        Py_DECREF(self);
        return gspy_raise(rc, &err, GSPY_CTX_DB, NULL, 0);
    }
    self->n_vertices = info.n_vertices;
    self->mesh = Py_XNewRef(mesh);
    return (PyObject *)self;
}

/* A boolean option: None keeps the default. */
static int opt_bool(PyObject *obj, int *out)
{
    if (!obj || obj == Py_None) return 0;
    int v = PyObject_IsTrue(obj);
    if (v < 0) return -1;
    *out = v;
    return 0;
}

static PyObject *db_build(PyObject *cls, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"mesh",         "method",     "threads", "progress",  "vmax",        "mmax",
                         "tol",          "spacing",    "vertex_sources", "sampled", "leaf_exact", "seed",
                         "max_samples",  "field_memory", "heat_time", "heat_refine", "fmm_start", "dgg_eps",
                         "near_radius", NULL};
    PyObject *mesh, *method = NULL, *threads = NULL, *progress = Py_False, *vmax = NULL, *mmax = NULL, *tol = NULL,
                    *spacing = NULL, *vertex_sources = NULL, *sampled = NULL, *leaf_exact = NULL, *seed = NULL,
                    *max_samples = NULL, *field_memory = NULL, *heat_time = NULL, *heat_refine = NULL,
                    *fmm_start = NULL, *dgg_eps = NULL, *near_radius = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!|OOO$OOOOOOOOOOOOOOO:build", kw, &gspy_MeshType, &mesh, &method,
                                     &threads, &progress, &vmax, &mmax, &tol, &spacing, &vertex_sources, &sampled,
                                     &leaf_exact, &seed, &max_samples, &field_memory, &heat_time, &heat_refine,
                                     &fmm_start, &dgg_eps, &near_radius))
        return NULL;
    gs_build_options o;
    gs_build_options_default(&o);
    uint32_t refine_default = o.solver.heat_refine; /* AUTO for builds */
    if (gspy_method(method, &o.method) < 0 || gspy_opt_u32(threads, o.threads, "threads", &o.threads) < 0 ||
        gspy_opt_u32(vmax, o.vmax, "vmax", &o.vmax) < 0 || gspy_opt_u32(mmax, o.mmax, "mmax", &o.mmax) < 0 ||
        gspy_opt_double(tol, o.tol, "tol", &o.tol) < 0 ||
        gspy_opt_double(spacing, o.sample_spacing, "spacing", &o.sample_spacing) < 0 ||
        gspy_opt_double(near_radius, o.near_radius, "near_radius", &o.near_radius) < 0 ||
        opt_bool(sampled, &o.sampled) < 0 || opt_bool(leaf_exact, &o.leaf_exact) < 0 ||
        opt_bool(vertex_sources, &o.vertex_sources) < 0 || gspy_opt_u32(seed, o.seed, "seed", &o.seed) < 0 ||
        gspy_opt_u32(max_samples, o.max_samples, "max_samples", &o.max_samples) < 0 ||
        gspy_opt_u32(field_memory, o.field_memory_mib, "field_memory", &o.field_memory_mib) < 0 ||
        gspy_solver_options(heat_time, heat_refine, fmm_start, dgg_eps, &o.solver) < 0)
        return NULL;
    if (!heat_refine || heat_refine == Py_None) o.solver.heat_refine = refine_default;
    o.repair = ((gspy_Mesh *)mesh)->repair; /* a repaired Mesh: its input ids go into the database */

    progress_state ps = {0};
    ps.percent = -1;
    if (PyCallable_Check(progress)) {
        ps.callback = progress;
    } else {
        int show = PyObject_IsTrue(progress);
        if (show < 0) return NULL;
        if (!show) ps.percent = -2; /* no report */
    }
    if (ps.percent != -2) {
        o.progress = on_progress;
        o.progress_user = &ps;
    }
    gs_db *db = NULL;
    gs_build_stats stats;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_build(((gspy_Mesh *)mesh)->mesh, &o, &db, &stats, &err);
    Py_END_ALLOW_THREADS
    if (o.progress && !ps.callback && ps.stage[0]) write_stderr(&ps, "\n");
    if (ps.exc_type) { /* the callback's exception (or a Ctrl-C during the bar's drawing) wins */
        gs_db_free(db);
#if PY_VERSION_HEX >= 0x030C0000
        Py_DECREF(ps.exc_type);
        if (ps.exc)
            PyErr_SetRaisedException(ps.exc);
        else
            PyErr_SetString(PyExc_SystemError, "the progress callback failed without an exception");
#else
        PyErr_Restore(ps.exc_type, ps.exc, ps.exc_tb);
#endif
        return NULL;
    }
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    gspy_Database *self = (gspy_Database *)wrap_db((PyTypeObject *)cls, db, mesh);
    if (self && !(self->stats = stats_dict(&stats))) Py_CLEAR(self);
    return (PyObject *)self;
}

/* ---- files -------------------------------------------------------------- */

static PyObject *db_open(PyObject *cls, PyObject *args, PyObject *kwargs)
{
    static char *kwlist[] = {"path", "verify", NULL};
    PyObject *path_obj;
    int verify = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|$p:open", kwlist, &path_obj, &verify)) return NULL;
    PyObject *path = gspy_path(path_obj);
    if (!path) return NULL;
    const char *p = PyBytes_AS_STRING(path);
    gs_db *db = NULL;
    gs_error err = {0};
    int rc, saved_errno;
    unsigned flags = verify ? GS_DB_OPEN_VERIFY : 0u;
    Py_BEGIN_ALLOW_THREADS
    errno = 0;
    rc = gs_db_open_ex(p, flags, &db, &err);
    saved_errno = errno;
    Py_END_ALLOW_THREADS
    PyObject *r = rc ? gspy_raise(rc, &err, GSPY_CTX_DB, p, saved_errno) : wrap_db((PyTypeObject *)cls, db, NULL);
    Py_DECREF(path);
    return r;
}

static PyObject *db_from_bytes(PyObject *cls, PyObject *data)
{
    Py_buffer view;
    if (PyObject_GetBuffer(data, &view, PyBUF_SIMPLE) < 0) return NULL;
    gs_db *db = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_open_memory(view.buf, (size_t)view.len, &db, &err);
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&view);
    return rc ? gspy_raise(rc, &err, GSPY_CTX_DB, NULL, 0) : wrap_db((PyTypeObject *)cls, db, NULL);
}

static PyObject *db_to_bytes(gspy_Database *self, PyObject *Py_UNUSED(ignored))
{
    size_t n = 0;
    const void *p = gs_db_file_bytes(self->db, &n);
    return PyBytes_FromStringAndSize(p, (Py_ssize_t)n);
}

/* pickle: Database.from_bytes(the file image); the unpickled database is
 * like an opened file (no mesh, no build_stats) */
static PyObject *db_reduce(gspy_Database *self, PyObject *Py_UNUSED(ignored))
{
    PyObject *from = PyObject_GetAttrString((PyObject *)Py_TYPE(self), "from_bytes");
    PyObject *bytes = from ? db_to_bytes(self, NULL) : NULL;
    PyObject *r = bytes ? Py_BuildValue("(O(O))", from, bytes) : NULL;
    Py_XDECREF(from);
    Py_XDECREF(bytes);
    return r;
}

static PyObject *db_save(gspy_Database *self, PyObject *path_obj)
{
    PyObject *path = gspy_path(path_obj);
    if (!path) return NULL;
    const char *p = PyBytes_AS_STRING(path);
    gs_error err = {0};
    int rc, saved_errno;
    Py_BEGIN_ALLOW_THREADS
    errno = 0;
    rc = gs_db_save(self->db, p, &err);
    saved_errno = errno;
    Py_END_ALLOW_THREADS
    PyObject *r = rc ? gspy_raise(rc, &err, GSPY_CTX_DB, p, saved_errno) : Py_NewRef(Py_None);
    Py_DECREF(path);
    return r;
}

/* ---- description -------------------------------------------------------- */

static PyObject *db_info(gspy_Database *self, PyObject *Py_UNUSED(ignored))
{
    gs_db_info i;
    gs_error err = {0};
    int rc = gs_db_get_info(self->db, &i, &err);
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_DB, NULL, 0);
    const char *method = gs_method_name(i.method);
    return Py_BuildValue("{s:I,s:I,s:I,s:I,s:I,s:d,s:I,s:d,s:d,s:K,s:s,s:I,s:I,s:d,s:O,s:O,s:O,s:d,s:I,s:I,s:d,s:I,s:d,s:d,s:I,"
                         "s:d,s:K}",
                         "format_version", i.format_version, "n_vertices", i.n_vertices, "n_nodes", i.n_nodes,
                         "n_leaves", i.n_leaves, "n_curves", i.n_curves, "avg_depth", i.avg_depth, "max_depth",
                         i.max_depth, "cost", i.cost, "bytes_per_vertex", i.bytes_per_vertex, "file_bytes",
                         (unsigned long long)i.file_bytes, "method", method ? method : "unknown", "vmax", i.vmax,
                         "mmax", i.mmax, "tol", i.tol, "vertex_sources", i.vertex_sources ? Py_True : Py_False,
                         "sampled", i.sampled ? Py_True : Py_False, "leaf_exact", i.leaf_exact ? Py_True : Py_False,
                         "spacing", i.sample_spacing, "seed", i.seed, "max_samples", i.max_samples, "heat_time",
                         i.solver.heat_time, "heat_refine", i.solver.heat_refine, "fmm_start",
                         i.solver.fmm_exact_start, "dgg_eps", i.solver.dgg_eps, "n_input_vertices",
                         gs_db_num_input_vertices(self->db), "near_radius", i.near_radius, "n_near_pairs",
                         (unsigned long long)i.n_near_pairs);
}

static PyObject *db_get_n_vertices(gspy_Database *self, void *Py_UNUSED(closure))
{
    return PyLong_FromUnsignedLong(self->n_vertices);
}

static PyObject *db_get_vertices(gspy_Database *self, void *Py_UNUSED(closure))
{
    npy_intp dims[2] = {self->n_vertices, 3};
    return gspy_readonly_view((PyObject *)self, 2, dims, NPY_DOUBLE, gs_db_positions(self->db));
}

static PyObject *db_get_mesh(gspy_Database *self, void *Py_UNUSED(closure))
{
    return Py_NewRef(self->mesh ? self->mesh : Py_None);
}

static PyObject *db_get_stats(gspy_Database *self, void *Py_UNUSED(closure))
{
    return self->stats ? PyDict_Copy(self->stats) : Py_NewRef(Py_None);
}

static PyObject *db_repr(gspy_Database *self)
{
    return PyUnicode_FromFormat("<geosep.Database of %u vertices>", self->n_vertices);
}

static void db_dealloc(gspy_Database *self)
{
    gs_db_free(self->db);
    Py_XDECREF(self->mesh);
    Py_XDECREF(self->checked);
    Py_XDECREF(self->stats);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyGetSetDef db_getset[] = {
    {"n_vertices", (getter)db_get_n_vertices, NULL, "Number of vertices of the mesh it was built from.", NULL},
    {"n_input_vertices", (getter)gspy_db_get_n_input_vertices, NULL,
     "Number of input vertices: of the mesh before repair for a database built\n"
     "from a repaired Mesh (input_distance), else n_vertices.",
     NULL},
    {"vertices", (getter)db_get_vertices, NULL,
     "The vertex positions it was built from: a read-only (n_vertices, 3) float64 array.", NULL},
    {"mesh", (getter)db_get_mesh, NULL,
     "The Mesh it was built from in this process, or None (an opened file keeps\n"
     "positions, not faces).",
     NULL},
    {"build_stats", (getter)db_get_stats, NULL,
     "For a database built in this process, a dict of the build's figures\n"
     "(seconds_tree, seconds_fields, seconds_fits, seconds_total, n_fields,\n"
     "n_functions, mean_degree, n_over_tol, mean_fit_error, n_near_pairs,\n"
     "seconds_near); else None.",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyMethodDef db_methods[] = {
    {"build", (PyCFunction)(void (*)(void))db_build, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "build($type, /, mesh, method='exact', threads=0, progress=False, **options)\n--\n\n"
     "Returns a new Database.\n\n"
     "Build the query database of a Mesh (the paper's preprocessing): a nested\n"
     "bisection tree with separator curves, distance fields by `method`\n"
     "(\"exact\", \"fmm\", \"heat\", \"dgg\" or \"graph\") and per-vertex distance\n"
     "functions.\n"
     "threads: 0 = all cores. progress=True draws a progress bar on stderr (one\n"
     "line per stage); a callable is called as progress(stage, fraction)\n"
     "instead, whenever the percentage changes (an exception it raises is\n"
     "raised when the build ends: builds are not cancelled). Options, as the command line's build options (None: default):\n"
     "  vmax (leaf size, 30), mmax (max polynomial degree, 20), tol (fit error\n"
     "  target at the root, 0.003), spacing (sample spacing in mean edge\n"
     "  lengths, 0.5), vertex_sources (bool; None: by the method), sampled\n"
     "  (store sampled values, False), leaf_exact (exact distances inside\n"
     "  leaves, True),\n"
     "  seed (partitioning seed, 1), max_samples (per curve, 192; 0: no cap),\n"
     "  field_memory (MiB per block of fields, 384), heat_time, heat_refine\n"
     "  (0..3 or \"auto\", the default), fmm_start, dgg_eps (method \"dgg\"),\n"
     "  near_radius (mean edge lengths, 5; 0: no near pairs; doc/accuracy.md).\n"
     "A Mesh made with repair=True gives a database that also answers by the\n"
     "input's vertex ids (input_distance, input_field).\n"
     "An unknown option raises TypeError, a value out of range ValueError. The\n"
     "GIL is released during the build."},
    {"open", (PyCFunction)(void (*)(void))db_open, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "open($type, path, *, verify=False)\n--\n\n"
     "Returns the opened Database.\n\n"
     "Open a database file (memory-mapped, used in place: opening takes\n"
     "milliseconds whatever the size). The structure is always checked (header,\n"
     "section table, counts, offsets): a truncated, incompatible or structurally\n"
     "corrupt file raises DatabaseError naming the section and field; an\n"
     "unreadable one OSError. verify=True also checks every checksum and stored\n"
     "value (it reads the whole file; geosep verify DB does the same): without\n"
     "it, a file damaged inside a coefficient opens and may answer wrongly for\n"
     "the pairs that use it (never crashes)."},
    {"from_bytes", (PyCFunction)db_from_bytes, METH_O | METH_CLASS,
     "from_bytes($type, data, /)\n--\n\n"
     "Returns the Database whose file image is data (bytes or any buffer, as\n"
     "to_bytes() gives or a .gsdb file holds). The bytes are copied and fully\n"
     "checked (checksums and stored values, as open(path, verify=True)): a\n"
     "corrupt or incompatible image raises DatabaseError."},
    {"to_bytes", (PyCFunction)db_to_bytes, METH_NOARGS,
     "to_bytes($self, /)\n--\n\n"
     "Returns the database's file image as bytes (what save() writes).\n"
     "Databases pickle as this image (pickle, multiprocessing, joblib): the\n"
     "unpickled one is like an opened file (mesh and build_stats are None)."},
    {"__reduce__", (PyCFunction)db_reduce, METH_NOARGS, NULL},
    {"save", (PyCFunction)db_save, METH_O,
     "save($self, path, /)\n--\n\nWrite the database to a file, atomically (a temporary file, then a rename)."},
    {"info", (PyCFunction)db_info, METH_NOARGS,
     "info($self, /)\n--\n\n"
     "A dict:\n"
     "format_version, n_vertices, n_nodes, n_leaves, n_curves, avg_depth,\n"
     "max_depth, cost (numbers stored per vertex), bytes_per_vertex, file_bytes,\n"
     "and the build's parameters: method, vmax, mmax, tol, vertex_sources,\n"
     "sampled, leaf_exact, spacing, seed, max_samples, heat_time, heat_refine,\n"
     "fmm_start, dgg_eps (method \"dgg\"; 0 for the others), n_input_vertices\n"
     "(input_distance), near_radius (mesh units; 0: none) and n_near_pairs (the\n"
     "exact distances stored for near pairs)."},
    GSPY_DB_QUERY_METHODS,
    GSPY_DB_PATH_METHODS,
    GSPY_DB_INPUT_METHODS,
    GSPY_DB_WITHIN_METHODS,
    {NULL, NULL, 0, NULL}};

PyTypeObject gspy_DatabaseType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "geosep.Database",
    .tp_basicsize = sizeof(gspy_Database),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A geodesic distance database (Gotsman & Hormann 2022): made by\n"
              "Database.build(mesh, ...) or Database.open(path), answers distance\n"
              "queries between vertices (distance, pairwise, field) and between surface\n"
              "points (point_distance) in well under a microsecond each.\n\n"
              "Vertex ids are the mesh's. Unreachable pairs (different components,\n"
              "unreferenced vertices) are +inf. An id out of range raises IndexError.\n"
              "A database of a repaired Mesh (repair=True) also answers by the input's\n"
              "vertex ids: input_distance, input_field (doc/repair.md).\n\n"
              "A Database is immutable: one may be queried from many threads at once;\n"
              "the GIL is released during builds and batch queries.",
    .tp_dealloc = (destructor)db_dealloc,
    .tp_repr = (reprfunc)db_repr,
    .tp_methods = db_methods,
    .tp_getset = db_getset,
};

int gspy_database_init_type(PyObject *module)
{
    if (PyType_Ready(&gspy_DatabaseType) < 0) return -1;
    return PyModule_AddObjectRef(module, "Database", (PyObject *)&gspy_DatabaseType);
}
