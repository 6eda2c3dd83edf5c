/* errors.c - the exception classes of geosep and the one place that turns a
 * library status code (GS_E*) and its message into a Python exception. */
#include "geosep_py.h"

PyObject *gspy_Error, *gspy_MeshError, *gspy_DatabaseError;

static PyObject *oserror(const char *message, const char *path, int saved_errno)
{
    /* OSError(errno, message) becomes the matching subclass (ENOENT:
     * FileNotFoundError, ...); the message already names the file, which
     * is also kept in .filename when the errno is known (an OSError with a
     * filename prints "[Errno E] strerror: filename", which without an
     * errno is "[Errno None] None: 'x'": the message would be lost). */
    PyObject *exc = saved_errno ? PyObject_CallFunction(PyExc_OSError, "is", saved_errno, message)
                                : PyObject_CallFunction(PyExc_OSError, "s", message);
    if (!exc) return NULL;
    if (path && saved_errno) {
        PyObject *fn = PyUnicode_DecodeFSDefault(path);
        if (!fn || PyObject_SetAttrString(exc, "filename", fn) < 0) {
            Py_XDECREF(fn);
            Py_DECREF(exc);
            return NULL;
        }
        Py_DECREF(fn);
    }
    PyErr_SetObject((PyObject *)Py_TYPE(exc), exc);
    Py_DECREF(exc);
    return NULL;
}

PyObject *gspy_raise(int status, const gs_error *err, gspy_ctx ctx, const char *path, int saved_errno)
{
    const char *msg = err && err->message[0] ? err->message : gs_status_string(status);
    PyObject *type;
    switch (status) {
    case GS_EIO: return oserror(msg, path, saved_errno);
    case GS_ENOMEM: type = PyExc_MemoryError; break;
    case GS_EARG: type = PyExc_ValueError; break;
    case GS_EMESH: type = gspy_MeshError; break;
    case GS_EPARSE:
    case GS_EFORMAT:
    case GS_ELIMIT:
        type = ctx == GSPY_CTX_MESH ? gspy_MeshError : ctx == GSPY_CTX_DB ? gspy_DatabaseError
               : status == GS_ELIMIT ? PyExc_ValueError : gspy_Error;
        break;
    default: type = gspy_Error; break; /* GS_EINTERNAL and any future code */
    }
    PyErr_SetString(type, msg);
    return NULL;
}

static PyObject *new_exception(PyObject *module, const char *name, const char *doc, PyObject *bases)
{
    char full[64];
    PyOS_snprintf(full, sizeof full, "geosep.%s", name);
    PyObject *cls = PyErr_NewExceptionWithDoc(full, doc, bases, NULL);
    if (cls && PyModule_AddObjectRef(module, name, cls) < 0) Py_CLEAR(cls);
    return cls;
}

int gspy_errors_init(PyObject *module)
{
    gspy_Error = new_exception(module, "Error",
                               "Base class of the errors geosep raises itself (a numerical or internal\n"
                               "failure raises Error; see MeshError and DatabaseError). Bad arguments\n"
                               "raise the built-in ValueError, TypeError or IndexError; files that\n"
                               "cannot be read or written raise OSError.",
                               NULL);
    if (!gspy_Error) return -1;
    PyObject *bases = PyTuple_Pack(2, gspy_Error, PyExc_ValueError);
    if (!bases) return -1;
    gspy_MeshError = new_exception(module, "MeshError",
                                   "An invalid mesh: a malformed mesh file, or a mesh (from a file or from\n"
                                   "arrays) that fails validation. The message is the library's, naming\n"
                                   "the file and line or the element that is wrong, e.g.\n"
                                   "'non-manifold vertex 253 ...'. A subclass of Error and ValueError.",
                                   bases);
    gspy_DatabaseError = new_exception(module, "DatabaseError",
                                       "A corrupt, truncated or incompatible database file; the message names\n"
                                       "the section and field that is wrong. A subclass of Error and ValueError.",
                                       bases);
    Py_DECREF(bases);
    return gspy_MeshError && gspy_DatabaseError ? 0 : -1;
}
