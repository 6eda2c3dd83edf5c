/* render.c - geosep.render: a picture of a mesh, coloured by a distance
 * field with isolines and optionally a database's separator curves (the
 * library's software rasterizer, gs_render / gs_render_png). */
#include "geosep_py.h"

#include <errno.h>

/* A pair of numbers (w, h) or (azimuth, elevation). */
static int pair(PyObject *obj, const char *name, double out[2])
{
    PyObject *seq = PySequence_Fast(obj, "");
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 2) {
        Py_XDECREF(seq);
        PyErr_Format(PyExc_TypeError, "%s must be a pair of numbers, got %R", name, obj);
        return -1;
    }
    for (int i = 0; i < 2; i++) {
        out[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, i));
        if (out[i] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            PyErr_Format(PyExc_TypeError, "%s must be a pair of numbers, got %R", name, obj);
            return -1;
        }
    }
    Py_DECREF(seq);
    return 0;
}

/* polylines=: one (k, 3) array or a sequence of them, into the options
 * (*xyz and *starts: PyMem buffers, the caller frees them). 0 or -1. */
static int polylines(PyObject *obj, double **xyz, uint32_t **starts, gs_render_options *o)
{
    PyArrayObject *one = (PyArrayObject *)PyArray_FROM_OTF(obj, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
    int single = one && PyArray_NDIM(one) == 2 && PyArray_DIM(one, 1) == 3;
    if (!single) {
        Py_XDECREF(one);
        PyErr_Clear();
    }
    PyObject *seq = single ? NULL : PySequence_Fast(obj, "");
    if (!single && !seq) {
        PyErr_SetString(PyExc_TypeError, "polylines must be a (k, 3) array or a sequence of them");
        return -1;
    }
    Py_ssize_t n = single ? 1 : PySequence_Fast_GET_SIZE(seq), total = 0;
    PyArrayObject **arr = PyMem_New(PyArrayObject *, (size_t)n + 1);
    int rc = arr ? 0 : (PyErr_NoMemory(), -1);
    Py_ssize_t got = 0;
    for (Py_ssize_t i = 0; i < n && !rc; ++i, ++got) {
        arr[i] = single ? one : (PyArrayObject *)PyArray_FROM_OTF(PySequence_Fast_GET_ITEM(seq, i), NPY_DOUBLE,
                                                                 NPY_ARRAY_IN_ARRAY);
        if (!arr[i] || PyArray_NDIM(arr[i]) != 2 || PyArray_DIM(arr[i], 1) != 3) {
            if (arr[i]) Py_DECREF(arr[i]);
            PyErr_Clear();
            PyErr_Format(PyExc_ValueError, "polylines[%zd] must be a (k, 3) array of points", i);
            rc = -1;
            break;
        }
        total += PyArray_DIM(arr[i], 0);
    }
    if (!rc && (total >= UINT32_MAX || n >= UINT32_MAX)) {
        PyErr_SetString(PyExc_ValueError, "polylines: too many points");
        rc = -1;
    }
    if (!rc && (!(*xyz = PyMem_New(double, 3 * (size_t)total + 1)) || !(*starts = PyMem_New(uint32_t, (size_t)n + 1))))
        rc = (PyErr_NoMemory(), -1);
    if (!rc) {
        (*starts)[0] = 0;
        for (Py_ssize_t i = 0; i < n; ++i) {
            npy_intp k = PyArray_DIM(arr[i], 0);
            memcpy(*xyz + 3 * (size_t)(*starts)[i], PyArray_DATA(arr[i]), 3 * (size_t)k * sizeof(double));
            (*starts)[i + 1] = (*starts)[i] + (uint32_t)k;
        }
        o->paths = *xyz, o->path_starts = *starts, o->n_paths = (uint32_t)n;
    }
    for (Py_ssize_t i = 0; i < got; ++i) Py_DECREF(arr[i]);
    PyMem_Free(arr);
    Py_XDECREF(seq);
    if (single && !arr) Py_DECREF(one);
    return rc;
}

const char gspy_render_doc[] =
    "render(mesh, field=None, *, isolines=10, separators=None, points=None, polylines=None, size=(640, 480), "
    "view=(30, 20), path=None)\n--\n\n"
    "Draw a mesh: shaded, coloured by a field (n_vertices values, e.g. a\n"
    "distance field; viridis from its smallest to its largest finite value,\n"
    "grey where not finite) with `isolines` dark lines at evenly spaced\n"
    "levels; separators: a Database of this mesh, whose separator curves are\n"
    "drawn (red: the root's, then orange, blue, green, purple by depth);\n"
    "points: (k, 3) positions drawn as dots; polylines: a (k, 3) array of a\n"
    "polyline's points (Database.path, Solver.path) or a list of them, drawn\n"
    "as white lines in a dark border. size: (width, height) in pixels;\n"
    "view: (azimuth, elevation) in degrees ((0, 0) looks from +z, y up).\n"
    "Returns an (height, width, 3) uint8 RGB array, or, with path, writes a\n"
    "PNG file (atomically) and returns None. The GIL is released while\n"
    "drawing.";

PyObject *gspy_render(PyObject *Py_UNUSED(module), PyObject *args, PyObject *kwargs)
{
    static char *kw[] = {"mesh", "field", "isolines", "separators", "points", "polylines", "size", "view", "path", NULL};
    PyObject *mesh_obj, *field_obj = Py_None, *iso_obj = NULL, *sep_obj = Py_None, *pts_obj = Py_None,
                        *lines_obj = Py_None, *size_obj = NULL, *view_obj = NULL, *path_obj = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!|O$OOOOOOO:render", kw, &gspy_MeshType, &mesh_obj, &field_obj,
                                     &iso_obj, &sep_obj, &pts_obj, &lines_obj, &size_obj, &view_obj, &path_obj))
        return NULL;
    const gs_mesh *mesh = ((gspy_Mesh *)mesh_obj)->mesh;
    gs_render_options o;
    gs_render_options_default(&o);
    double size[2] = {o.width, o.height}, view[2] = {o.azimuth_deg, o.elevation_deg};
    if ((size_obj && pair(size_obj, "size", size) < 0) || (view_obj && pair(view_obj, "view", view) < 0) ||
        gspy_opt_u32(iso_obj, o.isolines, "isolines", &o.isolines) < 0)
        return NULL;
    if (!(size[0] >= GS_RENDER_MIN_SIZE && size[0] <= GS_RENDER_MAX_SIZE && size[1] >= GS_RENDER_MIN_SIZE &&
          size[1] <= GS_RENDER_MAX_SIZE) ||
        size[0] != (uint32_t)size[0] || size[1] != (uint32_t)size[1]) {
        PyErr_Format(PyExc_ValueError, "size must be (width, height) in whole pixels, each %u to %u, got %R",
                     GS_RENDER_MIN_SIZE, GS_RENDER_MAX_SIZE, size_obj);
        return NULL;
    }
    o.width = (uint32_t)size[0];
    o.height = (uint32_t)size[1];
    o.azimuth_deg = view[0];
    o.elevation_deg = view[1];
    if (sep_obj != Py_None) {
        if (!PyObject_TypeCheck(sep_obj, &gspy_DatabaseType)) {
            PyErr_Format(PyExc_TypeError, "separators must be a geosep.Database or None, got %s",
                         Py_TYPE(sep_obj)->tp_name);
            return NULL;
        }
        o.separators = ((gspy_Database *)sep_obj)->db;
    }
    PyArrayObject *field = NULL, *points = NULL;
    PyObject *path = NULL, *out = NULL, *result = NULL;
    double *lines = NULL;
    uint32_t *starts = NULL;
    uint32_t n = gs_mesh_num_vertices(mesh);
    if (field_obj != Py_None) {
        field = (PyArrayObject *)PyArray_FROM_OTF(field_obj, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
        if (!field) goto done;
        if (PyArray_NDIM(field) != 1 || PyArray_DIM(field, 0) != (npy_intp)n) {
            PyErr_Format(PyExc_ValueError, "field must be an (n_vertices,) = (%u,) array of numbers, got %d-D of %zd",
                         n, PyArray_NDIM(field), (Py_ssize_t)PyArray_SIZE(field));
            goto done;
        }
        o.field = PyArray_DATA(field);
    }
    if (pts_obj != Py_None) {
        points = (PyArrayObject *)PyArray_FROM_OTF(pts_obj, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
        if (!points) goto done;
        if (PyArray_NDIM(points) != 2 || PyArray_DIM(points, 1) != 3 || PyArray_DIM(points, 0) >= UINT32_MAX) {
            PyErr_SetString(PyExc_ValueError, "points must be a (k, 3) array of positions");
            goto done;
        }
        o.points = PyArray_DATA(points);
        o.n_points = (uint32_t)PyArray_DIM(points, 0);
    }
    if (lines_obj != Py_None && polylines(lines_obj, &lines, &starts, &o) < 0) goto done;
    gs_error err = {0};
    int rc, saved_errno = 0;
    if (path_obj != Py_None) {
        if (!(path = gspy_path(path_obj))) goto done;
        const char *p = PyBytes_AS_STRING(path);
        Py_BEGIN_ALLOW_THREADS
        errno = 0;
        rc = gs_render_png(mesh, &o, p, &err);
        saved_errno = errno;
        Py_END_ALLOW_THREADS
        result = rc ? gspy_raise(rc, &err, GSPY_CTX_OTHER, p, saved_errno) : Py_NewRef(Py_None);
        goto done;
    }
    npy_intp dims[3] = {o.height, o.width, 3};
    if (!(out = PyArray_SimpleNew(3, dims, NPY_UINT8))) goto done;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_render(mesh, &o, PyArray_DATA((PyArrayObject *)out), &err);
    Py_END_ALLOW_THREADS
    if (rc) {
        gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    } else {
        result = Py_NewRef(out);
    }
done:
    Py_XDECREF(out);
    Py_XDECREF(path);
    Py_XDECREF(field);
    Py_XDECREF(points);
    PyMem_Free(lines);
    PyMem_Free(starts);
    return result;
}
