/* geodesic_internal.h - the one interface every distance-field method
 * implements (exact window propagation, edge-graph Dijkstra, and later fast
 * marching and the heat method): a reusable per-patch state plus a solve
 * call. solver.c validates arguments so that methods can trust them. */
#ifndef GS_GEODESIC_INTERNAL_H
#define GS_GEODESIC_INTERNAL_H

#include "../mesh/mesh_internal.h"

typedef struct gs__solve_stats {
    uint64_t windows_created;
    uint64_t windows_propagated;
} gs__solve_stats;

/* Sources handed to a method are validated: vertex < nv, or face < nf with
 * bary >= 0 summing to exactly 1 (renormalised). A surface point that lies
 * on a vertex (bary = e_i) is passed as that vertex. */
typedef struct gs__method_ops {
    const char *name;
    /* allocate per-patch state; *state receives it */
    int (*create)(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err);
    void (*destroy)(void *state);
    /* fill dist[0..nv) ; max_distance is +INFINITY when unbounded */
    int (*solve)(void *state, const gs_source *src, uint32_t n_src, double max_distance,
                 double *dist, gs__solve_stats *stats, gs_error *err);
    /* optional (NULL: n single solves): one field per source, dist row i
     * (nv doubles) for source i; for methods that solve several at once
     * faster (the heat method's batched linear solves) */
    int (*solve_each)(void *state, const gs_source *src, uint32_t n_src, double *dist,
                      gs__solve_stats *stats, gs_error *err);
    /* optional (NULL: create anew): state for another thread that gives the
     * same fields and shares what it can read-only with `state`, which
     * must outlive it (the heat method's factorisations) */
    int (*clone)(const void *state, void **out, gs_error *err);
} gs__method_ops;

extern const gs__method_ops gs__exact_ops; /* exact.c  */
extern const gs__method_ops gs__graph_ops; /* graph.c  */
extern const gs__method_ops gs__fmm_ops;   /* fmm.c    */
extern const gs__method_ops gs__heat_ops;  /* heat.c   */
extern const gs__method_ops gs__dgg_ops;   /* dgg.c    */

/* Exact solver state (gs__exact_ops): one bounded solve from one source
 * (normalised) whose cost is proportional to the region it reaches, not to
 * the patch (for dgg.c's many local runs). dist: nv doubles, all +INFINITY
 * on entry; on return the vertices listed in *touched (n_touched of them,
 * owned by the state, valid until its next solve) hold real path lengths,
 * exact where <= max_d, and every other entry is still +INFINITY: the
 * caller resets the touched entries before the next call. */
int gs__exact_solve_local(void *state, const gs_source *src, double max_d, double *dist,
                          const uint32_t **touched, uint32_t *n_touched, gs_error *err);
/* The same; direct_only: no windows from pseudo-source vertices (saddle,
 * boundary), only the rays straight from the source: a vertex reached
 * straight by its shortest path gets its exact distance (within max_d),
 * any other one the length of a straight path or of a path along edges,
 * or none (dgg.c's candidates: only straight paths matter there). */
int gs__exact_solve_local_ex(void *state, const gs_source *src, double max_d, int direct_only, double *dist,
                             const uint32_t **touched, uint32_t *n_touched, gs_error *err);
/* After gs__exact_solve_local from vertex source_vertex (or from a surface
 * point: pass GS_NONE): 1 if the shortest path found to u (distance du)
 * is straight (no bend at a vertex on the way: it leaves the source
 * directly), 0 if it bends at a pseudo-source vertex w, where then
 * du = d(w) + d(w, u). */
int gs__exact_straight(const void *state, uint32_t source_vertex, uint32_t u, double du);

/* ---- dgg (dgg.c) --------------------------------------------------------- */

/* Progress of a graph construction: fn(user, fraction done), called from
 * one thread (may be NULL). */
typedef struct gs__dgg_progress {
    void (*fn)(void *user, double frac);
    void *user;
} gs__dgg_progress;

/* The graph of topology t for eps (pruned to eps if prune, else every
 * candidate edge is kept), its local runs on nthreads OpenMP threads (0:
 * the OpenMP default); the same graph for any thread count. *graph: owned
 * by the caller until handed to gs__dgg_state_from_graph (or
 * gs__dgg_free). */
int gs__dgg_build(const gs__topo *t, double eps, int prune, uint32_t nthreads, const gs__dgg_progress *progress,
                  void **graph, gs_error *err);
void gs__dgg_free(void *graph);
/* A dgg solver state of t owning graph (freed here on failure). */
int gs__dgg_state_from_graph(const gs__topo *t, void *graph, void **state, gs_error *err);
/* A dgg state for the sub-patch t whose vertex v is vertex vmap[v] of the
 * graph of `whole` (vmap increasing; NULL: the same ids): the Dijkstra of
 * whole's graph restricted to t's vertices. whole and vmap must outlive it. */
int gs__dgg_view(const void *whole, const gs__topo *t, const uint32_t *vmap, void **state, gs_error *err);

typedef struct gs__dgg_stats {
    double seconds;        /* construction (wall)                          */
    double radius;         /* R (absolute)                                 */
    uint64_t candidates;   /* straight pairs within R_v (edges before pruning) */
    uint64_t edges;        /* edges kept                                   */
    uint64_t bytes;        /* the graph's memory                           */
    uint64_t solve_bytes;  /* per solver (thread): heap and maps           */
} gs__dgg_stats;
void gs__dgg_info(const void *state, gs__dgg_stats *st);
/* The same for a solver; GS_EARG if its method is not GS_METHOD_DGG. */
int gs__solver_dgg_info(const gs_solver *s, gs__dgg_stats *st, gs_error *err);
/* gs_solver_create_ex for GS_METHOD_DGG with the construction's threads,
 * pruning and progress given (opt->dgg_eps is checked as there). */
int gs__solver_create_dgg(const gs_patch *patch, const gs_solver_options *opt, uint32_t nthreads, int prune,
                          const gs__dgg_progress *progress, gs_solver **out, gs_error *err);
/* A solver of sub, a patch of the mesh of whole's patch, whose fields are
 * the Dijkstra of whole's dgg graph restricted to sub's vertices
 * (gs__dgg_view). whole's patch must be the whole mesh (identity); whole
 * and sub must outlive it. */
int gs__solver_dgg_view(const gs_solver *whole, const gs_patch *sub, gs_solver **out, gs_error *err);

/* One field per source: dist receives n rows of gs_patch_num_vertices()
 * doubles, row i the field of sources[i] alone (unbounded). Same results
 * as n calls of gs_solver_solve, up to rounding for methods with a batched
 * solve (heat). Sources are validated like gs_solver_solve's. */
int gs__solver_solve_each(gs_solver *solver, const gs_source *sources, uint32_t n, double *dist,
                          gs_error *err);

/* A solver of the same patch, method and options for another thread: it
 * gives the same fields bit for bit and shares with src what it only reads
 * (the heat method: its factorisations, a CHOLMOD workspace per solver), so
 * that n threads do not cost n factorisations' memory and time. src must
 * outlive it; each solver is used by one thread at a time. *out: new solver
 * (gs_solver_free). */
int gs__solver_clone(const gs_solver *src, gs_solver **out, gs_error *err);

/* Position of a source point: p = sum_i bary[i] * corner_i. */
void gs__source_position(const gs__topo *t, const gs_source *s, double p[3]);

/* The vertices a front-propagating method starts from: the source vertex at
 * distance 0, or the three corners of a source point's face at their
 * straight-line distance to it. Returns the count (1 or 3). */
uint32_t gs__source_seeds(const gs__topo *t, const gs_source *s, uint32_t v[3], double d[3]);

/* ---- exact paths (exact.c records, path.c backtracks) -------------------- */

/* What gave a vertex its distance in the last exact solve (kind[v]):
 *   NONE   a source vertex (distance 0), or not reached;
 *   EDGE   straight along an edge from the vertex tri[ref] (ref a corner of
 *          a face holding both);
 *   WINDOW straight from the window source (sxy[2v], sxy[2v+1]) in the frame
 *          of half-edge ref (tri[ref] at the origin, tri[next(ref)] on +x,
 *          the face ref/3 on y > 0; v is tri[prev(ref)]): the unfolded
 *          position of a vertex (tag GS_NONE) or of the point source src[tag];
 *   POINT  straight inside the face of point source src[ref]. */
enum { GS_EXTR_NONE = 0, GS_EXTR_EDGE = 1, GS_EXTR_WINDOW = 2, GS_EXTR_POINT = 3 };

/* The best window found for one surface point (gs__exact_set_target). */
typedef struct gs__exact_target {
    uint32_t face;   /* GS_NONE: none set */
    double bary[3];
    double dist;     /* +INFINITY when no window entering the face covers it */
    uint32_t h, tag; /* as ref and tag of a WINDOW record */
    double sx, sy;
} gs__exact_target;

typedef struct gs__exact_trace {
    uint8_t *kind;
    uint32_t *ref, *tag;
    double *sxy;
    double *dist;    /* the last field */
    double max_d;    /* its bound (+INFINITY: complete) */
    gs_source *src;  /* the last solve's (normalised) sources */
    uint32_t n_src;
    int valid;       /* a solve completed */
    gs__exact_target target;
} gs__exact_trace;

/* Exact solver state: make the next solves also find the distance of a
 * surface point (its best window), or stop (target NULL or a vertex). */
void gs__exact_set_target(void *state, const gs_source *target);
/* Exact solver state: the next bounded solves need only the paths to the
 * surface point at goal (xyz) no longer than their max_distance: windows
 * every path of which through to goal is longer (by its straight-line
 * distance) are dropped, so that only distances on such paths stay exact.
 * NULL: every distance up to the bound (the default). */
void gs__exact_set_goal(void *state, const double *goal);
/* The records of the last successful solve, NULL if there was none. */
const gs__exact_trace *gs__exact_get_trace(const void *state);
/* path.c: the path from the last solve's sources to target (normalised;
 * a surface point only if it was the solve's gs__exact_set_target). */
int gs__exact_trace_path(const gs__topo *t, const gs__exact_trace *tr, const gs_source *target, gs_path **out,
                         gs_error *err);

/* gs_solver_path with the solve bounded by max_distance (0: unbounded):
 * a target farther than that gets an empty path of infinite length; the
 * solve skips what cannot lead to the target within the bound
 * (gs__exact_set_goal). */
int gs__solver_path_bounded(gs_solver *s, const gs_source *source, const gs_source *target, double max_distance,
                            gs_path **out, gs_error *err);

/* path.c: a path made of n points (db_path.c builds them); takes ownership
 * of the malloc'ed arrays xyz (3n), face (n), bary (3n), also on failure. */
int gs__path_adopt(uint32_t n, double *xyz, uint32_t *face, double *bary, double length, gs_path **out,
                   gs_error *err);

#endif
