/* heat_internal.h - the heat method (Crane, Weischedel & Wardetzky 2013, "Geodesics
 * in heat"): heat flow u = (M + tL)^-1 delta for a short time t, the unit
 * field X = -grad u / |grad u| per face, and the Poisson problem
 * L phi = -div X, whose solution is the distance up to a constant.
 *
 * Discretisation (choices, in order):
 *  - Intrinsic Delaunay triangulation (Bobenko & Springborn 2007; Sharp,
 *    Soliman & Crane 2019): edges are flipped on edge lengths alone until
 *    every interior edge satisfies cot a + cot b >= 0, so the cotan weights
 *    are non-negative and slivers (bunny-5k has 0.4 degree corners) give
 *    well-conditioned matrices. Before flipping, lengths are mollified
 *    (Sharp & Crane 2020): if some triangle violates the triangle
 *    inequality by less than a margin eps = 1e-5 * mean edge length, every
 *    length is increased by the same delta so that all triangles satisfy it
 *    with that margin (a no-op on ordinary meshes; it keeps areas > 0).
 *  - L: the cotan Laplacian (positive semi-definite sign), M: lumped
 *    barycentric mass (area / 3 per corner), on the intrinsic mesh.
 *  - t = m h^2 (field t_step), m = gs_solver_options.heat_time (default 1:
 *    the paper's t = h^2), h the input mesh's mean edge length weighted by
 *    area: sum over faces of area x mean edge length / total area (h_time;
 *    the plain mean on uniform meshes). Where triangles vary in size, most
 *    of the surface, and of every geodesic, lies in the large ones, and a
 *    t below their edge length leaves them under-resolved (rocker-arm:
 *    edges 0.04 to 7 mean lengths, 1.57x the plain mean; its ME against
 *    exact distances 2.15% with the plain mean, 1.37% with this one).
 *  - Two heat flows, u at time t and w at time 4t (HEAT_T2_RATIO), and the
 *    direction X = -grad(log u - log w) / |...| per face, the gradient of
 *    the linear interpolant of the corner values. Why: a heat flow from a
 *    point decays like A(x) exp(-d / sqrt(t)), so log u = -d / sqrt(t) +
 *    log A is nearly linear across a triangle (u itself is not: the
 *    gradient of u's linear interpolant is biased by the triangle's shape)
 *    and the amplitude A, which varies across geodesics on a curved
 *    surface and tilts grad log u by O(sqrt(t)), is to first order the
 *    same for both times and cancels in the difference, which leaves
 *    (1 / sqrt(t) - 1 / sqrt(4t)) grad d. Measured against exact
 *    distances (doc/approximate-fields.md), this halves the mean error on bunny-5k and makes
 *    heat distances nearly additive (d(x,y) ~ d(x,s) + d(s,y) along a
 *    geodesic), which the SEP database relies on. Both systems are
 *    M-matrices (non-negative cotan weights on the intrinsic Delaunay
 *    mesh), so their direct solutions are positive and accurate
 *    componentwise far below the source's value: the logarithm is used
 *    wherever u is a normal number (>= DBL_MIN, about 700 sqrt(t) from the
 *    source). Beyond, where w still is (twice as far), -grad log w is
 *    used; where neither is, the face has no direction (as before, where
 *    u underflowed: X = 0 there, distances stop growing).
 *  - The start ball (HEAT_EXACT_START mean edge lengths around the
 *    sources): a field of unit vectors constant per face cannot represent
 *    the cone of distances at a point source (its first ring comes out
 *    cos(angle / 2) too short, an offset the whole field carries); inside
 *    the ball exact distances (window propagation bounded to its radius)
 *    are known, and every face with three corners in it takes the
 *    gradient of their linear interpolant (not normalised) instead.
 *  - Refinement (gs_solver_options.heat_refine = N > 0): the patch is
 *    subdivided 1-to-4 N times (midpoints of the edges: the same polyhedral
 *    surface, so the same exact distances, at 4^N times the triangles), the
 *    fields are solved on that mesh as above, with its own h (t = heat_time
 *    x its h^2, 4^-N times the unrefined t; start ball of its mean edge
 *    lengths), and read back at the patch's vertices, which keep their ids.
 *    A finer mesh makes the discrete heat kernel decay at the same rate in
 *    every direction, which is what makes heat distances additive along a
 *    geodesic (bunny-5k database vs its own fields, ME 0.80% / 0.51% /
 *    0.41% for N = 0 / 1 / 2; a smaller t on the original mesh does not do
 *    that, see doc/approximate-fields.md). Face sources go to the sub-face holding the point.
 *    The refined mesh and its factors exist only while the solver does.
 *  - Boundaries: the paper's recommendation, the average of the Neumann
 *    heat flow (the plain system) and the Dirichlet one (u = 0 on boundary
 *    vertices: a second factorisation over interior vertices). Closed
 *    patches use the Neumann factor only.
 *  - Poisson: L is singular (constants per connected component); one vertex
 *    per component is pinned to 0 (its row and column replaced by the
 *    identity's), which makes the matrix positive definite without
 *    perturbing the solution (the right-hand side sums to zero per
 *    component exactly). Dirichlet vertices and unreferenced ones are fixed
 *    the same way, so all (up to) three matrices share one sparsity pattern
 *    and one fill-reducing analysis; each is factored once in create.
 *  - Each component is shifted so that its smallest value over the sources
 *    it holds is 0; vertex sources get 0, tiny negatives are clamped to 0.
 *    Components (and unreferenced vertices) without a source get +INFINITY.
 *    max_distance is ignored: the whole field is computed anyway.
 * Sources: vertex v adds 1 to delta_v; a point of face f adds bary_i to the
 * corners of f; several sources sum their deltas.
 *
 * Files: heat_setup.c builds a solver (the intrinsic Delaunay triangulation,
 * the matrices and their factorisations, the refined mesh; create, clone,
 * destroy); heat.c solves (heat flows, directions, divergence, start ball,
 * Poisson, shifts). This header holds the state they share. */
#ifndef GS_HEAT_INTERNAL_H
#define GS_HEAT_INTERNAL_H

#include "../linalg/sparse.h"
#include "geodesic_internal.h"

/* Sources solved per batch: the triangular solves of a batch share each
 * pass over the factor (level-3 BLAS instead of level 2). */
enum { HEAT_BATCH = 16 };

typedef struct heat_state {
    /* a clone (gs__heat_clone): base, whose topology, geometry, maps and
     * factorisations it shares read-only; its own: the factor views, work
     * arrays, start-ball solver and batch buffers. NULL: the original */
    const struct heat_state *base;
    const gs__topo *t;   /* the mesh solved on: the patch's, or refined_t    */
    /* refined solve (heat_refine > 0): the patch's topology t0 (nv0
     * vertices), subdivided `refine` times into refined_t (own arrays); the
     * fields are solved on refined_t (its first nv0 vertices are t0's) into
     * rdist (rcap rows of nv), sources mapped into rsrc */
    const gs__topo *t0;
    uint32_t nv0, refine;
    gs__topo refined_t;
    double *rxyz, *rdist;
    uint32_t *rtri, rcap, rsrc_cap;
    gs_source *rsrc;
    uint32_t nv, nf;
    double t_step;      /* heat time step t (h^2 by default)                */
    double h_mean;      /* mean edge length of the mesh solved on           */
    double r_ball;      /* start ball radius                                */
    double h_time;      /* its mean edge length weighted by area: t's h     */
    /* intrinsic Delaunay triangulation: same faces count, flipped corners */
    uint32_t *itri;     /* 3*nf vertices                                    */
    uint32_t *iopp;     /* 3*nf twins (or GS_NONE)                          */
    double *ilen;       /* 3*nf lengths                                     */
    double *cot;        /* 3*nf cotangent of the angle at corner h          */
    double *area;       /* nf                                               */
    double *dgeo;       /* 12*nf: divergence geometry per face              */
    double *mass;       /* nv lumped mass                                   */
    uint32_t *comp;     /* nv component id, GS_NONE if unreferenced         */
    uint32_t n_comp;
    /* free vertices of each system (GS_NONE: fixed to 0, identity row) */
    uint32_t *map_n;    /* heat, Neumann: every referenced vertex           */
    uint32_t *map_d;    /* heat, Dirichlet: referenced interior vertices    */
    uint32_t *map_p;    /* Poisson: referenced, minus one pin per component */
    gs__sparse_factor *heat_n, *heat_d, *poisson;
    gs__sparse_factor *heat_n2, *heat_d2; /* the same at time 4t            */
    /* intrinsic faces around each vertex (CSR), for the start ball */
    uint32_t *vf_start, *vf;
    /* work arrays (nv each) */
    double *b, *x, *u, *w, *div, *phi, *cmin;
    /* batch work arrays (solve_each): kcap columns of nv each */
    double *kb, *ku, *kx, *kw;
    uint32_t kcap;
    uint64_t n_flips;
    /* start ball: exact solver (created on first use), its distances, a
     * per-face stamp so each face is visited once per field */
    void *exact;
    double *edist;
    uint32_t *fmark, stamp;
    /* the balls of the fields of a batch: field c's vertices and exact
     * distances are ball_v, ball_d [ball_start[c], ball_start[c + 1]) */
    uint32_t *ball_v, ball_n, ball_cap, ball_start[HEAT_BATCH + 1];
    double *ball_d, *csum;
} heat_state;

/* The second heat flow's time, in units of t. */
#define HEAT_T2_RATIO 4.0
/* Radius of the start ball, in mean edge lengths. */
#define HEAT_EXACT_START 4.0

/* heat_setup.c: the method's create, destroy and clone (gs__method_ops). */
int gs__heat_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err);
void gs__heat_destroy(void *state);
int gs__heat_clone(const void *state, void **out, gs_error *err);
/* Map n sources of the patch to the refined mesh (into s->rsrc, grown as
 * needed); s->refine > 0. */
int gs__heat_map_sources(heat_state *s, const gs_source *src, uint32_t n, gs_error *err);

#endif
