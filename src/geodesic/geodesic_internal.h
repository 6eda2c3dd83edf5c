/* geodesic_internal.h - the one interface every distance-field method
 * implements (exact window propagation, edge-graph Dijkstra, and later fast
 * marching and the heat method): a reusable per-patch state plus a solve
 * call. solver.c validates arguments so that methods can trust them. */
#ifndef GS_GEODESIC_INTERNAL_H
#define GS_GEODESIC_INTERNAL_H

#include "../mesh/mesh_internal.h"

typedef struct gs_solve_stats {
    uint64_t windows_created;
    uint64_t windows_propagated;
} gs_solve_stats;

/* Sources handed to a method are validated: vertex < nv, or face < nf with
 * bary >= 0 summing to exactly 1 (renormalised). A surface point that lies
 * on a vertex (bary = e_i) is passed as that vertex. */
typedef struct gs_method_ops {
    const char *name;
    /* allocate per-patch state; *state receives it */
    int (*create)(const gs_topo *t, const gs_solver_options *opt, void **state, gs_error *err);
    void (*destroy)(void *state);
    /* fill dist[0..nv) ; max_distance is +INFINITY when unbounded */
    int (*solve)(void *state, const gs_source *src, uint32_t n_src, double max_distance,
                 double *dist, gs_solve_stats *stats, gs_error *err);
    /* optional (NULL: n single solves): one field per source, dist row i
     * (nv doubles) for source i; for methods that solve several at once
     * faster (the heat method's batched linear solves) */
    int (*solve_each)(void *state, const gs_source *src, uint32_t n_src, double *dist,
                      gs_solve_stats *stats, gs_error *err);
    /* optional (NULL: create anew): state for another thread that gives the
     * same fields and shares what it can read-only with `state`, which
     * must outlive it (the heat method's factorisations) */
    int (*clone)(const void *state, void **out, gs_error *err);
} gs_method_ops;

extern const gs_method_ops gs_exact_ops; /* exact.c  */
extern const gs_method_ops gs_graph_ops; /* graph.c  */
extern const gs_method_ops gs_fmm_ops;   /* fmm.c    */
extern const gs_method_ops gs_heat_ops;  /* heat.c   */

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
void gs_source_position(const gs_topo *t, const gs_source *s, double p[3]);

/* The vertices a front-propagating method starts from: the source vertex at
 * distance 0, or the three corners of a source point's face at their
 * straight-line distance to it. Returns the count (1 or 3). */
uint32_t gs_source_seeds(const gs_topo *t, const gs_source *s, uint32_t v[3], double d[3]);

#endif
