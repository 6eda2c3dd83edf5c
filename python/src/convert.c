/* convert.c - Python arguments to the library's types: vertex ids (scalars
 * and arrays, checked against their range before any call into the
 * library), paths, options, methods and distance-field sources. */
#include "geosep_py.h"

#include <math.h>

int gspy_is_int_scalar(PyObject *obj)
{
    return PyLong_Check(obj) || PyArray_IsScalar(obj, Integer);
}

int gspy_index(PyObject *obj, uint32_t limit, const char *what, uint32_t *out)
{
    PyObject *i = PyNumber_Index(obj);
    if (!i) return -1;
    int overflow = 0;
    long long v = PyLong_AsLongLongAndOverflow(i, &overflow);
    Py_DECREF(i);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (overflow || v < 0 || (unsigned long long)v >= limit) {
        PyObject *r = PyObject_Repr(obj);
        if (r) PyErr_Format(PyExc_IndexError, "%s %U is out of range [0, %u)", what, r, limit);
        Py_XDECREF(r);
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

PyArrayObject *gspy_int_array(PyObject *obj, const char *what)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_O(obj);
    if (!a) return NULL;
    /* np.asarray([]) is float64: an empty array of any dtype is no ids */
    if (PyArray_SIZE(a) > 0 && !PyArray_ISINTEGER(a)) {
        PyErr_Format(PyExc_ValueError, "%s must be integers (vertex ids), got an array of dtype %S", what,
                     (PyObject *)PyArray_DESCR(a));
        Py_DECREF(a);
        return NULL;
    }
    PyArrayObject *r = (PyArrayObject *)PyArray_FromArray(a, PyArray_DescrFromType(NPY_INT64),
                                                          NPY_ARRAY_CARRAY_RO | NPY_ARRAY_FORCECAST);
    /* FORCECAST: uint64 ids above 2^63 become negative and are refused as such */
    Py_DECREF(a);
    return r;
}

int gspy_check_ids(const int64_t *ids, npy_intp n, uint32_t limit, const char *kind, const char *name, uint32_t *out)
{
    for (npy_intp i = 0; i < n; i++) {
        if (ids[i] < 0 || (uint64_t)ids[i] >= limit) {
            PyErr_Format(PyExc_IndexError, "%s %lld (%s, flat index %zd) is out of range [0, %u)", kind,
                         (long long)ids[i], name, (Py_ssize_t)i, limit);
            return -1;
        }
        if (out) out[i] = (uint32_t)ids[i];
    }
    return 0;
}

int gspy_check_array_ids(PyArrayObject *a, uint32_t limit, const char *kind, const char *name)
{
    return gspy_check_ids(PyArray_DATA(a), PyArray_SIZE(a), limit, kind, name, NULL);
}

PyObject *gspy_path(PyObject *obj)
{
    PyObject *bytes = NULL;
    if (!PyUnicode_FSConverter(obj, &bytes)) return NULL;
    return bytes;
}

int gspy_opt_double(PyObject *obj, double dflt, const char *what, double *out)
{
    if (!obj || obj == Py_None) return *out = dflt, 0;
    double v = PyFloat_AsDouble(obj);
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Format(PyExc_TypeError, "%s must be a number, got %s", what, Py_TYPE(obj)->tp_name);
        return -1;
    }
    *out = v;
    return 0;
}

int gspy_opt_u32(PyObject *obj, uint32_t dflt, const char *what, uint32_t *out)
{
    if (!obj || obj == Py_None) return *out = dflt, 0;
    if (PyBool_Check(obj) || !gspy_is_int_scalar(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be an integer, got %s", what, Py_TYPE(obj)->tp_name);
        return -1;
    }
    PyObject *i = PyNumber_Index(obj);
    if (!i) return -1;
    int overflow = 0;
    long long v = PyLong_AsLongLongAndOverflow(i, &overflow);
    Py_DECREF(i);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (overflow || v < 0 || v > (long long)UINT32_MAX - 1) {
        PyErr_Format(PyExc_ValueError, "%s must be an integer in [0, %u), got %R", what, UINT32_MAX, obj);
        return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

int gspy_method(PyObject *obj, gs_method *out)
{
    if (!obj || obj == Py_None) return *out = GS_METHOD_EXACT, 0;
    const char *name = PyUnicode_Check(obj) ? PyUnicode_AsUTF8(obj) : NULL;
    if (!name) {
        if (!PyErr_Occurred())
            PyErr_Format(PyExc_TypeError, "method must be a str (\"exact\", \"graph\", \"fmm\", \"heat\" or \"dgg\"), got %s",
                         Py_TYPE(obj)->tp_name);
        return -1;
    }
    gs_error err = {0};
    if (gs_method_from_name(name, out, &err) != GS_OK) {
        PyErr_Format(PyExc_ValueError, "unknown method %R: expected \"exact\", \"graph\", \"fmm\", \"heat\" or \"dgg\"", obj);
        return -1;
    }
    return 0;
}

int gspy_solver_options(PyObject *heat_time, PyObject *heat_refine, PyObject *fmm_start, PyObject *dgg_eps,
                        gs_solver_options *opt)
{
    gs_solver_options d;
    gs_solver_options_default(&d);
    if (gspy_opt_double(dgg_eps, d.dgg_eps, "dgg_eps", &opt->dgg_eps) < 0) return -1;
    if (!(opt->dgg_eps >= GS_DGG_EPS_MIN && opt->dgg_eps <= GS_DGG_EPS_MAX)) {
        PyErr_Format(PyExc_ValueError, "dgg_eps must be in [%g, %g], got %g", GS_DGG_EPS_MIN, GS_DGG_EPS_MAX,
                     opt->dgg_eps);
        return -1;
    }
    if (gspy_opt_double(heat_time, d.heat_time, "heat_time", &opt->heat_time) < 0) return -1;
    if (gspy_opt_double(fmm_start, d.fmm_exact_start, "fmm_start", &opt->fmm_exact_start) < 0) return -1;
    if (heat_refine && PyUnicode_Check(heat_refine)) {
        if (PyUnicode_CompareWithASCIIString(heat_refine, "auto") != 0) {
            PyErr_Format(PyExc_ValueError, "heat_refine must be 0 to %d or \"auto\", got %R", GS_HEAT_REFINE_MAX,
                         heat_refine);
            return -1;
        }
        opt->heat_refine = GS_HEAT_REFINE_AUTO;
        return 0;
    }
    if (gspy_opt_u32(heat_refine, d.heat_refine, "heat_refine", &opt->heat_refine) < 0) return -1;
    if (opt->heat_refine > GS_HEAT_REFINE_MAX && opt->heat_refine != GS_HEAT_REFINE_AUTO) {
        PyErr_Format(PyExc_ValueError, "heat_refine must be 0 to %d or \"auto\", got %u", GS_HEAT_REFINE_MAX,
                     opt->heat_refine);
        return -1;
    }
    return 0;
}

gs_source *gspy_sources(PyObject *obj, uint32_t n_vertices, uint32_t *n_out)
{
    uint32_t v;
    if (gspy_is_int_scalar(obj)) {
        if (gspy_index(obj, n_vertices, "source vertex", &v) < 0) return NULL;
        gs_source *s = PyMem_New(gs_source, 1);
        if (!s) return (gs_source *)PyErr_NoMemory();
        s[0] = gs_source_vertex(v);
        *n_out = 1;
        return s;
    }
    PyArrayObject *a = gspy_int_array(obj, "sources");
    if (!a) return NULL;
    npy_intp n = PyArray_SIZE(a);
    gs_source *s = NULL;
    if (PyArray_NDIM(a) > 1) {
        PyErr_SetString(PyExc_ValueError, "sources must be a vertex id or a 1-D sequence of vertex ids");
    } else if (n == 0) {
        PyErr_SetString(PyExc_ValueError, "sources is empty: give at least one vertex id");
    } else if (n > (npy_intp)UINT32_MAX - 1) {
        PyErr_SetString(PyExc_ValueError, "too many sources");
    } else if (!(s = PyMem_New(gs_source, (size_t)n))) {
        PyErr_NoMemory();
    } else {
        const int64_t *ids = PyArray_DATA(a);
        if (gspy_check_ids(ids, n, n_vertices, "source vertex", "sources", NULL) < 0) {
            PyMem_Free(s);
            s = NULL;
        } else {
            for (npy_intp i = 0; i < n; i++) s[i] = gs_source_vertex((uint32_t)ids[i]);
        }
        *n_out = (uint32_t)n;
    }
    Py_DECREF(a);
    return s;
}

int gspy_max_distance(PyObject *obj, double *out)
{
    if (gspy_opt_double(obj, 0, "max_distance", out) < 0) return -1;
    if (obj && obj != Py_None && !(*out > 0)) { /* NaN, 0 and negative values */
        PyErr_Format(PyExc_ValueError, "max_distance must be > 0 (or None, or inf: no bound), got %R", obj);
        return -1;
    }
    return 0;
}
