/* module.c - the extension module geosep._geosep: imports numpy's C API,
 * registers the exceptions and types, and the module-level functions. */
#define GSPY_IMPORT_ARRAY
#include "geosep_py.h"

static PyMethodDef module_methods[] = {
    {"distance_field", (PyCFunction)(void (*)(void))gspy_distance_field, METH_VARARGS | METH_KEYWORDS,
     gspy_distance_field_doc},
    {"geodesic_path", (PyCFunction)(void (*)(void))gspy_geodesic_path, METH_VARARGS | METH_KEYWORDS,
     gspy_geodesic_path_doc},
    {"render", (PyCFunction)(void (*)(void))gspy_render, METH_VARARGS | METH_KEYWORDS, gspy_render_doc},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    .m_name = "geosep._geosep",
    .m_doc = "The C extension of geosep (import geosep, not this module).",
    .m_size = -1,
    .m_methods = module_methods,
};

PyMODINIT_FUNC PyInit__geosep(void)
{
    import_array(); /* returns NULL with ImportError if numpy's C API is unusable */
    PyObject *m = PyModule_Create(&module_def);
    if (!m) return NULL;
    if (PyModule_AddStringConstant(m, "__version__", gs_version_string()) < 0 || gspy_errors_init(m) < 0 ||
        gspy_mesh_init_type(m) < 0 || gspy_solver_init_type(m) < 0 || gspy_database_init_type(m) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
