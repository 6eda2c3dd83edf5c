/* mesh.c - geosep.Mesh: an immutable, validated triangle mesh (gs_mesh),
 * made from numpy arrays, a mesh file or a generator spec. */
#include "geosep_py.h"

#include <errno.h>
#include <string.h>

PyObject *gspy_readonly_view(PyObject *base, int nd, npy_intp *dims, int typenum, const void *data)
{
    PyObject *a = PyArray_SimpleNewFromData(nd, dims, typenum, (void *)data);
    if (!a) return NULL;
    Py_INCREF(base);
    if (PyArray_SetBaseObject((PyArrayObject *)a, base) < 0) { /* steals base */
        Py_DECREF(a);
        return NULL;
    }
    PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
    return a;
}

PyObject *gspy_mesh_wrap(PyTypeObject *type, gs_mesh *mesh)
{
    gspy_Mesh *self = (gspy_Mesh *)type->tp_alloc(type, 0);
    if (!self) {
        gs_mesh_free(mesh);
        return NULL;
    }
    self->mesh = mesh;
    return (PyObject *)self;
}

/* gspy_mesh_wrap keeping what the repair did (steals both). */
static PyObject *mesh_wrap_repaired(PyTypeObject *type, gs_mesh *mesh, gs_repair *rep)
{
    PyObject *r = gspy_mesh_wrap(type, mesh);
    if (r) ((gspy_Mesh *)r)->repair = rep;
    else gs_repair_free(rep);
    return r;
}

/* Shape (k, 3) and a dtype of the right kind, else ValueError saying what
 * was expected: `expect` describes the argument. */
static PyArrayObject *table(PyObject *obj, const char *name, const char *expect, int integers)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(obj);
    if (!a) return NULL;
    int kind_ok = integers ? PyArray_ISINTEGER(a) : (PyArray_ISINTEGER(a) || PyArray_ISFLOAT(a));
    if (PyArray_NDIM(a) != 2 || PyArray_DIM(a, 1) != 3 || !kind_ok) {
        PyObject *shape = PyObject_GetAttrString((PyObject *)a, "shape");
        if (shape)
            PyErr_Format(PyExc_ValueError, "%s must be %s, got an array of shape %R and dtype %S", name, expect,
                         shape, (PyObject *)PyArray_DESCR(a));
        Py_XDECREF(shape);
        Py_DECREF(a);
        return NULL;
    }
    PyArrayObject *r = (PyArrayObject *)PyArray_FromArray(
        a, PyArray_DescrFromType(integers ? NPY_INT64 : NPY_DOUBLE), NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
    Py_DECREF(a);
    return r;
}

static PyObject *mesh_new(PyTypeObject *type, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"V", "F", "repair", NULL};
    PyObject *V_obj, *F_obj;
    int repair = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OO|p:Mesh", kw, &V_obj, &F_obj, &repair)) return NULL;
    PyArrayObject *V = table(V_obj, "V", "an (n, 3) array of floats (vertex positions)", 0);
    if (!V) return NULL;
    PyArrayObject *F = table(F_obj, "F", "an (m, 3) array of int32 or int64 (the vertex ids of each face)", 1);
    if (!F) {
        Py_DECREF(V);
        return NULL;
    }
    PyObject *result = NULL;
    uint32_t *tri = NULL;
    npy_intp nv = PyArray_DIM(V, 0), nf = PyArray_DIM(F, 0);
    if (nv >= (npy_intp)UINT32_MAX || nf >= (npy_intp)UINT32_MAX) {
        PyErr_SetString(gspy_MeshError, "the mesh has more vertices or faces than geosep supports (2^32 - 1)");
        goto done;
    }
    tri = PyMem_New(uint32_t, (size_t)(3 * nf) + 1);
    if (!tri) {
        PyErr_NoMemory();
        goto done;
    }
    const int64_t *f = PyArray_DATA(F);
    for (npy_intp i = 0; i < 3 * nf; i++) {
        /* what uint32 cannot hold; the library checks the rest (>= n) */
        if (f[i] < 0 || f[i] >= (int64_t)UINT32_MAX) {
            PyErr_Format(gspy_MeshError, "face %zd: vertex id %lld out of range [0, %zd)", (Py_ssize_t)(i / 3),
                         (long long)f[i], (Py_ssize_t)nv);
            goto done;
        }
        tri[i] = (uint32_t)f[i];
    }
    gs_mesh *mesh = NULL;
    gs_repair *rep = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    if (repair)
        rc = gs_mesh_repair(PyArray_DATA(V), (uint32_t)nv, tri, (uint32_t)nf, &mesh, &rep, &err);
    else
        rc = gs_mesh_create(PyArray_DATA(V), (uint32_t)nv, tri, (uint32_t)nf, &mesh, &err);
    Py_END_ALLOW_THREADS
    result = rc ? gspy_raise(rc, &err, GSPY_CTX_MESH, NULL, 0) : mesh_wrap_repaired(type, mesh, rep);
done:
    PyMem_Free(tri);
    Py_DECREF(V);
    Py_DECREF(F);
    return result;
}

static void mesh_dealloc(gspy_Mesh *self)
{
    gs_mesh_free(self->mesh);
    gs_repair_free(self->repair);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyObject *mesh_load(PyObject *cls, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"path", "format", "repair", NULL};
    PyObject *path_obj, *fmt_obj = Py_None;
    int repair = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|Op:load", kw, &path_obj, &fmt_obj, &repair)) return NULL;
    gs_mesh_format fmt = GS_FORMAT_AUTO;
    if (fmt_obj != Py_None) {
        static const char *names[] = {"obj", "off", "ply", "stl"};
        const char *s = PyUnicode_Check(fmt_obj) ? PyUnicode_AsUTF8(fmt_obj) : NULL;
        for (int i = 0; s && i < 4; i++)
            if (!strcmp(s, names[i])) fmt = (gs_mesh_format)(GS_FORMAT_OBJ + i);
        if (fmt == GS_FORMAT_AUTO) {
            if (!PyErr_Occurred())
                PyErr_Format(PyExc_ValueError, "format must be None, \"obj\", \"off\", \"ply\" or \"stl\", got %R",
                             fmt_obj);
            return NULL;
        }
    }
    PyObject *path = gspy_path(path_obj);
    if (!path) return NULL;
    const char *p = PyBytes_AS_STRING(path);
    gs_mesh *mesh = NULL;
    gs_repair *rep = NULL;
    gs_error err = {0};
    int rc, saved_errno;
    Py_BEGIN_ALLOW_THREADS
    errno = 0;
    rc = repair ? gs_mesh_repair_file(p, fmt, &mesh, &rep, &err) : gs_mesh_load(p, fmt, &mesh, &err);
    saved_errno = errno;
    Py_END_ALLOW_THREADS
    PyObject *r = rc ? gspy_raise(rc, &err, GSPY_CTX_MESH, p, saved_errno)
                     : mesh_wrap_repaired((PyTypeObject *)cls, mesh, rep);
    Py_DECREF(path);
    return r;
}

static PyObject *mesh_generate(PyObject *cls, PyObject *args)
{
    const char *spec;
    if (!PyArg_ParseTuple(args, "s:generate", &spec)) return NULL;
    gs_mesh *mesh = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_mesh_generate(spec, &mesh, &err);
    Py_END_ALLOW_THREADS
    return rc ? gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0) : gspy_mesh_wrap((PyTypeObject *)cls, mesh);
}

static PyObject *mesh_subdivide(gspy_Mesh *self, PyObject *Py_UNUSED(ignored))
{
    gs_mesh *mesh = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_mesh_subdivide(self->mesh, &mesh, &err);
    Py_END_ALLOW_THREADS
    return rc ? gspy_raise(rc, &err, GSPY_CTX_MESH, NULL, 0) : gspy_mesh_wrap(Py_TYPE(self), mesh);
}

static PyObject *mesh_save(gspy_Mesh *self, PyObject *path_obj)
{
    PyObject *path = gspy_path(path_obj);
    if (!path) return NULL;
    const char *p = PyBytes_AS_STRING(path);
    gs_error err = {0};
    int rc, saved_errno;
    Py_BEGIN_ALLOW_THREADS
    errno = 0;
    rc = gs_mesh_save_obj(self->mesh, p, &err);
    saved_errno = errno;
    Py_END_ALLOW_THREADS
    PyObject *r = rc ? gspy_raise(rc, &err, GSPY_CTX_MESH, p, saved_errno) : Py_NewRef(Py_None);
    Py_DECREF(path);
    return r;
}

static PyObject *mesh_random_vertices(gspy_Mesh *self, PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"k", "seed", NULL};
    PyObject *k_obj;
    unsigned long long seed = 1;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|K:random_vertices", kw, &k_obj, &seed)) return NULL;
    uint32_t k;
    if (gspy_opt_u32(k_obj, 0, "k", &k) < 0) return NULL; /* -1 is refused, not 2^32 - 1 */
    npy_intp dims[1] = {k};
    PyObject *out = PyArray_SimpleNew(1, dims, NPY_UINT32);
    if (!out) return NULL;
    gs_error err = {0};
    int rc = gs_mesh_random_vertices(self->mesh, k, seed, PyArray_DATA((PyArrayObject *)out), &err);
    if (rc) {
        Py_DECREF(out);
        return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    }
    return out;
}

static int set_item(PyObject *d, const char *key, PyObject *value)
{
    if (!value) return -1;
    int rc = PyDict_SetItemString(d, key, value);
    Py_DECREF(value);
    return rc;
}

static PyObject *mesh_report(gspy_Mesh *self, PyObject *Py_UNUSED(ignored))
{
    gs_mesh_report r;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_mesh_get_report(self->mesh, &r, &err);
    Py_END_ALLOW_THREADS
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_MESH, NULL, 0);
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    if (set_item(d, "n_vertices", PyLong_FromUnsignedLong(r.n_vertices)) < 0 ||
        set_item(d, "n_faces", PyLong_FromUnsignedLong(r.n_faces)) < 0 ||
        set_item(d, "n_edges", PyLong_FromUnsignedLong(r.n_edges)) < 0 ||
        set_item(d, "unreferenced", PyLong_FromUnsignedLong(r.n_unreferenced)) < 0 ||
        set_item(d, "components", PyLong_FromUnsignedLong(r.n_components)) < 0 ||
        set_item(d, "boundary_edges", PyLong_FromUnsignedLong(r.n_boundary_edges)) < 0 ||
        set_item(d, "boundary_loops", PyLong_FromUnsignedLong(r.n_boundary_loops)) < 0 ||
        set_item(d, "euler", PyLong_FromLong(r.euler)) < 0 || set_item(d, "genus", PyLong_FromLong(r.genus)) < 0 ||
        set_item(d, "min_angle_deg", PyFloat_FromDouble(r.min_angle_deg)) < 0 ||
        set_item(d, "max_angle_deg", PyFloat_FromDouble(r.max_angle_deg)) < 0 ||
        set_item(d, "min_edge", PyFloat_FromDouble(r.min_edge)) < 0 ||
        set_item(d, "max_edge", PyFloat_FromDouble(r.max_edge)) < 0 ||
        set_item(d, "mean_edge", PyFloat_FromDouble(r.mean_edge)) < 0 ||
        set_item(d, "bbox_min", Py_BuildValue("(ddd)", r.bbox_min[0], r.bbox_min[1], r.bbox_min[2])) < 0 ||
        set_item(d, "bbox_max", Py_BuildValue("(ddd)", r.bbox_max[0], r.bbox_max[1], r.bbox_max[2])) < 0) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

static PyObject *mesh_vertices(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    npy_intp dims[2] = {gs_mesh_num_vertices(self->mesh), 3};
    return gspy_readonly_view((PyObject *)self, 2, dims, NPY_DOUBLE, gs_mesh_positions(self->mesh));
}

static PyObject *mesh_faces(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    npy_intp dims[2] = {gs_mesh_num_faces(self->mesh), 3};
    return gspy_readonly_view((PyObject *)self, 2, dims, NPY_UINT32, gs_mesh_faces(self->mesh));
}

static PyObject *mesh_n_vertices(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    return PyLong_FromUnsignedLong(gs_mesh_num_vertices(self->mesh));
}

static PyObject *mesh_n_faces(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    return PyLong_FromUnsignedLong(gs_mesh_num_faces(self->mesh));
}

/* Short names of the kinds of change, in gs_repair_kind order: the keys of
 * repair_report["counts"]. */
static const char *const repair_kind_key[] = {
    "repeated_corner",    "duplicate_face",     "zero_area_collapsed", "zero_area_split", "zero_area_needle",
    "zero_area_boundary", "zero_area_dropped",  "seam_edge",           "seam_ambiguous",  "welded_vertex",
    "nonmanifold_edge",   "flipped_face",       "orientation_cut",     "sheet_cut",       "split_vertex"};
_Static_assert(sizeof repair_kind_key / sizeof *repair_kind_key == GS_REPAIR_NUM_KINDS,
               "a name for every gs_repair_kind");

static PyObject *id_or_none(uint32_t v)
{
    return v == GS_NONE ? Py_NewRef(Py_None) : PyLong_FromUnsignedLong(v);
}

static PyObject *mesh_repair_report(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    const gs_repair *r = self->repair;
    if (!r) Py_RETURN_NONE;
    PyObject *d = PyDict_New(), *counts = PyDict_New(), *examples = PyDict_New();
    if (!d || !counts || !examples) goto fail;
    for (int k = 0; k < GS_REPAIR_NUM_KINDS; k++) {
        if (set_item(counts, repair_kind_key[k], PyLong_FromUnsignedLongLong(r->count[k])) < 0) goto fail;
        if (!r->n_examples[k]) continue;
        PyObject *list = PyList_New(r->n_examples[k]);
        if (!list) goto fail;
        for (uint32_t i = 0; i < r->n_examples[k]; i++) {
            const gs_repair_example *e = &r->example[k][i];
            PyObject *ex = PyDict_New();
            if (!ex) {
                Py_DECREF(list);
                goto fail;
            }
            PyList_SET_ITEM(list, i, ex);
            PyObject *vs = Py_BuildValue("(NNN)", id_or_none(e->vertex[0]), id_or_none(e->vertex[1]),
                                         id_or_none(e->vertex[2]));
            if (set_item(ex, "face", id_or_none(e->face)) < 0 || set_item(ex, "line", id_or_none(e->line)) < 0 ||
                set_item(ex, "vertices", vs) < 0) {
                Py_DECREF(list);
                goto fail;
            }
        }
        if (set_item(examples, repair_kind_key[k], list) < 0) goto fail;
    }
    size_t n = gs_repair_format(r, NULL, 0);
    char *text = PyMem_Malloc(n + 1);
    if (!text) {
        PyErr_NoMemory();
        goto fail;
    }
    gs_repair_format(r, text, n + 1);
    PyObject *t = PyUnicode_DecodeUTF8(text, (Py_ssize_t)n, "replace");
    PyMem_Free(text);
    if (set_item(d, "text", t) < 0 || set_item(d, "n_input_vertices", PyLong_FromUnsignedLong(r->n_input_vertices)) < 0 ||
        set_item(d, "n_input_faces", PyLong_FromUnsignedLong(r->n_input_faces)) < 0 ||
        set_item(d, "n_vertices", PyLong_FromUnsignedLong(r->n_vertices)) < 0 ||
        set_item(d, "n_faces", PyLong_FromUnsignedLong(r->n_faces)) < 0)
        goto fail;
    int rc = PyDict_SetItemString(d, "counts", counts) | PyDict_SetItemString(d, "examples", examples);
    Py_DECREF(counts);
    Py_DECREF(examples);
    if (rc) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
fail:
    Py_XDECREF(d);
    Py_XDECREF(counts);
    Py_XDECREF(examples);
    return NULL;
}

static PyObject *mesh_vertex_map(gspy_Mesh *self, void *Py_UNUSED(closure))
{
    if (!self->repair) Py_RETURN_NONE;
    npy_intp dims[1] = {self->repair->n_input_vertices};
    return gspy_readonly_view((PyObject *)self, 1, dims, NPY_UINT32, self->repair->vertex_map);
}

static PyObject *mesh_input_aliases(gspy_Mesh *self, PyObject *v_obj)
{
    const gs_repair *r = self->repair;
    uint32_t v;
    if (gspy_index(v_obj, r ? r->n_input_vertices : gs_mesh_num_vertices(self->mesh), "input vertex id", &v) < 0)
        return NULL;
    if (!r) { /* not repaired: every vertex is its own only alias */
        npy_intp dims[1] = {1};
        PyObject *a = PyArray_SimpleNew(1, dims, NPY_UINT32);
        if (!a) return NULL;
        *(uint32_t *)PyArray_DATA((PyArrayObject *)a) = v;
        PyArray_CLEARFLAGS((PyArrayObject *)a, NPY_ARRAY_WRITEABLE);
        return a;
    }
    npy_intp dims[1] = {(npy_intp)r->alias_start[v + 1] - (npy_intp)r->alias_start[v]};
    return gspy_readonly_view((PyObject *)self, 1, dims, NPY_UINT32, r->alias + r->alias_start[v]);
}

static PyObject *mesh_repr(gspy_Mesh *self)
{
    return PyUnicode_FromFormat("<geosep.Mesh with %u vertices and %u faces>", gs_mesh_num_vertices(self->mesh),
                                gs_mesh_num_faces(self->mesh));
}

static PyGetSetDef mesh_getset[] = {
    {"vertices", (getter)mesh_vertices, NULL,
     "Vertex positions: a read-only (n_vertices, 3) float64 array (a view of the\n"
     "mesh's own memory, in the order given).",
     NULL},
    {"faces", (getter)mesh_faces, NULL,
     "Faces: a read-only (n_faces, 3) uint32 array of vertex ids, counter-clockwise\n"
     "(a view of the mesh's own memory; uint32 is the library's index type).",
     NULL},
    {"n_vertices", (getter)mesh_n_vertices, NULL, "Number of vertices (used by faces or not).", NULL},
    {"n_faces", (getter)mesh_n_faces, NULL, "Number of triangles.", NULL},
    {"repair_report", (getter)mesh_repair_report, NULL,
     "What repair=True did (doc/repair.md), or None if the mesh was not repaired.\n"
     "A dict: counts (every kind of change by name, with its count: repeated_corner,\n"
     "duplicate_face, zero_area_collapsed, zero_area_split, zero_area_needle,\n"
     "zero_area_boundary, zero_area_dropped, seam_edge, seam_ambiguous,\n"
     "welded_vertex, nonmanifold_edge, flipped_face, orientation_cut, sheet_cut,\n"
     "split_vertex), examples (for each kind made, up to five dicts of face, line\n"
     "and vertices: input ids, None where absent), text (the report as geosep\n"
     "repair prints it), n_input_vertices, n_input_faces, n_vertices, n_faces.",
     NULL},
    {"vertex_map", (getter)mesh_vertex_map, NULL,
     "None if the mesh was not repaired; else a read-only (n_input_vertices,)\n"
     "uint32 array: the vertex each input vertex became (itself, or for a welded\n"
     "vertex the one it was welded into). Input vertices keep their ids and\n"
     "positions; copies made by splitting a vertex are appended (input_aliases).",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

/* pickle: Mesh(V, F) again (validated as any new Mesh). A repaired mesh
 * is refused: its vertex map to the input would be lost. */
static PyObject *mesh_reduce(gspy_Mesh *self, PyObject *Py_UNUSED(ignored))
{
    if (self->repair) {
        PyErr_SetString(PyExc_TypeError, "a repaired Mesh cannot be pickled (its map to the input's vertex ids "
                                         "would be lost): pickle the input arrays and repair them again");
        return NULL;
    }
    PyObject *v = mesh_vertices(self, NULL), *f = v ? mesh_faces(self, NULL) : NULL;
    PyObject *vc = f ? PyArray_NewCopy((PyArrayObject *)v, NPY_CORDER) : NULL;
    PyObject *fc = vc ? PyArray_NewCopy((PyArrayObject *)f, NPY_CORDER) : NULL;
    PyObject *r = fc ? Py_BuildValue("(O(OO))", (PyObject *)Py_TYPE(self), vc, fc) : NULL;
    Py_XDECREF(v), Py_XDECREF(f), Py_XDECREF(vc), Py_XDECREF(fc);
    return r;
}

static PyMethodDef mesh_methods[] = {
    {"__reduce__", (PyCFunction)mesh_reduce, METH_NOARGS, NULL},
    {"load", (PyCFunction)(void (*)(void))mesh_load, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "load($type, /, path, format=None, repair=False)\n--\n\n"
     "Read and validate a mesh file (.obj, .off, .ply, .stl; format=None: by the\n"
     "extension, then by the content). Polygons are fan-triangulated; vertex ids\n"
     "are the file's order. Raises OSError if the file cannot be read and\n"
     "MeshError naming the line or element if it is malformed or the mesh is\n"
     "invalid (non-manifold, inconsistently oriented, degenerate, ...).\n"
     "repair=True repairs an invalid mesh instead, as Mesh(V, F, repair=True)\n"
     "does (examples in repair_report name the file's lines); parse errors\n"
     "stay errors."},
    {"generate", (PyCFunction)mesh_generate, METH_VARARGS | METH_CLASS,
     "generate($type, spec, /)\n--\n\n"
     "A test or demo mesh from a spec string, e.g. \"grid:20,20\" (flat 20 x 20\n"
     "vertex grid on the unit square), \"grid:NX,NY,W,H\", \"peaks:N\", \"plate:N\",\n"
     "\"cylinder:NU,NV[,R,H]\", \"cone:NU,NV[,R,H]\", \"cube:N[,S]\",\n"
     "\"torus:NU,NV[,R,r]\", \"sphere:N\" (icosphere, N subdivisions), \"two:N\" (two\n"
     "components), \"graded:N[,P]\" (flat grid graded towards a corner). A bad spec raises ValueError naming the bad argument."},
    {"subdivide", (PyCFunction)mesh_subdivide, METH_NOARGS,
     "subdivide($self, /)\n--\n\n"
     "A new mesh with every face split into four at its edge midpoints (the same\n"
     "surface). Vertex ids 0..n_vertices-1 are kept; midpoints follow."},
    {"save", (PyCFunction)mesh_save, METH_O,
     "save($self, path, /)\n--\n\nWrite the mesh as OBJ, exactly (written to a temporary file, then renamed)."},
    {"random_vertices", (PyCFunction)(void (*)(void))mesh_random_vertices, METH_VARARGS | METH_KEYWORDS,
     "random_vertices($self, /, k, seed=1)\n--\n\n"
     "Returns a (k,) uint32 array:\n"
     "k distinct vertices used by faces, drawn deterministically from seed (the\n"
     "procedure of the shared ground-truth files)."},
    {"input_aliases", (PyCFunction)mesh_input_aliases, METH_O,
     "input_aliases($self, v, /)\n--\n\n"
     "Returns a read-only uint32 array:\n"
     "every vertex of this mesh that carries corners of input vertex v, the\n"
     "vertex_map one first (a vertex split by repair: itself and its copies; a\n"
     "welded one: the vertex it was welded into). The distance to an input\n"
     "vertex is the least over its aliases. For a mesh not repaired: [v]."},
    {"report", (PyCFunction)mesh_report, METH_NOARGS,
     "report($self, /)\n--\n\n"
     "A dict of\n"
     "what the validation accepted but is worth knowing: n_vertices, n_faces,\n"
     "n_edges, unreferenced (vertices used by no face), components (face-connected),\n"
     "boundary_edges, boundary_loops, euler (V - E + F over referenced vertices),\n"
     "genus (summed over components), min_angle_deg, max_angle_deg, min_edge,\n"
     "max_edge, mean_edge, bbox_min and bbox_max (tuples of 3 floats)."},
    {NULL, NULL, 0, NULL}};

PyTypeObject gspy_MeshType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "geosep.Mesh",
    .tp_basicsize = sizeof(gspy_Mesh),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Mesh(V, F, repair=False)\n--\n\n"
              "An immutable, validated triangle mesh. V: (n, 3) array of floats (vertex\n"
              "positions); F: (m, 3) array of int32 or int64 vertex ids (zero-based,\n"
              "counter-clockwise). Both are copied. The mesh is validated as a mesh file\n"
              "is: out-of-range ids, repeated ids in a face, non-finite coordinates,\n"
              "zero-area faces, non-manifold edges or vertices and inconsistently\n"
              "oriented neighbours raise MeshError with the library's message; a wrong\n"
              "shape or dtype raises ValueError. Several components, boundaries and\n"
              "unreferenced vertices are accepted (see report()).\n\n"
              "repair=True repairs what validation would refuse, knowingly\n"
              "(doc/repair.md): duplicate faces and faces repeating a vertex dropped,\n"
              "zero-area faces removed, unwelded seams glued, extra faces of an edge\n"
              "detached, components oriented, non-manifold vertices split. Every input\n"
              "vertex keeps its id and position; copies are appended. repair_report,\n"
              "vertex_map and input_aliases() say what was done and where each input\n"
              "vertex went; out-of-range ids and non-finite coordinates still raise.\n\n"
              "A Mesh is immutable and may be shared between threads.",
    .tp_new = mesh_new,
    .tp_dealloc = (destructor)mesh_dealloc,
    .tp_repr = (reprfunc)mesh_repr,
    .tp_methods = mesh_methods,
    .tp_getset = mesh_getset,
};

int gspy_mesh_init_type(PyObject *module)
{
    if (PyType_Ready(&gspy_MeshType) < 0) return -1;
    return PyModule_AddObjectRef(module, "Mesh", (PyObject *)&gspy_MeshType);
}
