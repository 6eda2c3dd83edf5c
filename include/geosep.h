/* geosep.h - the one public header of geosep: fast point-to-point geodesic
 * distance queries on triangle meshes (Gotsman & Hormann, SIGGRAPH Asia 2022).
 * One header (about 1,150 lines, most of them the contract of each function:
 * ownership, thread safety, errors) so that users include one file and
 * the installed API is one place to read.
 *
 * Conventions (stated once, they hold for every function below):
 *  - Every function that can fail returns an int status: GS_OK (0) on success,
 *    a negative GS_E* code on failure. gs_status_string() turns a code into text.
 *  - Functions that can fail take a `gs_error *err` last; it may be NULL. On
 *    failure it receives a human-readable message naming the file, line,
 *    element or argument that is wrong. On success it is left untouched.
 *  - Indices are uint32_t. GS_NONE (0xFFFFFFFF) means "no index".
 *  - Vertex ids are the user's: the order of the vertices in the input file or
 *    array is the order everywhere. Nothing is merged, dropped or reordered
 *    (STL, which has no shared vertices, is welded by exact position, in order
 *    of first appearance).
 *  - Ownership: an object returned through `T **out` is owned by the caller
 *    and released with its gs_T_free(), which accepts NULL. Arrays passed in
 *    are only read during the call and never retained unless said otherwise.
 *    Output arrays are caller-owned and sized as documented.
 *  - Threads: immutable objects (gs_mesh, gs_patch) may be shared freely
 *    between threads. Objects with scratch space (gs_solver) belong to one
 *    thread at a time. Nothing in the library keeps global mutable state.
 *  - The library never prints and never exits.
 */
#ifndef GEOSEP_H
#define GEOSEP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* GS_API marks the functions exported from the shared library; everything
 * else in it is hidden (built with -fvisibility=hidden). */
#if defined(_WIN32) && defined(GEOSEP_SHARED_BUILD)
#define GS_API __declspec(dllexport)
#elif defined(__GNUC__) && __GNUC__ >= 4
#define GS_API __attribute__((visibility("default")))
#else
#define GS_API
#endif

/* GEOSEP_VERSION_MAJOR, _MINOR, _PATCH and GEOSEP_VERSION_STRING: the
 * version of these headers (generated from the project's version). */
#include "geosep_version.h"

/* "MAJOR.MINOR.PATCH" of the linked library (may differ from
 * GEOSEP_VERSION_STRING if the program was built against other headers);
 * static storage. */
GS_API const char *gs_version_string(void);

#define GS_NONE UINT32_MAX

/* The largest thread count a call takes (gs_build_options.threads,
 * gs_db_field_threads, gs_db_radius_matrix); above it: GS_EARG. */
#define GS_MAX_THREADS 1024u

/* ---- status codes (pinned: values never change) ------------------------ */
enum {
    GS_OK = 0,
    GS_EIO = -1,          /* a file could not be opened, read or written   */
    GS_EPARSE = -2,       /* a file is malformed (syntax, counts, sizes)   */
    GS_EMESH = -3,        /* the mesh is invalid (topology or geometry)    */
    GS_ENOMEM = -4,       /* out of memory                                 */
    GS_EARG = -5,         /* an argument is invalid (NULL, out of range)   */
    GS_EFORMAT = -6,      /* unknown or unsupported file format            */
    GS_ELIMIT = -7,       /* a size exceeds what geosep supports           */
    GS_EINTERNAL = -8     /* a numerical or internal failure               */
};

/* Static text for a status code ("ok", "i/o error", ...). Never NULL. */
GS_API const char *gs_status_string(int status);

/* Detailed message for the last failure of a call given this struct. */
typedef struct gs_error {
    int status;
    char message[512];
} gs_error;

/* ======================================================================== */
/* Meshes                                                                   */
/* ======================================================================== */

/* An immutable, validated triangle mesh: positions, faces, connectivity. */
typedef struct gs_mesh gs_mesh;

typedef enum gs_mesh_format {
    GS_FORMAT_AUTO = 0, /* by file extension (.obj .off .ply .stl), then content */
    GS_FORMAT_OBJ,
    GS_FORMAT_OFF,
    GS_FORMAT_PLY,
    GS_FORMAT_STL
} gs_mesh_format;

/* Range of edge lengths geosep accepts (mesh units): squared and 4th-power
 * lengths in the validation and the solvers then stay finite and normal, and
 * distances scale with the mesh (a mesh scaled by s has its distances
 * scaled by s, to rounding). Rescale meshes outside this range. */
#define GS_MESH_MAX_EDGE 1e50
#define GS_MESH_MIN_EDGE 1e-50

/* Read and validate a mesh file. Readers are safe for untrusted input: a
 * malformed file gives GS_EPARSE/GS_EMESH with a message naming the file and
 * the line (text formats) or element (binary formats), never a crash.
 * Rejected: non-finite coordinates, face indices out of range or repeated in
 * a face, edges longer than GS_MESH_MAX_EDGE or shorter (but not zero) than
 * GS_MESH_MIN_EDGE, zero-area faces, non-manifold edges or vertices, inconsistently
 * oriented neighbouring faces, header counts the file cannot hold.
 * Accepted and reported by gs_mesh_get_report(): several components,
 * boundary loops, genus, vertices used by no face.
 * Polygons are fan-triangulated. *out receives a new mesh (caller frees). */
GS_API int gs_mesh_load(const char *path, gs_mesh_format format, gs_mesh **out,
                 gs_error *err);

/* Build a mesh from arrays: xyz holds 3*n_vertices doubles, tri holds
 * 3*n_faces vertex indices (counter-clockwise). Same validation as
 * gs_mesh_load: in particular n_faces = 0 is GS_EMESH, as a file without
 * faces (there is no surface to measure distances on; vertices used by no
 * face are accepted when there is a face). Arrays are copied. *out receives a new mesh (caller frees). */
GS_API int gs_mesh_create(const double *xyz, uint32_t n_vertices, const uint32_t *tri,
                   uint32_t n_faces, gs_mesh **out, gs_error *err);

GS_API void gs_mesh_free(gs_mesh *mesh);

GS_API uint32_t gs_mesh_num_vertices(const gs_mesh *mesh);
GS_API uint32_t gs_mesh_num_faces(const gs_mesh *mesh);
/* Borrowed pointers, valid while the mesh lives: 3*n_vertices doubles and
 * 3*n_faces indices. */
GS_API const double *gs_mesh_positions(const gs_mesh *mesh);
GS_API const uint32_t *gs_mesh_faces(const gs_mesh *mesh);

/* Health report: what is accepted but worth knowing. */
typedef struct gs_mesh_report {
    uint32_t n_vertices;          /* all vertices, used or not             */
    uint32_t n_faces;
    uint32_t n_edges;
    uint32_t n_unreferenced;      /* vertices used by no face              */
    uint32_t n_components;        /* face-connected components             */
    uint32_t n_boundary_edges;
    uint32_t n_boundary_loops;
    int32_t euler;                /* V - E + F over referenced vertices    */
    int32_t genus;                /* sum over components of genus          */
    double min_angle_deg;         /* smallest corner angle                 */
    double max_angle_deg;         /* largest corner angle                  */
    double min_edge, max_edge, mean_edge;
    double bbox_min[3], bbox_max[3];
} gs_mesh_report;

/* Fill *report (caller-owned). Never fails for a valid mesh. */
GS_API int gs_mesh_get_report(const gs_mesh *mesh, gs_mesh_report *report,
                       gs_error *err);

/* Generate a test or demo mesh from a spec string (all sizes in mesh units;
 * defaults in brackets). Flat meshes face +z, closed ones face outwards.
 *   "grid:NX,NY[,W,H]"        flat NX x NY vertex grid on [0,W]x[0,H] [1,1]; NX,NY >= 2
 *   "peaks:N[,W]"             N x N grid of MATLAB's peaks surface on [-3,3]^2; N >= 2;
 *                             with W, the same heights on a W x W grid centred on the
 *                             origin [6] ("peaks:50,49": the mesh surf(peaks(50)) draws)
 *   "plate:N"                 flat plate [0,1]^2 with three round (polygonal)
 *                             holes, about N vertices; N >= 50
 *   "cylinder:NU,NV[,R,H]"    open prism-cylinder, NU >= 3 around, NV >= 2 rings [1,1]
 *   "cone:NU,NV[,R,H]"        open frustum of height H, base radius R, top radius
 *                             R/4 (the apex, cut off, would be at 4H/3) [1,1]
 *   "cube:N[,S]"              closed cube surface of side S, N x N quads per face [1]
 *   "torus:NU,NV[,R,r]"       closed torus, radii R > r [1,0.4]; NU,NV >= 3
 *   "knot:NU,NV[,r]"          closed tube of radius r <= 0.5 [0.4] around the
 *                             trefoil ((2 + cos 3t) cos 2t, (2 + cos 3t) sin 2t,
 *                             sin 3t): NU >= 8 rings of NV >= 3 vertices
 *   "sphere:N"                closed unit icosphere, N <= 9 subdivisions
 *   "two:N"                   two disjoint flat N x N grids (two components)
 *   "graded:N[,P]"            flat N x N grid on the unit square graded towards
 *                             the origin: vertex (i,j) at ((i/(N-1))^P,
 *                             (j/(N-1))^P), 1 <= P <= 8 [3], N <= 4096
 * Integers are plain digits; sizes plain decimals ("2", "0.5", "1e-3") from
 * 1e-30 to 1e30, no blanks, signs, hex, inf or nan. Bad specs give GS_EARG
 * naming the spec and the bad argument, sizes over 2^26 vertices GS_ELIMIT.
 * *out receives a new mesh (caller frees). */
GS_API int gs_mesh_generate(const char *spec, gs_mesh **out, gs_error *err);

/* 1-to-4 midpoint subdivision: every face is split into four by its edge
 * midpoints (flat: the surface, and so its geodesic distances, are
 * unchanged). Vertex ids 0..n_vertices-1 are kept; each edge's midpoint is
 * appended in order of first appearance. *out receives a new mesh (caller
 * frees). GS_ELIMIT if the result would exceed 2^31 vertices or faces. */
GS_API int gs_mesh_subdivide(const gs_mesh *mesh, gs_mesh **out, gs_error *err);

/* Choose k distinct vertices used by faces, deterministically: candidates
 * are the referenced vertices in increasing id order (m of them); a
 * splitmix64 generator with state = seed draws v = candidates[next() % m],
 * skipping repeats, until k are chosen (the procedure of the shared
 * ground-truth files). out receives k ids in draw order. GS_EARG if k > m. */
GS_API int gs_mesh_random_vertices(const gs_mesh *mesh, uint32_t k, uint64_t seed, uint32_t *out,
                            gs_error *err);

/* Write a mesh as OBJ (vertex order kept; "%.17g" so it reads back bit-exact).
 * The file is written to a temporary name and renamed: never left partial. */
GS_API int gs_mesh_save_obj(const gs_mesh *mesh, const char *path, gs_error *err);

/* ---- Repair: flawed meshes as people download them (doc/repair.md) ------ */

/* Kinds of change gs_mesh_repair makes (pinned values, new kinds appended). */
typedef enum gs_repair_kind {
    GS_REPAIR_REPEATED_CORNER = 0, /* face naming a vertex twice: dropped     */
    GS_REPAIR_DUPLICATE_FACE,      /* same three vertices as an earlier face  */
                                   /*   (either orientation): dropped         */
    GS_REPAIR_ZERO_AREA_COLLAPSED, /* zero-area face with corners at one      */
                                   /*   position: they are welded, it is gone */
    GS_REPAIR_ZERO_AREA_SPLIT,     /* zero-area (collinear) face: the face    */
                                   /*   across its longest edge is split at   */
                                   /*   its middle corner, it is gone         */
    GS_REPAIR_ZERO_AREA_NEEDLE,    /* zero-area face with a tiny edge (below  */
                                   /*   1e-6 of its longest) that no split    */
                                   /*   removes: that edge is collapsed (its  */
                                   /*   ends welded, the faces of the second  */
                                   /*   moving by the edge's length)          */
    GS_REPAIR_ZERO_AREA_BOUNDARY,  /* zero-area face whose longest edge is on */
                                   /*   the boundary: dropped (same surface)  */
    GS_REPAIR_ZERO_AREA_DROPPED,   /* zero-area face dropped otherwise: a     */
                                   /*   zero-width gap where it was           */
    GS_REPAIR_SEAM_EDGE,           /* boundary edge glued to the one boundary */
                                   /*   edge at the same positions (seam)     */
    GS_REPAIR_SEAM_AMBIGUOUS,      /* boundary edges left open: more than two */
                                   /*   at the same positions                 */
    GS_REPAIR_WELDED_VERTEX,       /* vertex merged into a coincident one:    */
                                   /*   unreferenced, mapped to it            */
    GS_REPAIR_NONMANIFOLD_EDGE,    /* edge of more than two faces: the best   */
                                   /*   pair kept, the others detached        */
    GS_REPAIR_FLIPPED_FACE,        /* face reversed to agree with its         */
                                   /*   component's orientation               */
    GS_REPAIR_ORIENTATION_CUT,     /* edge cut open: the component is not     */
                                   /*   orientable (Moebius strip)            */
    GS_REPAIR_SHEET_CUT,           /* edge cut open so that sheets meeting    */
                                   /*   there get separate vertices           */
    GS_REPAIR_SPLIT_VERTEX,        /* vertex whose faces form several fans    */
                                   /*   (non-manifold, or where a cut or a    */
                                   /*   detached face ends): one vertex per   */
                                   /*   fan, the new copies appended          */
    GS_REPAIR_NUM_KINDS
} gs_repair_kind;

#define GS_REPAIR_EXAMPLES 5

/* Where one change was made, in the input's terms. */
typedef struct gs_repair_example {
    uint32_t face;      /* input triangle (polygons fan-triangulated, file  */
                        /*   order), GS_NONE if none                         */
    uint32_t line;      /* its line (text files) or element (binary files); */
                        /*   GS_NONE for arrays                              */
    uint32_t vertex[3]; /* input vertex ids concerned, GS_NONE if unused     */
} gs_repair_example;

/* What gs_mesh_repair did, and where every input vertex went. */
typedef struct gs_repair {
    uint32_t n_input_vertices, n_input_faces; /* faces: triangles           */
    uint32_t n_vertices, n_faces;             /* of the repaired mesh       */
    uint64_t count[GS_REPAIR_NUM_KINDS];      /* changes of each kind       */
    uint32_t n_examples[GS_REPAIR_NUM_KINDS]; /* <= GS_REPAIR_EXAMPLES      */
    gs_repair_example example[GS_REPAIR_NUM_KINDS][GS_REPAIR_EXAMPLES];
    char file[256];       /* input file ("" for arrays), cut if longer      */
    char unit[16];        /* what example lines count: "line", "face", ...  */
    /* Vertex ids: input vertex v keeps id v and its position; new vertices */
    /* (copies of split vertices) are appended. vertex_map[v] is the        */
    /* repaired vertex v became: v itself, or for a welded vertex the one   */
    /* it was welded into. Every repaired vertex that carries some of v's   */
    /* corners is listed in alias[alias_start[v] .. alias_start[v+1]),      */
    /* vertex_map[v] first, then increasing (a split vertex: itself and its */
    /* copies; a vertex no face uses: itself, or the vertex it was welded   */
    /* into before its faces were removed).                                 */
    uint32_t *vertex_map;     /* n_input_vertices                           */
    uint32_t *alias_start;    /* n_input_vertices + 1                       */
    uint32_t *alias;          /* alias_start[n_input_vertices]              */
    uint32_t *vertex_origin;  /* n_vertices: the input vertex at whose      */
                              /*   position each repaired vertex is (v for  */
                              /*   v < n_input_vertices)                    */
    uint32_t *face_origin;    /* n_faces: input triangle each face is (or   */
                              /*   was split from)                          */
    uint8_t *face_change;     /* n_faces: GS_REPAIR_FACE_*: how its corners */
                              /*   relate to face_origin's                  */
} gs_repair;

enum {
    GS_REPAIR_FACE_SAME = 0,    /* the input triangle's corners, in order     */
                                /*   (each possibly replaced by its copy or   */
                                /*   by the vertex it was welded into)        */
    GS_REPAIR_FACE_FLIPPED = 1, /* the same, reversed: (c0, c2, c1)           */
    GS_REPAIR_FACE_SPLIT = 2    /* one of the two pieces of the input         */
                                /*   triangle, split at a zero-area face's    */
                                /*   middle corner                            */
};

/* Repair a triangle soup into a valid mesh, knowingly: faces repeating a
 * vertex and duplicate faces are dropped; zero-area faces are removed
 * without opening holes where possible (coincident corners welded, or the
 * neighbour across the longest edge split at the middle corner); boundary
 * edges at exactly the same positions as exactly one other boundary edge
 * are glued (unwelded seams) and their vertices welded; of an edge's faces
 * beyond two, the best-aligned pair is kept and the others detached; each
 * component is oriented consistently (the majority of its faces keep
 * theirs; a non-orientable one is cut open where needed); each vertex
 * whose faces form several fans becomes one vertex per fan. Positions never
 * move: the repaired surface is the input's, but for the faces dropped (and
 * the needles collapsed: GS_REPAIR_ZERO_AREA_NEEDLE).
 * Input: xyz (3 * n_vertices, finite) and tri (3 * n_faces, indices <
 * n_vertices); GS_EMESH if a coordinate is not finite, an index out of
 * range, an edge longer than GS_MESH_MAX_EDGE, or nothing is left.
 * *out receives the repaired mesh (valid for gs_mesh_create; caller frees);
 * *info, if info is not NULL, what was done (caller frees with
 * gs_repair_free). A mesh that needs nothing comes out identical, with
 * every count 0. Reentrant; the arrays are only read during the call. */
GS_API int gs_mesh_repair(const double *xyz, uint32_t n_vertices, const uint32_t *tri,
                          uint32_t n_faces, gs_mesh **out, gs_repair **info, gs_error *err);

/* Same from a mesh file (read as gs_mesh_load reads it, but without its
 * topological checks; the readers' own checks stay: syntax, counts,
 * indices in range, finite coordinates). Examples name the file's lines
 * (text) or elements (binary). */
GS_API int gs_mesh_repair_file(const char *path, gs_mesh_format format, gs_mesh **out,
                               gs_repair **info, gs_error *err);

GS_API void gs_repair_free(gs_repair *info);

/* Static text describing a kind ("non-manifold vertices split ..."), or
 * NULL if kind is out of range. */
GS_API const char *gs_repair_kind_name(int kind);

/* The report as text (doc/repair.md shows it): a first line with the
 * counts before and after, then one line per kind of change made with its
 * count and examples. Written into buf (size bytes, always terminated if
 * size > 0); returns the length of the whole text, as snprintf does. */
GS_API size_t gs_repair_format(const gs_repair *info, char *buf, size_t size);

/* ======================================================================== */
/* Patches: a subset of a mesh's faces with its own vertex numbering         */
/* ======================================================================== */

/* A patch is the surface made of some faces of a mesh: distances on a patch
 * are measured along paths that stay inside it (the paper's d_P, eq. 1).
 * Local vertices are the vertices of the chosen faces in increasing order of
 * their mesh id; local faces are the chosen faces in the order given.
 * Special case: faces == NULL means the whole mesh, and then local ids equal
 * mesh ids for vertices and faces (unreferenced vertices included).
 * A patch may have non-manifold ("bow-tie") vertices where two fans of its
 * faces touch; paths may pass through them. The patch keeps a pointer to
 * the mesh, which must outlive it. *out receives a new patch (caller frees). */
typedef struct gs_patch gs_patch;

GS_API int gs_patch_create(const gs_mesh *mesh, const uint32_t *faces,
                    uint32_t n_faces, gs_patch **out, gs_error *err);
GS_API void gs_patch_free(gs_patch *patch);

GS_API uint32_t gs_patch_num_vertices(const gs_patch *patch);
GS_API uint32_t gs_patch_num_faces(const gs_patch *patch);
/* Mesh id of a local vertex / face (GS_NONE if out of range). */
GS_API uint32_t gs_patch_vertex_to_mesh(const gs_patch *patch, uint32_t local);
GS_API uint32_t gs_patch_face_to_mesh(const gs_patch *patch, uint32_t local);
/* Local id of a mesh vertex, GS_NONE if the patch does not contain it. */
GS_API uint32_t gs_patch_vertex_from_mesh(const gs_patch *patch, uint32_t mesh_vertex);

/* ======================================================================== */
/* Geodesic distance fields on a patch                                      */
/* ======================================================================== */

typedef enum gs_method {
    GS_METHOD_EXACT = 0, /* exact polyhedral distances, window propagation   */
    GS_METHOD_GRAPH = 1, /* Dijkstra on the edge graph (upper bound, baseline) */
    GS_METHOD_FMM = 2,   /* fast marching (Kimmel & Sethian 1998)            */
    GS_METHOD_HEAT = 3,  /* the heat method (Crane et al. 2013), CHOLMOD      */
    GS_METHOD_DGG = 4    /* discrete geodesic graph (Wang et al. 2017): exact */
                         /*   local runs build a graph once per solver, pruned */
                         /*   to dgg_eps; each field is a short exact run from */
                         /*   the source, then a Dijkstra on the graph; a     */
                         /*   build makes one graph of the whole mesh          */
                         /*   (doc/approximate-fields.md)                      */
} gs_method;

/* Text name ("exact", "graph", "fmm", "heat", "dgg") of a method, or NULL. */
GS_API const char *gs_method_name(gs_method method);
/* Method from its name; GS_EARG if unknown. */
GS_API int gs_method_from_name(const char *name, gs_method *method, gs_error *err);

/* A source point. face == GS_NONE: the vertex `vertex` (local id).
 * Otherwise the point sum_i bary[i] * corner_i of local face `face`
 * (bary >= 0, summing to 1 within 1e-9; it is renormalised). */
typedef struct gs_source {
    uint32_t vertex;
    uint32_t face;
    double bary[3];
} gs_source;

/* Convenience constructors. */
GS_API gs_source gs_source_vertex(uint32_t local_vertex);
GS_API gs_source gs_source_point(uint32_t local_face, double b0, double b1, double b2);

/* A reusable distance solver bound to one patch. It allocates its working
 * memory once (growing it when needed) and can solve any number of sources;
 * no state of one solve leaks into the next. One thread at a time. The patch
 * must outlive the solver. *out receives a new solver (caller frees). */
typedef struct gs_solver gs_solver;

GS_API int gs_solver_create(const gs_patch *patch, gs_method method, gs_solver **out,
                     gs_error *err);

/* Parameters of the approximate methods (ignored by the others). */
typedef struct gs_solver_options {
    double heat_time;       /* heat: t = heat_time * h^2, h the patch's mean   */
                            /*   edge length weighted by triangle area         */
                            /*   [1: Crane et al.'s t = h^2]                    */
    double fmm_exact_start; /* fmm: vertices within this many mean edge lengths */
                            /*   of the sources get exact distances, and the   */
                            /*   march starts from them; 0: the plain march    */
                            /*   from the source vertices [4]                   */
    uint32_t heat_refine;   /* heat: solve on the patch subdivided 1-to-4 this */
                            /*   many times (midpoint subdivision: the same    */
                            /*   surface), read back at its vertices; 0..3 [0] */
                            /*   (h above is then the subdivided patch's; the  */
                            /*   solver's memory and time grow more than 4^N), */
                            /*   or GS_HEAT_REFINE_AUTO (gs_heat_refine_auto   */
                            /*   of the patch's vertex count; gs_db_build: of  */
                            /*   the whole mesh's, and its default)            */
    double dgg_eps;         /* dgg: target relative error: sets the radius of  */
                            /*   the local exact runs (gs_dgg_radius), and the */
                            /*   graph is pruned to within 1 + eps of the      */
                            /*   unpruned one [1e-3], in [GS_DGG_EPS_MIN,      */
                            /*   GS_DGG_EPS_MAX]                                */
} gs_solver_options;

/* Range of gs_solver_options.dgg_eps. */
#define GS_DGG_EPS_MIN 1e-5
#define GS_DGG_EPS_MAX 0.5

/* The radius R, in mean edge lengths of the patch, of the local exact runs
 * that build a dgg graph for target error eps: every pair of vertices
 * within R (inside the patch) is joined by a graph path of at most
 * (1 + eps) times its geodesic length, and a solver's fields are exact
 * within 6 R of each source. Pure function, thread-safe. */
GS_API double gs_dgg_radius(double eps);

/* Range of gs_solver_options.heat_time. Values below the default 1 only
 * add error (the heat barely leaves the source's neighbours); far above it
 * the field stops changing (the t -> infinity limit) and then rounding
 * spoils it. doc/approximate-fields.md has the measured accuracy. */
#define GS_HEAT_TIME_MIN 1e-8
#define GS_HEAT_TIME_MAX 1e8

/* Largest gs_solver_options.heat_refine (3: 64x the triangles). */
#define GS_HEAT_REFINE_MAX 3

/* gs_solver_options.heat_refine: chosen from the vertex count (below). */
#define GS_HEAT_REFINE_AUTO UINT32_MAX

/* The heat method's resolution for a mesh of nv vertices: the fewest
 * 1-to-4 subdivisions (at most 2) that give at least
 * GS_HEAT_REFINE_AUTO_VERTICES vertices. Heat fields of coarse meshes are
 * not additive enough for a database to reproduce them to the paper's 0.5%;
 * from about 20,000 vertices they are (doc/approximate-fields.md). Pure
 * function, thread-safe. */
#define GS_HEAT_REFINE_AUTO_VERTICES 32000u
GS_API uint32_t gs_heat_refine_auto(uint32_t nv);

GS_API void gs_solver_options_default(gs_solver_options *opt);

/* gs_solver_create with options (NULL: defaults). GS_EARG if an option is
 * out of range (heat_time in [GS_HEAT_TIME_MIN, GS_HEAT_TIME_MAX], fmm_exact_start finite and
 * >= 0, heat_refine at most GS_HEAT_REFINE_MAX or GS_HEAT_REFINE_AUTO, dgg_eps in
 * [GS_DGG_EPS_MIN, GS_DGG_EPS_MAX]). GS_METHOD_DGG builds its graph here (the
 * expensive part: OpenMP threads, the library's default count; the graph
 * does not depend on the thread count). *out receives a new solver (caller frees); opt is copied. */
GS_API int gs_solver_create_ex(const gs_patch *patch, gs_method method, const gs_solver_options *opt,
                        gs_solver **out, gs_error *err);
GS_API void gs_solver_free(gs_solver *solver);

/* Distance field from a set of sources (the pointwise minimum of their
 * fields). dist receives gs_patch_num_vertices() doubles, in local vertex
 * order: +INFINITY where unreachable inside the patch (another component,
 * an unreferenced vertex). max_distance > 0 stops the propagation early:
 * every vertex with distance <= max_distance is exact, others may be
 * +INFINITY or any value > max_distance. Pass 0 or INFINITY for no bound. */
GS_API int gs_solver_solve(gs_solver *solver, const gs_source *sources,
                    uint32_t n_sources, double max_distance, double *dist,
                    gs_error *err);

/* Statistics of the last solve (for benchmarks); any pointer may be NULL.
 * Same thread rules as the solver. */
GS_API void gs_solver_last_stats(const gs_solver *solver, uint64_t *windows_created,
                          uint64_t *windows_propagated, double *seconds);

/* One-shot convenience: create a solver, solve, free it. */
GS_API int gs_distance_field(const gs_patch *patch, gs_method method,
                      const gs_source *sources, uint32_t n_sources,
                      double max_distance, double *dist, gs_error *err);

/* ---- exact geodesic paths (doc/paths.md) ---------------------------------
 * A path is a polyline of surface points from a source to a target whose
 * length is the exact polyhedral distance (to rounding, ~1e-12 relative):
 * it is straight inside every face and bends only at saddle, boundary or
 * non-manifold vertices. Point i is given as xyz and as local face
 * face[i] with barycentric weights bary[3i..3i+2] (>= 0, summing to 1);
 * face[i] holds the segment from point i to point i+1 (the last point: the
 * segment arriving at it), so consecutive points share a face. Points are
 * the source, the crossings with the edges, the vertices passed through and
 * the target, without repeats; source == target gives one point. A target
 * the source cannot reach (another component) gives an empty path (0
 * points, length +INFINITY) and GS_OK. */
typedef struct gs_path gs_path;

/* Exact shortest path on the solver's patch from `source` to `target`
 * (each a vertex or a surface point, local ids, as gs_solver_solve's
 * sources): solves the exact field from source (one gs_solver_solve:
 * the solver's last field is then source's), then backtracks. GS_EARG if
 * the solver's method is not GS_METHOD_EXACT or a point is invalid
 * (message names which). *out receives a new path (gs_path_free); on error
 * *out is NULL. Same thread rules as the solver. */
GS_API int gs_solver_path(gs_solver *solver, const gs_source *source, const gs_source *target,
                          gs_path **out, gs_error *err);

/* Path to the vertex target->vertex (a surface point that is a vertex is
 * accepted) from the sources of the solver's last gs_solver_solve, which
 * must have used the exact method: solve once, trace to many targets
 * (each trace costs about the path's number of faces, not a solve). With
 * several sources it leads to the nearest. GS_EARG if the method is not
 * exact, no exact solve succeeded yet, the target is a surface point
 * inside a face (use gs_solver_path) or lies beyond the last solve's
 * max_distance. *out: new path (gs_path_free), NULL on error. Same thread
 * rules as the solver. */
GS_API int gs_solver_trace(gs_solver *solver, const gs_source *target, gs_path **out, gs_error *err);

/* Accessors (NULL/0-safe; arrays belong to the path, valid until
 * gs_path_free; a path is immutable: any number of threads may read it).
 * xyz: 3n doubles, faces: n local face ids, bary: 3n doubles (NULL when
 * n == 0). length: the sum of the segments' lengths (+INFINITY when empty). */
GS_API uint32_t gs_path_num_points(const gs_path *path);
GS_API double gs_path_length(const gs_path *path);
GS_API const double *gs_path_xyz(const gs_path *path);
GS_API const uint32_t *gs_path_faces(const gs_path *path);
GS_API const double *gs_path_bary(const gs_path *path);
GS_API void gs_path_free(gs_path *path);

/* ======================================================================== */
/* Query databases (the paper's SEP method)                                 */
/* ======================================================================== */

/* An opened, validated database: immutable, safe to query from any number
 * of threads at once. */
typedef struct gs_db gs_db;

/* Progress callback: stage name ("tree", "graph" (GS_METHOD_DGG only),
 * "fields", "leaves", "near", "write") and the fraction done in [0,1].
 * Called from the building thread only. */
typedef void (*gs_progress_fn)(void *user, const char *stage, double fraction);

typedef struct gs_build_options {
    gs_method method;        /* distance fields to compress [GS_METHOD_EXACT]  */
    uint32_t vmax;           /* leaf patch size [30]                           */
    uint32_t mmax;           /* maximum polynomial degree [20]                 */
    double tol;              /* fit mean relative error target at the root     */
                             /*   [0.003], 1.5x looser per tree level, at most */
                             /*   max(tol, 2%)                                 */
    uint32_t threads;        /* 0: all cores, at most GS_MAX_THREADS [0]       */
    int vertex_sources;      /* 1: fields from the corners of the triangles    */
                             /*   holding samples + barycentric interpolation  */
                             /*   (the paper); 0: from the samples; -1: by the */
                             /*   method: samples for exact fields, vertices   */
                             /*   for approximate ones (measured best) [-1]    */
    int sampled;             /* 1: SEPsam (sampled values, piecewise linear)   */
    int leaf_exact;          /* 1: store exact distances inside leaves; 0:    */
                             /*   answer same-leaf pairs with the Euclidean    */
                             /*   distance, which underestimates on curved     */
                             /*   leaves (bunny-5k: 56%) [1]                   */
    double near_radius;      /* near pairs, in mean edge lengths: every pair  */
                             /*   of vertices in different leaves nearer than  */
                             /*   this (2 to 10 times this from a vertex with  */
                             /*   an uncertified fit, see gs_build_stats) whose*/
                             /*   answer through the separators is off by more */
                             /*   than 2% gets its exact distance stored       */
                             /*   (section 'near_pairs'); 0: none [5]          */
    uint32_t seed;           /* partitioning seed [1]                          */
    double sample_spacing;   /* separator sample spacing / mean edge length    */
                             /*   [0.5]                                        */
    gs_solver_options solver;/* parameters of fmm and heat [defaults, but     */
                             /*   heat_refine GS_HEAT_REFINE_AUTO: from the    */
                             /*   mesh's vertex count]                         */
    uint32_t max_samples;    /* samples per curve at most: longer curves are   */
                             /*   thinned to this many, evenly by arc length;  */
                             /*   bounds the fields per separator; 0: no cap   */
                             /*   [192]; then split into pieces of at most 48  */
                             /*   sample intervals, each a function per vertex */
    uint32_t field_memory_mib; /* memory for one block of distance fields, in  */
                             /*   MiB: a node's fields are computed block by   */
                             /*   block and folded into its samples (float),   */
                             /*   never all at once; two blocks live at a time */
                             /*   (at least 16 fields each). Peak memory is    */
                             /*   about 2 x this + n_owned x n_samples x 4     */
                             /*   bytes for the largest node + the factors     */
                             /*   (heat) + the database [384]                  */
    gs_progress_fn progress; /* may be NULL                                    */
    void *progress_user;
    const gs_repair *repair; /* the repair that made the mesh (gs_mesh_repair's */
                             /*   info), or NULL [NULL]: its input-id aliases */
                             /*   are stored, and the database then answers   */
                             /*   by input id too (gs_db_input_distance); its */
                             /*   n_vertices must be the mesh's (GS_EARG).    */
                             /*   Only read during gs_db_build                */
} gs_build_options;

GS_API void gs_build_options_default(gs_build_options *opt);

typedef struct gs_build_stats {
    double seconds_tree, seconds_fields, seconds_fits, seconds_total;
    uint64_t n_fields;       /* distance fields solved                         */
    uint64_t n_functions;    /* separator distance functions fitted            */
    double mean_degree;
    uint64_t n_over_tol;     /* fits that missed tol even at degree mmax       */
    uint64_t n_uncertified;  /* fits whose largest error at the samples, or    */
                             /*   outside the band the samples allow between   */
                             /*   them, is above 2% at every degree (the one   */
                             /*   with the smallest is kept; doc/accuracy.md)  */
    double max_fit_error;    /* the largest such error over all fits           */
    double mean_fit_error;   /* mean relative error of the fits on the samples */
    uint64_t n_near_pairs;   /* near pairs stored (near_radius)                */
    double seconds_near;     /* their exact fields and checks (also counted    */
                             /*   in seconds_fields)                           */
} gs_build_stats;

/* Build a database in memory. stats may be NULL. *out receives a new
 * database (caller frees with gs_db_free); save it with gs_db_save. A mesh
 * whose bounding box's centre lies more than 1000 of its diagonals from the
 * origin is built from a copy moved to the origin (far out, positions lose
 * the digits that tell nearby separator points apart); the database keeps
 * the mesh's own positions. */
GS_API int gs_db_build(const gs_mesh *mesh, const gs_build_options *opt, gs_db **out,
                gs_build_stats *stats, gs_error *err);

/* Write atomically (temporary file, then rename). */
GS_API int gs_db_save(const gs_db *db, const char *path, gs_error *err);

/* Open a database file (memory-mapped, used in place: nothing is built in
 * memory, so opening takes about the same time whatever the size). The
 * structure is validated (header and its checksum, section table, counts,
 * tree, record index: what makes every read of a query land inside the
 * file): a truncated file or a corrupt structure gives GS_EPARSE naming the
 * section and field, never a crash; a file of another format version gives
 * GS_EFORMAT naming its version. The sections' checksums and the stored
 * values are not read: a corrupt value in an unchecked file may give a
 * wrong distance (never a crash, never a read outside the file); open with
 * GS_DB_OPEN_VERIFY or call gs_db_verify to check them. *out: new database,
 * freed with gs_db_free. Thread-safe (distinct out). */
GS_API int gs_db_open(const char *path, gs_db **out, gs_error *err);

/* Flags of gs_db_open_ex. */
#define GS_DB_OPEN_VERIFY 1u /* also gs_db_verify's full check (reads the whole file) */

/* gs_db_open with flags (0 or GS_DB_OPEN_VERIFY); GS_EARG for unknown bits. */
GS_API int gs_db_open_ex(const char *path, unsigned flags, gs_db **out, gs_error *err);

/* The full check of an open database: every section's checksum, then every
 * record (each function's block well formed, coefficients finite and in
 * range, its minimum not above its values), positions and leaf tables.
 * GS_OK, or GS_EPARSE naming the section, vertex and field. Reads the whole
 * file (about 10 ms per 100 MB for the checksums, more for the records).
 * Thread-safe; db is not modified. */
GS_API int gs_db_verify(const gs_db *db, gs_error *err);

/* Same as gs_db_open_ex(.., GS_DB_OPEN_VERIFY, ..) from a caller's buffer
 * (copied: the database owns its copy). */
GS_API int gs_db_open_memory(const void *data, size_t size, gs_db **out, gs_error *err);

/* Borrowed: the database's file image, the bytes gs_db_save writes (for a
 * database held elsewhere than in a file: a blob store, a pickle; open it
 * again with gs_db_open_memory). *size (may be NULL) receives its length.
 * Valid while db lives; NULL and 0 for a NULL db. Thread-safe. */
GS_API const void *gs_db_file_bytes(const gs_db *db, size_t *size);

GS_API void gs_db_free(gs_db *db);

typedef struct gs_db_info {
    uint32_t format_version;
    uint32_t n_vertices, n_nodes, n_leaves, n_curves;
    double avg_depth;        /* average leaf depth over vertices (paper: h) */
    uint32_t max_depth;
    double cost;             /* numbers stored per vertex, as Table 1 counts */
    double bytes_per_vertex; /* whole file / n_vertices                      */
    uint64_t file_bytes;
    uint64_t n_functions;    /* separator distance functions stored          */
    uint64_t records_bytes;  /* of which the functions' records (minima,     */
                             /*   blocks)                                    */
    gs_method method;
    uint32_t vmax, mmax;
    double tol;
    int vertex_sources, sampled, leaf_exact;
    double sample_spacing;     /* build parameters (gs_build_options)          */
    uint32_t seed;
    uint32_t max_samples;      /* cap on samples per curve (0: none)          */
    gs_solver_options solver;  /* the field method's parameters (heat_refine  */
                               /*   as used: never GS_HEAT_REFINE_AUTO; 0     */
                               /*   for methods other than heat)              */
    double near_radius;        /* near pairs: the radius (mesh units; 0: no   */
                               /*   section) and how many are stored          */
    uint64_t n_near_pairs;
    uint64_t near_bytes;       /* the section's size                          */
} gs_db_info;

GS_API int gs_db_get_info(const gs_db *db, gs_db_info *info, gs_error *err);

/* Approximate geodesic distance between vertices x and y: +INFINITY if they
 * are not connected, NaN if an id is out of range. Thread-safe, allocation
 * free. */
GS_API double gs_db_distance(const gs_db *db, uint32_t x, uint32_t y);

/* n pairs (pairs[2i], pairs[2i+1]) -> out[i]. GS_EARG names the first
 * out-of-range id. */
GS_API int gs_db_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out,
                    gs_error *err);

/* Distances from x to every vertex (out: n_vertices doubles), each equal
 * bit for bit to gs_db_distance(db, x, y). x's separator functions are
 * decoded and tabulated once and shared by all targets. GS_EARG for a NULL
 * argument or x out of range; GS_ENOMEM if the work array (about 1 KB per
 * separator function of x, freed before returning) cannot be allocated.
 * Thread-safe (the database is only read). */
GS_API int gs_db_field(const gs_db *db, uint32_t x, double *out, gs_error *err);

/* gs_db_field on `threads` OpenMP threads (0: the library's default count;
 * 1: gs_db_field): the targets in chunks of consecutive vertex ids (at
 * most 4096), each thread with its own copy of x's decoded functions. The same answers, bit for bit,
 * for any number of threads. out: n_vertices doubles (the caller's); the
 * work arrays are freed before returning. GS_EARG for a NULL argument, x
 * out of range or threads > GS_MAX_THREADS; GS_ENOMEM. Thread-safe (the
 * database is only read). */
GS_API int gs_db_field_threads(const gs_db *db, uint32_t x, double *out, uint32_t threads, gs_error *err);

/* ---- Neighbourhoods (src/query/within.c, radius.c) --------------------- */

/* Vertices and their database distances from one vertex, by increasing
 * distance (ties: lower id first); dist[i] == gs_db_distance(db, x, ids[i])
 * bit for bit. Owned by the caller: gs_neighbors_free (accepts NULL). */
typedef struct gs_neighbors {
    size_t n;        /* entries                                             */
    uint32_t *ids;   /* n vertex ids                                        */
    double *dist;    /* n distances                                         */
} gs_neighbors;

GS_API void gs_neighbors_free(gs_neighbors *nb);

/* Every vertex y with gs_db_distance(db, x, y) <= r (x itself included,
 * at 0; vertices used by no face never, unless y == x), by increasing
 * distance: exactly the vertices of the thresholded gs_db_field. Whole
 * subtrees of the bisection tree are skipped with lower bounds taken from
 * the file (the stored minima of the separator functions, and bounding
 * spheres), so the cost grows with the answer, not with n_vertices. The
 * first call on a database computes these bounds for every tree node (one
 * pass over every vertex's stored minima, about the time of one
 * gs_db_field; 4 bytes per function of each node's root path, plus 52
 * bytes per node and 4 per vertex: 0.9 MB for 60,000 vertices) and keeps
 * them until gs_db_free.
 * r: a number >= 0 (+INFINITY: every vertex at a finite distance, i.e.
 * connected to x; unreachable vertices are never listed). *out: new
 * result (gs_neighbors_free), NULL on error. GS_EARG for a NULL argument,
 * x out of range or a bad r; GS_ENOMEM. Thread-safe (threads racing for
 * the first call each compute the bounds, one is kept). */
GS_API int gs_db_within(const gs_db *db, uint32_t x, double r, gs_neighbors **out, gs_error *err);

/* The k nearest to x among candidates[0..n_candidates) (database
 * distances; a repeated candidate counts once): min(k, distinct
 * candidates) entries by increasing distance, ties to the lower id;
 * unreachable candidates come last at +INFINITY (a corrupt, unverified
 * file's NaN answers count as +INFINITY). Candidates are answered in
 * increasing order of the lower bounds gs_db_within uses, until the bound
 * exceeds the k-th distance found. *out: new result (gs_neighbors_free),
 * NULL on error. GS_EARG for a NULL argument or an id out of range (the
 * message names the candidate); GS_ENOMEM. Thread-safe. */
GS_API int gs_db_nearest(const gs_db *db, uint32_t x, const uint32_t *candidates, size_t n_candidates, size_t k,
                         gs_neighbors **out, gs_error *err);

/* A sparse matrix in compressed sparse rows (scipy.sparse.csr_matrix's
 * layout): row i's entries are indices/data[indptr[i] .. indptr[i+1]),
 * columns increasing within a row. Owned by the caller: gs_csr_free
 * (accepts NULL). */
typedef struct gs_csr {
    uint32_t n_rows, n_cols;
    uint64_t nnz;       /* entries: indptr[n_rows]                          */
    uint64_t *indptr;   /* n_rows + 1                                       */
    uint32_t *indices;  /* nnz column ids                                   */
    double *data;       /* nnz values                                       */
} gs_csr;

GS_API void gs_csr_free(gs_csr *m);

/* The radius matrix of many sources: row i holds gs_db_within(db,
 * sources[i], r) by increasing vertex id (n_rows = n_sources, n_cols =
 * n_vertices). Rows are computed on `threads` OpenMP threads (0: the
 * library's default count); the result does not depend on the count.
 * *out: new matrix (gs_csr_free), NULL on error. GS_EARG for a NULL
 * argument, a bad r, a source out of range (named) or threads >
 * GS_MAX_THREADS; GS_ENOMEM.
 * Thread-safe (the database is only read). */
GS_API int gs_db_radius_matrix(const gs_db *db, const uint32_t *sources, uint32_t n_sources, double r,
                               uint32_t threads, gs_csr **out, gs_error *err);

/* Borrowed: the vertex positions the database was built from (3 *
 * n_vertices doubles, x y z per vertex), valid while db lives; NULL if db
 * is NULL. (To check that a mesh is the database's.) */
GS_API const double *gs_db_positions(const gs_db *db);

/* The bisection tree (read-only; for drawing the separators). Node 0 is
 * the root; a node's parent has a smaller id; the root has depth 0 and
 * parent GS_NONE; gs_db_get_info gives n_nodes. */
/* The leaf node of vertex v: GS_NONE if v is used by no face, v is out of
 * range or db is NULL. Thread-safe, allocation free. */
GS_API uint32_t gs_db_vertex_leaf(const gs_db *db, uint32_t v);
/* Parent (GS_NONE for the root) and depth of a node; either pointer may be
 * NULL. GS_EARG if db is NULL or node >= n_nodes. Thread-safe. */
GS_API int gs_db_tree_node(const gs_db *db, uint32_t node, uint32_t *parent, uint32_t *depth, gs_error *err);

/* ---- Distances between surface points (src/query/points.c) ------------- */

/* A point of the surface: p = sum_i weight[i] * position(corner[i]), with
 * corner[] the three vertices of one face of the mesh (the database stores
 * positions, not faces, so the caller names the corners; gs_surface_point_
 * from_face does it from a mesh) and weight[] its barycentric coordinates.
 * Valid when: every corner < n_vertices, every weight finite and >=
 * GS_POINT_WEIGHT_MIN, |sum of the weights - 1| <= GS_POINT_WEIGHT_SUM_TOL
 * (the exact sum of the three doubles, not a rounded one),
 * and, if two or more corners have nonzero weight, each of those is used by
 * some face (a vertex on its own may be an unreferenced one: it is then
 * answered as gs_db_distance answers it, +INFINITY to everything else).
 * Weights are then clamped at 0 and divided by their sum. A corner repeated adds its
 * weights; only corners of nonzero weight are used, so a vertex v is
 * {v, v, v} with weights {1, 0, 0} (gs_surface_point_vertex), and a point
 * on an edge gives the same answers whichever of the edge's two faces
 * names it. */
typedef struct gs_surface_point {
    uint32_t corner[3];
    double weight[3];
} gs_surface_point;

#define GS_POINT_WEIGHT_MIN (-1e-12)
#define GS_POINT_WEIGHT_SUM_TOL 1e-9

/* Constructors (no validation). */
GS_API gs_surface_point gs_surface_point_make(uint32_t v0, uint32_t v1, uint32_t v2, double w0, double w1, double w2);
GS_API gs_surface_point gs_surface_point_vertex(uint32_t v);

/* The point sum_i bary[i] * corner_i of face `face` of mesh (its corners in
 * the mesh's order). GS_EARG if face >= gs_mesh_num_faces or a NULL
 * argument; the weights are checked by the queries, not here. */
GS_API int gs_surface_point_from_face(const gs_mesh *mesh, uint32_t face, double b0, double b1, double b2,
                               gs_surface_point *out, gs_error *err);

/* GS_OK if p is valid for db (rules above), else GS_EARG with a message
 * naming the bad corner or weight. */
GS_API int gs_db_point_check(const gs_db *db, const gs_surface_point *p, gs_error *err);

/* Approximate geodesic distance between two surface points p = sum_i l_i v_i
 * and q = sum_j m_j w_j (nonzero weights only), from the database's vertex
 * queries d(v_i, w_j) by the identity that holds for points in a plane,
 *   |p - q|^2 = sum_ij l_i m_j |v_i - w_j|^2 - sum_{i<k} l_i l_k |v_i - v_k|^2
 *                                           - sum_{j<k} m_j m_k |w_j - w_k|^2,
 * with geodesic distances in place of the first sum (the interpolation the
 * paper uses for separator samples, sec. 4.2, after Rustamov et al. 2009):
 *   d(p, q)^2 ~ sum_ij l_i m_j d(v_i, w_j)^2 - (the same two edge terms).
 * With exact vertex distances it is exact where the geodesics from p's
 * corners to q's unfold into one plane with p and q (a flat region away
 * from cut loci), and a close estimate elsewhere (README, "Distances
 * between surface points", gives the measured errors). Details:
 *  - two corners (of nonzero weight) of one point are an edge of its face
 *    (or one vertex): their distance is the straight one (exact), not a
 *    vertex query; so a point and a corner of its face, or two points of
 *    one face, get their straight distance in the face (when the corners
 *    involved have nonzero weights);
 *  - when every corner pair's distance is the straight one (same face, or
 *    same leaf without leaf tables), the answer is |p - q| itself (the
 *    identity then holds exactly; computed directly, it avoids the
 *    cancellation of nearby points);
 *  - a negative square is clamped at 0, and the answer is never below the
 *    straight |p - q| (vertex queries never are either);
 *  - two vertices (one corner each) give gs_db_distance exactly; the same
 *    point twice (the same corners of nonzero weight with the same
 *    weights) gives 0; d(p, q) == d(q, p) bit for bit;
 *  - +INFINITY if p and q are not connected; NaN if db, p or q is NULL or
 *    a point is invalid (gs_db_point_check says why).
 * At most 9 vertex queries. Thread-safe, allocation free. */
GS_API double gs_db_point_distance(const gs_db *db, const gs_surface_point *p, const gs_surface_point *q);

/* n pairs (pairs[2i], pairs[2i+1]) -> out[i]. Invalid points give NaN in
 * out[] and GS_EARG naming the first one (pair, point and what is wrong);
 * the other pairs are still answered. Thread-safe, allocation free. */
GS_API int gs_db_point_distances(const gs_db *db, const gs_surface_point *pairs, size_t n, double *out,
                          gs_error *err);

/* Distances from p to every vertex (out: n_vertices doubles), each equal
 * bit for bit to gs_db_point_distance(db, p, vertex y); from the corners'
 * gs_db_field. GS_EARG for an invalid p or NULL argument, GS_ENOMEM if the
 * work arrays (8 bytes x n_vertices per corner after the first, freed
 * before returning) cannot be allocated. Thread-safe. */
GS_API int gs_db_point_field(const gs_db *db, const gs_surface_point *p, double *out, gs_error *err);

/* Farthest-point sampling by the database's distances (greedy): out[0] =
 * seed_vertex, and each further out[i] is the vertex whose database
 * distance to the nearest of out[0..i-1] is largest. A vertex unreachable
 * from every sample so far (another component) counts as infinitely far,
 * so each component gets a sample before any gets a second; vertices used
 * by no face are never chosen; ties go to the lowest id. out receives k
 * vertex ids (caller's array). GS_EARG if k exceeds the number of vertices
 * used by faces, seed_vertex is out of range or used by no face, or an
 * argument is NULL; GS_ENOMEM if the work arrays cannot be allocated.
 * Cost: a gs_db_field while some vertex is unreached from every sample so
 * far (the first sample; one per component), then for each sample a
 * gs_db_within of the distance of that sample to the ones before (only
 * the vertices within it can come closer): far below a field each once
 * the samples spread out. Memory: 2 x n_vertices doubles, freed before
 * returning. Thread-safe (the database is only read). */
GS_API int gs_db_farthest_point_sampling(const gs_db *db, uint32_t k, uint32_t seed_vertex, uint32_t *out,
                                         gs_error *err);

/* ---- Queries by input vertex id (src/query/input.c; doc/repair.md) ------
 * A database built from a repaired mesh (gs_build_options.repair, geosep
 * build --repair) stores where every input vertex went: input vertex v
 * became the repaired vertices of its alias list (itself; a split vertex
 * also its copies; a welded vertex the one it was welded into). A query by
 * input ids answers the least distance over the aliases of each side:
 * d_in(x, y) = min over aliases a of x, b of y of gs_db_distance(a, b)
 * (0 when x == y). Without aliases stored, input ids are the vertex ids
 * and these calls answer as gs_db_distance / gs_db_field. */

/* The number of input vertices (n_vertices without aliases); 0 if db is
 * NULL. Thread-safe, allocation free. */
GS_API uint32_t gs_db_num_input_vertices(const gs_db *db);

/* Input vertex v's aliases (repaired vertex ids, the first the vertex v
 * became, then increasing): the first min(count, cap) written to out
 * (caller's array; may be NULL with cap 0). Returns the count (at least
 * 1), or 0 if v >= gs_db_num_input_vertices or db is NULL. Thread-safe,
 * allocation free. */
GS_API uint32_t gs_db_input_aliases(const gs_db *db, uint32_t v, uint32_t *out, uint32_t cap);

/* d_in(x, y) above: +INFINITY if not connected, NaN if an id is >=
 * gs_db_num_input_vertices. Thread-safe, allocation free. */
GS_API double gs_db_input_distance(const gs_db *db, uint32_t x, uint32_t y);

/* n pairs of input ids (pairs[2i], pairs[2i+1]) -> out[i]. Out-of-range ids
 * give NaN in out[] and GS_EARG naming the first; the other pairs are still
 * answered. Thread-safe, allocation free. */
GS_API int gs_db_input_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out, gs_error *err);

/* d_in from input vertex x to every input vertex (out: caller's array of
 * gs_db_num_input_vertices doubles), from gs_db_field of x's aliases.
 * GS_EARG for x out of range or a NULL argument; GS_ENOMEM if the work
 * arrays (8 bytes per repaired vertex, 16 when x has several aliases; freed
 * before returning) cannot be allocated. Thread-safe. */
GS_API int gs_db_input_field(const gs_db *db, uint32_t x, double *out, gs_error *err);

/* ---- Paths from a database (src/query/db_path.c, doc/paths.md) --------- */

/* GS_OK if mesh is the one db was built from: the same number of
 * vertices, every position bit for bit, and the same vertices used by no
 * face; else GS_EARG naming the first difference. Reads every vertex
 * (about 0.1 ms per 60k vertices). Thread-safe. */
GS_API int gs_db_check_mesh(const gs_db *db, const gs_mesh *mesh, gs_error *err);

/* A geodesic path from x to y (each a vertex or a surface point of mesh,
 * as gs_solver_path takes them: gs_source_vertex / gs_source_point) from
 * the database, without solving a field: a walk along the valley of the
 * database's d(x, .) + d(., y), then shortened until locally shortest
 * (funnel unfolding and vertex flips; doc/paths.md). The database does not
 * store faces: mesh must be the one db was built from (GS_EARG if the
 * vertex counts differ or a vertex the path visits is not where db has it;
 * gs_db_check_mesh checks every vertex). The result has the form of
 * gs_solver_path's paths (points as xyz and as face + barycentric weights,
 * consecutive points in one face, straight in faces and across edges,
 * bending only at saddle and boundary vertices) but is the locally
 * shortest path along the database's route: its length is never below
 * the exact distance and within 1% of it on the shared meshes (up to 2.4%
 * on rough ones: doc/accuracy.md). A path
 * longer than the database's distance by more than its usual error is
 * traced again from y, and if still too long (or the two walks differ and
 * the corridor is small) replaced by the exact
 * shortest path inside the corridor of shorter paths (an exact solve on
 * those faces: milliseconds, for about 1% of the paths). x == y gives one
 * point (GS_EARG for a vertex used by no face); points in different
 * components, or a vertex used by no face, an empty path (0 points,
 * length +INFINITY) and GS_OK. GS_EARG for an invalid point (the message
 * names X or Y and what is wrong), GS_ENOMEM, GS_EINTERNAL if the database
 * answers NaN (a corrupt file). *out receives a new path (gs_path_free),
 * NULL on error. Thread-safe: db and mesh are only read; each call
 * allocates its own work space (about the path's faces and the vertices
 * it queried). */
GS_API int gs_db_path(const gs_db *db, const gs_mesh *mesh, const gs_source *x, const gs_source *y,
                      gs_path **out, gs_error *err);

/* ======================================================================== */
/* Pictures (src/render): a software rasterizer, PNG output                 */
/* ======================================================================== */

/* What to draw. The camera looks at the mesh from direction (azimuth,
 * elevation) in degrees, y up: (0, 0) looks from +z towards -z with +x to
 * the right (a flat generated mesh face-on), azimuth 90 looks from +x,
 * elevation 90 from +y (above). Orthographic, fitted so that the vertices
 * used by faces fill the image less a margin of 5% on every side. Shading:
 * Lambert (two-sided) + ambient, smooth vertex normals, 3x3 supersampling
 * (2x2 above 4 megapixels, 1x1 above 16), white background (255,255,255).
 * Colours: the field by a viridis colour map from its smallest (dark
 * violet) to its largest finite value (yellow); a face with a non-finite
 * (inf or NaN) corner value is neutral grey (R = G = B); no field: a plain
 * light surface. Isolines: dark lines about 1.5 pixels wide (at any zoom:
 * from the field's screen-space gradient) at the levels
 * min + k (max - min) / (isolines + 1), k = 1..isolines. Separators: each
 * node's separator drawn between the vertices of its two subtrees (the
 * database keeps each vertex's leaf, not the curves): through the
 * midpoints of the edges it cuts (and a face's centroid where three
 * subtrees meet), then smoothed; by depth red (the root's, 4 pixels
 * wide), orange, blue, green, purple, then dark grey, thinner deeper down
 * (to 1.2 pixels), on top of the surface, hidden where the surface is in
 * front. Paths: white lines 2.5 pixels wide with a dark border (6 pixels
 * in all), over the separators, hidden where the surface is in front.
 * Points: white dots in a dark ring (9 pixels), on top, hidden where the
 * surface is in front. */
typedef struct gs_render_options {
    uint32_t width, height;      /* pixels, GS_RENDER_MIN_SIZE..MAX [640x480] */
    double azimuth_deg;          /* finite [30]                              */
    double elevation_deg;        /* finite [20]                              */
    const double *field;         /* n_vertices values, or NULL [NULL]        */
    uint32_t isolines;           /* 0..GS_RENDER_MAX_ISOLINES; ignored       */
                                 /*   without a field [10]                   */
    const gs_db *separators;     /* NULL or a database of this mesh (same    */
                                 /*   vertex count and positions) [NULL]     */
    const double *points;        /* 3 * n_points coordinates, finite [NULL]  */
    uint32_t n_points;           /*   [0]                                    */
    const double *paths;         /* polylines (paths: gs_path_xyz, geosep    */
    const uint32_t *path_starts; /*   path): path i is the points path_      */
    uint32_t n_paths;            /*   starts[i] .. path_starts[i+1]-1 of     */
                                 /*   paths (3 coordinates each, finite);    */
                                 /*   n_paths + 1 increasing offsets from 0  */
                                 /*   [NULL, NULL, 0]                        */
} gs_render_options;

#define GS_RENDER_MIN_SIZE 16u
#define GS_RENDER_MAX_SIZE 8192u
#define GS_RENDER_MAX_ISOLINES 1000u

/* Fill *opt with the defaults above. */
GS_API void gs_render_options_default(gs_render_options *opt);

/* Draw the mesh into rgb: width * height * 3 bytes (caller-owned), rows top
 * to bottom, R G B per pixel. The options' arrays are only read during the
 * call. GS_EARG (naming the option) if an argument is NULL or out of range
 * or the separators' database is not this mesh's; GS_ENOMEM. rgb is
 * untouched on failure. Thread-safe (no shared state: any number of calls
 * at once, on the same mesh and database too). */
GS_API int gs_render(const gs_mesh *mesh, const gs_render_options *opt, uint8_t *rgb, gs_error *err);

/* gs_render into an 8-bit RGB PNG file (libpng), written atomically
 * (temporary file, then rename): on failure no file, nor a partial one, is
 * left (an existing file is kept as it was). GS_EIO naming the path if it
 * cannot be written. Thread-safe. */
GS_API int gs_render_png(const gs_mesh *mesh, const gs_render_options *opt, const char *path, gs_error *err);

/* ======================================================================== */
/* Evaluation (paper section 5) and the LAND baseline                       */
/* ======================================================================== */

/* Errors of one candidate field against an exact one, as section 5 defines
 * them: e(y) = |d - d^|/d over y != source with finite d > 0. */
typedef struct gs_field_errors {
    double me, rmse, max;    /* mean, root-mean-square, max relative error  */
    uint64_t n_used;         /* pairs in the means                          */
    uint64_t n_skipped;      /* d = 0 (y != source) or d not finite         */
    uint64_t n_invalid;      /* candidate negative or non-finite, d finite  */
} gs_field_errors;

GS_API int gs_field_errors_compute(const double *exact, const double *approx, uint32_t n,
                            uint32_t source, gs_field_errors *out, gs_error *err);

/* The tail of the errors over many fields (what a user's single answers
 * see). me, rmse: the paper's measures, each field's ME / RMSE averaged over
 * the fields (section 5); all the others pool every (source, y) pair used:
 * p99, p999: nearest-rank quantiles of e (the value at rank ceil(q N));
 * max; near_me: the mean e over the "near pairs", those whose exact d is
 * below near_frac times the median exact d of all pairs used (the CLI and
 * the benchmarks use near_frac = 0.1); max_under / max_over: the largest e
 * where d^ < d / d^ > d; n_under_5pct / n_over_5pct: pairs with e > 5%.
 * Pairs are used as gs_field_errors_compute uses them. With no pair used,
 * every measure is NaN. */
typedef struct gs_error_stats {
    double me, rmse, p99, p999, max;
    double near_me, near_frac, median_d;
    double max_under, max_over;
    uint64_t n_used, n_near, n_under_5pct, n_over_5pct, n_skipped, n_invalid;
    uint32_t n_fields;       /* fields with at least one pair used          */
} gs_error_stats;

/* An accumulator of pairs' errors: 9 bytes per pair used. Create, add fields,
 * read the result (as often as wanted), free. Not thread-safe per object. */
typedef struct gs_error_acc gs_error_acc;
GS_API int gs_error_acc_create(gs_error_acc **out, gs_error *err);
/* Add one field's pairs (same arguments and rules as gs_field_errors_compute).
 * GS_ENOMEM leaves the accumulator as it was before the call's pairs. */
GS_API int gs_error_acc_add(gs_error_acc *acc, const double *exact, const double *approx, uint32_t n,
                            uint32_t source, gs_error *err);
/* The statistics of every pair added so far (near_frac >= 0: see above);
 * needs 4 bytes per pair of scratch (GS_ENOMEM otherwise). */
GS_API int gs_error_acc_result(const gs_error_acc *acc, double near_frac, gs_error_stats *out, gs_error *err);
GS_API void gs_error_acc_free(gs_error_acc *acc);

/* LAND (Burghard & Klein 2015), the baseline of the paper's Table 1: m
 * landmarks chosen by farthest-point sampling with geodesic distances (the
 * first is the lowest-numbered vertex used by a face; each next one is the
 * vertex farthest from all chosen ones, unreachable vertices first, so that
 * every component gets one), the exact distances from each landmark to
 * every vertex (m numbers per vertex), and the triangle-inequality bounds
 *   lower(x,y) = max_l |d(l,x) - d(l,y)|,  upper(x,y) = min_l d(l,x) + d(l,y)
 * over the landmarks l that reach x or y. LAND's estimate is the lower
 * bound (which the authors show has bounded relative error and is a metric);
 * gs_land_bounds gives both bounds.
 * Immutable after build: safe to query from any number of threads. */
typedef struct gs_land gs_land;

/* Choose m landmarks (1 <= m <= number of vertices used by faces, else
 * GS_EARG) and solve their fields with `method` on the whole mesh. The mesh
 * is only read during the call. *out receives a new object (caller frees). */
GS_API int gs_land_build(const gs_mesh *mesh, uint32_t m, gs_method method, gs_land **out,
                  gs_error *err);

/* LAND's estimate (the lower bound) of d(x, y): 0 if x == y; +INFINITY if x
 * and y are not connected (or lie in a component without a landmark); NaN
 * if an id is out of range. Allocation free. */
GS_API double gs_land_distance(const gs_land *l, uint32_t x, uint32_t y);

/* Both bounds (lower <= exact <= upper for exact landmark fields); either
 * pointer may be NULL. GS_EARG if an id is out of range. */
GS_API int gs_land_bounds(const gs_land *l, uint32_t x, uint32_t y, double *lower, double *upper,
                   gs_error *err);

/* Estimates from x to every vertex (out: gs_land_num_vertices() doubles). */
GS_API int gs_land_field(const gs_land *l, uint32_t x, double *out, gs_error *err);

GS_API uint32_t gs_land_num_vertices(const gs_land *l);
GS_API uint32_t gs_land_num_landmarks(const gs_land *l);
/* Borrowed: the landmark vertex ids in the order chosen, valid while l lives. */
GS_API const uint32_t *gs_land_landmarks(const gs_land *l);

GS_API void gs_land_free(gs_land *l);

/* ======================================================================== */
/* Ground-truth distance files (format GEOGT1, doc/file-formats.md)         */
/* ======================================================================== */

/* Distances from n_sources source vertices to every vertex. */
typedef struct gs_gt {
    uint32_t n_vertices;
    uint32_t n_sources;
    uint32_t *sources; /* n_sources source vertex ids                      */
    double *dist;      /* n_sources * n_vertices; row j is source j's field */
} gs_gt;

/* Read a GEOGT1 file; checks magic, counts against the file size, source
 * ids < n_vertices. *out receives a new gs_gt (caller frees with gs_gt_free). */
GS_API int gs_gt_read(const char *path, gs_gt **out, gs_error *err);

/* Write a GEOGT1 file atomically (temporary file, then rename). dist holds
 * n_sources * n_vertices doubles, row-major by source. */
GS_API int gs_gt_write(const char *path, uint32_t n_vertices, uint32_t n_sources,
                const uint32_t *sources, const double *dist, gs_error *err);

GS_API void gs_gt_free(gs_gt *gt);

#ifdef __cplusplus
}
#endif
#endif /* GEOSEP_H */
