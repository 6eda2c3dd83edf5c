/* dbpath.c - Database.path: geodesic paths from a database (gs_db_path) and
 * the mesh it was built from. */
#include "geosep_py.h"

const char gspy_db_path_doc[] =
    "path($self, /, x, y, *, mesh=None, return_faces=False)\n--\n\n"
    "Returns a (k, 3) float64 array of points, or with return_faces=True a\n"
    "tuple (points, faces (k,) int64, bary (k, 3) float64).\n\n"
    "A geodesic path from x to y, each a vertex id or a surface point\n"
    "(face, (b0, b1, b2)), from the database, without solving a field: a\n"
    "polyline on the surface (x, every crossing with an edge, every vertex it\n"
    "passes through, y; faces[i] holds the segment from point i to point i+1,\n"
    "the last point the segment arriving at it), locally shortest, never\n"
    "shorter than the exact distance and within 1% of it on the meshes\n"
    "measured (doc/paths.md). mesh: the Mesh the database was built from\n"
    "(default: that mesh, when built in this process; a database stores\n"
    "positions, not faces); another mesh raises ValueError. x == y gives one\n"
    "point; y unreachable from x (another component) a (0, 3) array. A vertex\n"
    "or face id out of range raises IndexError, bad weights ValueError. Runs\n"
    "without the GIL (any number of threads at once).";

PyObject *gspy_db_path(PyObject *self_obj, PyObject *args, PyObject *kwargs)
{
    gspy_Database *self = (gspy_Database *)self_obj;
    static char *kw[] = {"x", "y", "mesh", "return_faces", NULL};
    PyObject *xo, *yo, *mesh_obj = Py_None;
    int with_faces = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "OO|$Op:path", kw, &xo, &yo, &mesh_obj, &with_faces)) return NULL;
    const gs_mesh *m = gspy_db_mesh(self, mesh_obj, "path");
    if (!m) return NULL;
    gs_source x, y;
    if (gspy_path_end(xo, m, "x", &x) < 0 || gspy_path_end(yo, m, "y", &y) < 0) return NULL;
    gs_path *p = NULL;
    gs_error err = {0};
    int rc;
    Py_BEGIN_ALLOW_THREADS
    rc = gs_db_path(self->db, m, &x, &y, &p, &err);
    Py_END_ALLOW_THREADS
    if (rc == GS_EARG) { /* the weights (ids were checked): the library's message */
        PyErr_SetString(PyExc_ValueError, err.message);
        return NULL;
    }
    if (rc) return gspy_raise(rc, &err, GSPY_CTX_OTHER, NULL, 0);
    PyObject *out = gspy_path_arrays(p, with_faces);
    gs_path_free(p);
    return out;
}
