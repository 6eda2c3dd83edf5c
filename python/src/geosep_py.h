/* geosep_py.h - what the files of the Python extension geosep._geosep share:
 * the object types (Mesh, Solver, Database), the exception classes, and the
 * helpers that turn Python arguments into the library's arrays and the
 * library's status codes into Python exceptions. */
#ifndef GEOSEP_PY_H
#define GEOSEP_PY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL gspy_ARRAY_API
#ifndef GSPY_IMPORT_ARRAY /* defined by module.c only, which imports numpy */
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "geosep.h"

/* ---- exceptions (errors.c) ---------------------------------------------- */

extern PyObject *gspy_Error, *gspy_MeshError, *gspy_DatabaseError;

/* What a failing call was working on: picks the exception class of
 * GS_EPARSE, GS_EFORMAT and GS_ELIMIT (a mesh file or a database file). */
typedef enum { GSPY_CTX_OTHER, GSPY_CTX_MESH, GSPY_CTX_DB } gspy_ctx;

/* Set the Python exception for a failed call (status < 0, the message in
 * err) and return NULL. path (may be NULL) and saved_errno (0: unknown) go
 * into the OSError of GS_EIO. */
PyObject *gspy_raise(int status, const gs_error *err, gspy_ctx ctx, const char *path, int saved_errno);
int gspy_errors_init(PyObject *module);

/* ---- argument conversion (convert.c) ------------------------------------ */

/* A vertex or face id as a Python int (or numpy integer), checked against
 * [0, limit): 0, or -1 with TypeError / IndexError set. `what` names it. */
int gspy_index(PyObject *obj, uint32_t limit, const char *what, uint32_t *out);

/* True for a Python int or a numpy integer scalar (not an array). */
int gspy_is_int_scalar(PyObject *obj);

/* Any array-like of integers (any shape; an empty one of any dtype) as a new
 * C-contiguous int64 array; NULL with ValueError naming `what` otherwise. */
PyArrayObject *gspy_int_array(PyObject *obj, const char *what);

/* Check n int64 ids against [0, limit) and copy them to out as uint32 (out
 * may be NULL: check only). -1 with IndexError naming the first bad id, its
 * kind ("vertex id"), the argument's name and the flat index. */
int gspy_check_ids(const int64_t *ids, npy_intp n, uint32_t limit, const char *kind, const char *name, uint32_t *out);
/* gspy_check_ids of an int64 array (gspy_int_array's), checking only. */
int gspy_check_array_ids(PyArrayObject *a, uint32_t limit, const char *kind, const char *name);

/* A path (str, bytes or os.PathLike) as a new bytes object; NULL on error. */
PyObject *gspy_path(PyObject *obj);

/* An optional float argument: None gives dflt. -1 with TypeError. */
int gspy_opt_double(PyObject *obj, double dflt, const char *what, double *out);

/* An optional count (a non-negative int below 2^32): None gives dflt. */
int gspy_opt_u32(PyObject *obj, uint32_t dflt, const char *what, uint32_t *out);

/* Method from its name ("exact", "graph", "fmm", "heat"); ValueError. */
int gspy_method(PyObject *obj, gs_method *out);

/* Solver options from their Python values (each may be NULL or None:
 * default): heat_time, heat_refine (int or "auto"), fmm_start. */
int gspy_solver_options(PyObject *heat_time, PyObject *heat_refine, PyObject *fmm_start, PyObject *dgg_eps,
                        gs_solver_options *opt);

/* Sources (an int or a sequence of ints, not empty) as a new array of
 * vertex sources, checked against [0, n_vertices). NULL with an exception
 * set otherwise; free with PyMem_Free. */
gs_source *gspy_sources(PyObject *obj, uint32_t n_vertices, uint32_t *n_out);

/* max_distance: None -> 0 (no bound), else a number > 0 (inf allowed). */
int gspy_max_distance(PyObject *obj, double *out);

/* ---- types -------------------------------------------------------------- */

typedef struct {
    PyObject_HEAD
    gs_mesh *mesh;     /* owned, immutable */
    gs_repair *repair; /* owned: what repair=True did, or NULL */
} gspy_Mesh;

typedef struct {
    PyObject_HEAD
    PyObject *mesh;          /* the gspy_Mesh it solves on (a reference)   */
    gs_patch *patch;         /* the whole mesh, owned                      */
    gs_solver *solver;       /* owned; scratch space: used under lock only */
    PyThread_type_lock lock; /* one solve at a time                        */
    gs_method method;
    gs_solver_options options;
} gspy_Solver;

typedef struct {
    PyObject_HEAD
    gs_db *db;          /* owned, immutable: queried without the GIL         */
    uint32_t n_vertices;
    PyObject *mesh;     /* the Mesh it was built from, or NULL (opened)      */
    PyObject *checked;  /* the last Mesh found to match it (point_distance)  */
    PyObject *stats;    /* dict of the build's statistics, or NULL           */
} gspy_Database;

extern PyTypeObject gspy_MeshType, gspy_SolverType, gspy_DatabaseType;

/* mesh.c */
int gspy_mesh_init_type(PyObject *module);
PyObject *gspy_mesh_wrap(PyTypeObject *type, gs_mesh *mesh); /* steals mesh */
/* A read-only array viewing data owned by `base` (which it keeps alive). */
PyObject *gspy_readonly_view(PyObject *base, int nd, npy_intp *dims, int typenum, const void *data);

/* solver.c */
int gspy_solver_init_type(PyObject *module);
PyObject *gspy_distance_field(PyObject *module, PyObject *args, PyObject *kwargs);
extern const char gspy_distance_field_doc[];
PyObject *gspy_geodesic_path(PyObject *module, PyObject *args, PyObject *kwargs);
extern const char gspy_geodesic_path_doc[];
/* One end of a path: a vertex id, or (face, (b0, b1, b2)). 0, or -1 with
 * TypeError / IndexError / ValueError set. */
int gspy_path_end(PyObject *obj, const gs_mesh *m, const char *name, gs_source *out);
/* A path as numpy arrays: (k, 3) xyz, or (xyz, faces (k,), bary (k, 3)). */
PyObject *gspy_path_arrays(const gs_path *p, int with_faces);

/* dbpath.c: Database.path */
PyObject *gspy_db_path(PyObject *self, PyObject *args, PyObject *kwargs);
extern const char gspy_db_path_doc[];
#define GSPY_DB_PATH_METHODS                                                                                  \
    {"path", (PyCFunction)(void (*)(void))gspy_db_path, METH_VARARGS | METH_KEYWORDS, gspy_db_path_doc}

/* render.c */
PyObject *gspy_render(PyObject *module, PyObject *args, PyObject *kwargs);
extern const char gspy_render_doc[];

/* database.c */
int gspy_database_init_type(PyObject *module);

/* dbquery.c: the queries, methods of Database */
/* d(x, y) for ints (a float) or arrays broadcast as numpy does (a float64
 * array), by vertex id or (input) by input vertex id; batches without the
 * GIL. New reference, or NULL with IndexError / ValueError set. */
PyObject *gspy_db_pairs(gspy_Database *self, PyObject *x, PyObject *y, int input);
/* The Mesh that names faces for the Database method `method`: mesh_obj, or
 * the one the database was built from (None); it must be the database's
 * (gs_db_check_mesh, remembered per Mesh object). Borrowed; NULL with
 * TypeError / ValueError set. */
const gs_mesh *gspy_db_mesh(gspy_Database *self, PyObject *mesh_obj, const char *method);
PyObject *gspy_db_distance(PyObject *self, PyObject *args);
PyObject *gspy_db_pairwise(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *gspy_db_field(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *gspy_db_point_distance(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *gspy_db_farthest_point_sampling(PyObject *self, PyObject *args, PyObject *kwargs);
extern const char gspy_db_distance_doc[], gspy_db_pairwise_doc[], gspy_db_field_doc[],
    gspy_db_point_distance_doc[], gspy_db_farthest_point_sampling_doc[];
/* dbinput.c: the queries by input vertex id (a repaired mesh's database) */
PyObject *gspy_db_input_distance(PyObject *self, PyObject *args);
PyObject *gspy_db_input_field(PyObject *self, PyObject *arg);
PyObject *gspy_db_input_aliases(PyObject *self, PyObject *arg);
PyObject *gspy_db_get_n_input_vertices(PyObject *self, void *closure);
extern const char gspy_db_input_distance_doc[], gspy_db_input_field_doc[], gspy_db_input_aliases_doc[];
#define GSPY_DB_INPUT_METHODS                                                                                 \
    {"input_distance", (PyCFunction)gspy_db_input_distance, METH_VARARGS, gspy_db_input_distance_doc},        \
        {"input_field", (PyCFunction)gspy_db_input_field, METH_O, gspy_db_input_field_doc},                   \
    {                                                                                                         \
        "input_aliases", (PyCFunction)gspy_db_input_aliases, METH_O, gspy_db_input_aliases_doc                \
    }

#define GSPY_DB_QUERY_METHODS                                                                                 \
    {"distance", (PyCFunction)gspy_db_distance, METH_VARARGS, gspy_db_distance_doc},                          \
        {"pairwise", (PyCFunction)(void (*)(void))gspy_db_pairwise, METH_VARARGS | METH_KEYWORDS,             \
         gspy_db_pairwise_doc},                                                                               \
        {"field", (PyCFunction)(void (*)(void))gspy_db_field, METH_VARARGS | METH_KEYWORDS,                   \
         gspy_db_field_doc},                                                                                  \
        {"farthest_point_sampling", (PyCFunction)(void (*)(void))gspy_db_farthest_point_sampling,             \
         METH_VARARGS | METH_KEYWORDS, gspy_db_farthest_point_sampling_doc},                                  \
    {                                                                                                         \
        "point_distance", (PyCFunction)(void (*)(void))gspy_db_point_distance, METH_VARARGS | METH_KEYWORDS,  \
            gspy_db_point_distance_doc                                                                        \
    }

/* dbwithin.c: neighbourhoods, methods of Database */
PyObject *gspy_db_within(PyObject *self, PyObject *args);
PyObject *gspy_db_nearest(PyObject *self, PyObject *args);
PyObject *gspy_db_radius_matrix(PyObject *self, PyObject *args, PyObject *kwargs);
extern const char gspy_db_within_doc[], gspy_db_nearest_doc[], gspy_db_radius_matrix_doc[];
#define GSPY_DB_WITHIN_METHODS                                                                                \
    {"within", (PyCFunction)gspy_db_within, METH_VARARGS, gspy_db_within_doc},                                \
        {"nearest", (PyCFunction)gspy_db_nearest, METH_VARARGS, gspy_db_nearest_doc},                         \
    {                                                                                                         \
        "radius_matrix", (PyCFunction)(void (*)(void))gspy_db_radius_matrix, METH_VARARGS | METH_KEYWORDS,    \
            gspy_db_radius_matrix_doc                                                                         \
    }

#endif /* GEOSEP_PY_H */
