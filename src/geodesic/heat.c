/* heat.c - the heat method (Crane, Weischedel & Wardetzky 2013, "Geodesics
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
 * corners of f; several sources sum their deltas. */
#include "../linalg/sparse.h"
#include "geodesic_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sources solved per batch: the triangular solves of a batch share each
 * pass over the factor (level-3 BLAS instead of level 2). */
enum { HEAT_BATCH = 16 };

typedef struct heat_state {
    /* a clone (heat_clone): base, whose topology, geometry, maps and
     * factorisations it shares read-only; its own: the factor views, work
     * arrays, start-ball solver and batch buffers. NULL: the original */
    const struct heat_state *base;
    const gs_topo *t;   /* the mesh solved on: the patch's, or refined_t    */
    /* refined solve (heat_refine > 0): the patch's topology t0 (nv0
     * vertices), subdivided `refine` times into refined_t (own arrays); the
     * fields are solved on refined_t (its first nv0 vertices are t0's) into
     * rdist (rcap rows of nv), sources mapped into rsrc */
    const gs_topo *t0;
    uint32_t nv0, refine;
    gs_topo refined_t;
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
    gs_sparse_factor *heat_n, *heat_d, *poisson;
    gs_sparse_factor *heat_n2, *heat_d2; /* the same at time 4t            */
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

/* ---- intrinsic geometry ------------------------------------------------- */

/* Area of a triangle from its lengths (Kahan's stable Heron formula). */
static double tri_area(double a, double b, double c)
{
    double s; /* sort a >= b >= c */
    if (a < b) { s = a; a = b; b = s; }
    if (b < c) { s = b; b = c; c = s; }
    if (a < b) { s = a; a = b; b = s; }
    double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    return q > 0 ? 0.25 * sqrt(q) : 0.0;
}

/* cot of the angle opposite length a in the triangle (a, b, c). */
static double cot_opposite(double a, double b, double c)
{
    double A = tri_area(a, b, c);
    if (!(A > 0)) return 0.0;
    return (b * b + c * c - a * a) / (4.0 * A);
}

/* Sum of the cotangents opposite interior edge h (in both faces). */
static double edge_cot_sum(const heat_state *s, uint32_t h)
{
    uint32_t g = s->iopp[h];
    double a = cot_opposite(s->ilen[h], s->ilen[gs_next(h)], s->ilen[gs_prev(h)]);
    double b = cot_opposite(s->ilen[g], s->ilen[gs_next(g)], s->ilen[gs_prev(g)]);
    return a + b;
}

static void set_slot(heat_state *s, uint32_t slot, uint32_t twin, double len)
{
    s->iopp[slot] = twin;
    s->ilen[slot] = len;
    if (twin != GS_NONE) s->iopp[twin] = slot;
}

/* Flip interior edge h (from a to b; c opposite in its face, d opposite in
 * the twin's face). Returns 0 if the configuration is degenerate. */
static int flip_edge(heat_state *s, uint32_t h)
{
    uint32_t g = s->iopp[h];
    uint32_t f1 = h / 3, f2 = g / 3;
    if (f1 == f2) return 0;
    uint32_t nh = gs_next(h), ph = gs_prev(h), ng = gs_next(g), pg = gs_prev(g);
    uint32_t a = s->itri[h], b = s->itri[nh], c = s->itri[ph], d = s->itri[pg];
    if (c == d) return 0;
    uint32_t o_nh = s->iopp[nh], o_ph = s->iopp[ph], o_ng = s->iopp[ng], o_pg = s->iopp[pg];
    uint32_t outer[4] = {o_nh, o_ph, o_ng, o_pg};
    for (int k = 0; k < 4; ++k)
        if (outer[k] != GS_NONE && (outer[k] / 3 == f1 || outer[k] / 3 == f2)) return 0;
    double l_ab = s->ilen[h], l_bc = s->ilen[nh], l_ca = s->ilen[ph];
    double l_ad = s->ilen[ng], l_db = s->ilen[pg];
    /* lay out a = (0,0), b = (l_ab, 0), c above, d below */
    double cx = (l_ab * l_ab + l_ca * l_ca - l_bc * l_bc) / (2 * l_ab);
    double cy = sqrt(fmax(l_ca * l_ca - cx * cx, 0.0));
    double dx = (l_ab * l_ab + l_ad * l_ad - l_db * l_db) / (2 * l_ab);
    double dy = -sqrt(fmax(l_ad * l_ad - dx * dx, 0.0));
    double l_cd = hypot(cx - dx, cy - dy);
    if (!(l_cd > 0) || !isfinite(l_cd)) return 0;
    /* new faces: f1 = (d, c, a), f2 = (c, d, b); h and g are the diagonal */
    s->itri[h] = d; s->itri[nh] = c; s->itri[ph] = a;
    s->itri[g] = c; s->itri[ng] = d; s->itri[pg] = b;
    s->iopp[h] = g; s->iopp[g] = h;
    s->ilen[h] = s->ilen[g] = l_cd;
    set_slot(s, nh, o_ph, l_ca); /* c -> a */
    set_slot(s, ph, o_ng, l_ad); /* a -> d */
    set_slot(s, ng, o_pg, l_db); /* d -> b */
    set_slot(s, pg, o_nh, l_bc); /* b -> c */
    return 1;
}

static int make_intrinsic_delaunay(heat_state *s, gs_error *err)
{
    const gs_topo *t = s->t;
    size_t nh = 3 * (size_t)s->nf;
    memcpy(s->itri, t->tri, nh * sizeof *s->itri);
    memcpy(s->iopp, t->opp, nh * sizeof *s->iopp);
    memcpy(s->ilen, t->len, nh * sizeof *s->ilen);
    /* mollification (Sharp & Crane 2020) */
    double eps = 1e-5 * s->h_mean, delta = 0;
    for (uint32_t f = 0; f < s->nf; ++f)
        for (int i = 0; i < 3; ++i) {
            double a = s->ilen[3 * f + i], b = s->ilen[3 * f + (i + 1) % 3],
                   c = s->ilen[3 * f + (i + 2) % 3];
            delta = fmax(delta, eps - (b + c - a));
        }
    if (delta > 0)
        for (size_t h = 0; h < nh; ++h) s->ilen[h] += delta;
    /* flip non-Delaunay edges: a stack of half-edge slots */
    uint32_t *stack = gs__malloc(nh ? nh : 1, sizeof *stack);
    uint8_t *queued = gs__calloc(nh ? nh : 1, 1);
    if (!stack || !queued) {
        free(stack);
        free(queued);
        return gs__fail(err, GS_ENOMEM, "out of memory building the intrinsic triangulation");
    }
    size_t top = 0;
    for (size_t h = 0; h < nh; ++h)
        if (s->iopp[h] != GS_NONE && h < s->iopp[h]) {
            stack[top++] = (uint32_t)h;
            queued[h] = 1;
        }
    uint64_t max_flips = 50 * (uint64_t)nh + 1000;
    while (top && s->n_flips < max_flips) {
        uint32_t h = stack[--top];
        queued[h] = 0;
        if (s->iopp[h] == GS_NONE) continue;
        if (edge_cot_sum(s, h) >= -1e-10) continue;
        if (!flip_edge(s, h)) continue;
        s->n_flips++;
        uint32_t g = s->iopp[h];
        uint32_t around[4] = {gs_next(h), gs_prev(h), gs_next(g), gs_prev(g)};
        for (int k = 0; k < 4; ++k) {
            uint32_t e = around[k];
            if (s->iopp[e] == GS_NONE) continue;
            if (!queued[e] && top < nh) {
                stack[top++] = e;
                queued[e] = 1;
            }
        }
    }
    free(stack);
    free(queued);
    return GS_OK;
}

/* ---- matrices ----------------------------------------------------------- */

static uint32_t comp_find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

static void build_geometry(heat_state *s)
{
    memset(s->mass, 0, s->nv * sizeof *s->mass);
    for (uint32_t f = 0; f < s->nf; ++f) {
        const double *l = s->ilen + 3 * (size_t)f;
        double A = tri_area(l[0], l[1], l[2]);
        s->area[f] = A;
        for (int i = 0; i < 3; ++i) {
            /* corner i is opposite half-edge (i + 1) % 3 */
            double opp = l[(i + 1) % 3], b = l[i], c = l[(i + 2) % 3];
            s->cot[3 * (size_t)f + i] = A > 0 ? (b * b + c * c - opp * opp) / (4.0 * A) : 0.0;
            s->mass[s->itri[3 * (size_t)f + i]] += A / 3.0;
        }
    }
}

/* Assemble and factor the nv x nv matrix a*M + c*L on the free vertices
 * (map[v] != GS_NONE); a fixed vertex v gets the row and column of the
 * identity (x_v = b_v = 0), its couplings kept as explicit zeros. So every
 * system of a patch has the same sparsity pattern, and the fill-reducing
 * analysis of the first one (like == NULL) is reused by the others. */
static gs_sparse_factor *factor_system(const heat_state *s, const uint32_t *map, double a,
                                       double c, const gs_sparse_factor *like, gs_error *err)
{
    size_t cap = (size_t)s->nv + 3 * (size_t)s->nf * 3;
    uint32_t *ti = gs__malloc(cap, sizeof *ti), *tj = gs__malloc(cap, sizeof *tj);
    double *tx = gs__malloc(cap, sizeof *tx);
    if (!ti || !tj || !tx) {
        free(ti), free(tj), free(tx);
        gs__fail(err, GS_ENOMEM, "out of memory assembling the heat method's matrices");
        return NULL;
    }
    size_t k = 0;
    for (uint32_t v = 0; v < s->nv; ++v) {
        ti[k] = tj[k] = v;
        tx[k++] = map[v] != GS_NONE ? a * s->mass[v] : 1.0;
    }
    /* every half-edge h: weight cot(angle opposite h) / 2 */
    for (size_t h = 0; h < 3 * (size_t)s->nf; ++h) {
        double w = 0.5 * s->cot[3 * (h / 3) + (h % 3 + 2) % 3] * c;
        uint32_t i = s->itri[h], j = s->itri[gs_next((uint32_t)h)];
        int fi = map[i] != GS_NONE, fj = map[j] != GS_NONE;
        if (i == j) continue;
        if (fi) ti[k] = tj[k] = i, tx[k++] = w;
        if (fj) ti[k] = tj[k] = j, tx[k++] = w;
        ti[k] = i > j ? i : j;
        tj[k] = i > j ? j : i;
        tx[k++] = fi && fj ? -w : 0.0;
    }
    gs_sparse_factor *F = gs_sparse_factor_create(s->nv, k, ti, tj, tx, like, err);
    free(ti), free(tj), free(tx);
    return F;
}

/* Per face, from a 2D layout of the intrinsic face (p0 = (0,0), p1 on the
 * x axis, p2 above): the edges opposite each corner rotated by +90 degrees
 * (grad u = sum_i u_i * those / (2 area), only its direction is used) and
 * each corner's divergence weights 0.5 (cot_k (p_j - p_i) + cot_j (p_k -
 * p_i)). Computed once, used by every solve: 12 doubles per face. */
static void build_divergence_geometry(heat_state *s)
{
    for (uint32_t f = 0; f < s->nf; ++f) {
        double *q = s->dgeo + 12 * (size_t)f;
        memset(q, 0, 12 * sizeof *q);
        if (!(s->area[f] > 0)) continue;
        const double *l = s->ilen + 3 * (size_t)f; /* l[0]=|p0p1| l[1]=|p1p2| l[2]=|p2p0| */
        double p[3][2];
        p[0][0] = 0, p[0][1] = 0;
        p[1][0] = l[0], p[1][1] = 0;
        p[2][0] = (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2 * l[0]);
        p[2][1] = 2 * s->area[f] / l[0];
        const double *ct = s->cot + 3 * (size_t)f;
        for (int i = 0; i < 3; ++i) {
            int j = (i + 1) % 3, k = (i + 2) % 3;
            q[2 * i] = -(p[k][1] - p[j][1]);
            q[2 * i + 1] = p[k][0] - p[j][0];
            q[6 + 2 * i] = 0.5 * (ct[k] * (p[j][0] - p[i][0]) + ct[j] * (p[k][0] - p[i][0]));
            q[7 + 2 * i] = 0.5 * (ct[k] * (p[j][1] - p[i][1]) + ct[j] * (p[k][1] - p[i][1]));
        }
    }
}

/* What a clone owns (and the original too). */
static void free_own(heat_state *s)
{
    gs_sparse_factor_free(s->heat_n);
    gs_sparse_factor_free(s->heat_d);
    gs_sparse_factor_free(s->poisson);
    gs_sparse_factor_free(s->heat_n2);
    gs_sparse_factor_free(s->heat_d2);
    if (s->exact) gs_exact_ops.destroy(s->exact);
    free(s->edist), free(s->fmark);
    free(s->ball_v), free(s->ball_d), free(s->csum);
    free(s->b), free(s->x), free(s->u), free(s->w), free(s->div), free(s->phi), free(s->cmin);
    free(s->kb), free(s->ku), free(s->kx), free(s->kw);
    free(s->rdist), free(s->rsrc);
}

/* The work arrays every solver (original or clone) allocates up front, for
 * s->nv vertices; 0 on failure (free_own frees what was allocated). */
static int alloc_own(heat_state *s)
{
    size_t nv = s->nv ? s->nv : 1;
    int ok = (s->b = gs__malloc(nv, sizeof(double))) && (s->x = gs__malloc(nv, sizeof(double))) &&
             (s->u = gs__malloc(nv, sizeof(double))) && (s->w = gs__malloc(nv, sizeof(double))) &&
             (s->div = gs__malloc(nv, sizeof(double))) && (s->phi = gs__malloc(nv, sizeof(double))) &&
             (s->cmin = gs__malloc(nv, sizeof(double))) && (s->csum = gs__malloc(2 * nv, sizeof(double)));
    if (ok && s->refine) {
        s->rsrc_cap = 16, s->rcap = 1;
        ok = (s->rsrc = gs__malloc(s->rsrc_cap, sizeof *s->rsrc)) && (s->rdist = gs__malloc(nv, sizeof *s->rdist));
    }
    return ok;
}

static void heat_destroy(void *state)
{
    heat_state *s = state;
    if (!s) return;
    free_own(s);
    if (!s->base) { /* the original: what its clones share too */
        free(s->vf_start), free(s->vf);
        free(s->itri), free(s->iopp), free(s->ilen), free(s->cot), free(s->area), free(s->dgeo);
        free(s->mass), free(s->comp), free(s->map_n), free(s->map_d), free(s->map_p);
        if (s->refine) gs_topo_free(&s->refined_t);
        free(s->rxyz), free(s->rtri);
    }
    free(s);
}

/* Subdivide t0 `levels` times into s->refined_t (arrays rxyz, rtri). */
static int refine_patch(heat_state *s, const gs_topo *t0, uint32_t levels, gs_error *err)
{
    const gs_topo *cur = t0;
    for (uint32_t l = 0; l < levels; ++l) {
        double *xyz;
        uint32_t *tri, nv, nf;
        int rc = gs__subdivide_arrays(cur, &nv, &xyz, &nf, &tri, err);
        if (l > 0) {
            gs_topo_free(&s->refined_t);
            free(s->rxyz), free(s->rtri);
            s->rxyz = NULL, s->rtri = NULL;
        }
        if (rc) return rc;
        s->rxyz = xyz, s->rtri = tri;
        rc = gs_topo_build(&s->refined_t, nv, xyz, nf, tri, GS_TOPO_ALLOW_NONMANIFOLD_VERTICES, NULL, err);
        if (rc) {
            free(s->rxyz), free(s->rtri);
            s->rxyz = NULL, s->rtri = NULL;
            return rc;
        }
        cur = &s->refined_t;
    }
    return GS_OK;
}

/* A source of the patch as a source of the refined mesh: a vertex keeps its
 * id; a point of face f lies in one of the four faces f becomes at each
 * level (a corner face if one of its coordinates is >= 1/2, else the
 * middle one), with coordinates relative to it; a point that lands on a
 * refined vertex becomes that vertex. */
static gs_source refine_source(const heat_state *s, const gs_source *in)
{
    if (in->face == GS_NONE) return *in;
    uint32_t f = in->face;
    double b0 = in->bary[0], b1 = in->bary[1], b2 = in->bary[2];
    for (uint32_t l = 0; l < s->refine; ++l) {
        uint32_t k;
        double c0, c1, c2;
        if (b0 >= 0.5) k = 0, c0 = 2 * b0 - 1, c1 = 2 * b1, c2 = 2 * b2;
        else if (b1 >= 0.5) k = 1, c0 = 2 * b0, c1 = 2 * b1 - 1, c2 = 2 * b2;
        else if (b2 >= 0.5) k = 2, c0 = 2 * b0, c1 = 2 * b1, c2 = 2 * b2 - 1;
        else k = 3, c0 = 1 - 2 * b2, c1 = 1 - 2 * b0, c2 = 1 - 2 * b1;
        double sum = c0 + c1 + c2;
        b0 = c0 / sum, b1 = c1 / sum, b2 = c2 / sum;
        f = 4 * f + k;
    }
    const uint32_t *c = s->rtri + 3 * (size_t)f;
    if (b0 == 1.0) return gs_source_vertex(c[0]);
    if (b1 == 1.0) return gs_source_vertex(c[1]);
    if (b2 == 1.0) return gs_source_vertex(c[2]);
    return gs_source_point(f, b0, b1, b2);
}

static int heat_create(const gs_topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    heat_state *s = calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory creating a heat solver");
    s->t0 = t;
    s->nv0 = t->nv;
    if (opt->heat_refine > 0) {
        int rc = refine_patch(s, t, opt->heat_refine, err);
        if (rc) {
            free(s);
            return rc;
        }
        s->refine = opt->heat_refine;
        t = &s->refined_t;
    }
    s->t = t;
    s->nv = t->nv;
    s->nf = t->nf;
    size_t nh = 3 * (size_t)t->nf, nv = t->nv ? t->nv : 1;
    s->itri = gs__malloc(nh + 1, sizeof *s->itri);
    s->iopp = gs__malloc(nh + 1, sizeof *s->iopp);
    s->ilen = gs__malloc(nh + 1, sizeof *s->ilen);
    s->cot = gs__malloc(nh + 1, sizeof *s->cot);
    s->area = gs__malloc(t->nf + 1, sizeof *s->area);
    s->dgeo = gs__malloc(12 * (size_t)t->nf + 1, sizeof *s->dgeo);
    s->mass = gs__malloc(nv, sizeof *s->mass);
    s->comp = gs__malloc(nv, sizeof *s->comp);
    s->map_n = gs__malloc(nv, sizeof *s->map_n);
    s->map_d = gs__malloc(nv, sizeof *s->map_d);
    s->map_p = gs__malloc(nv, sizeof *s->map_p);
    s->vf_start = gs__malloc(nv + 1, sizeof *s->vf_start);
    s->vf = gs__malloc(nh + 1, sizeof *s->vf);
    if (!s->itri || !s->iopp || !s->ilen || !s->cot || !s->area || !s->dgeo || !s->mass || !s->comp ||
        !s->map_n || !s->map_d || !s->map_p || !s->vf_start || !s->vf || !alloc_own(s)) {
        heat_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a heat solver");
    }
    /* mean edge length (each interior edge once) and t = h^2 */
    double sum = 0;
    uint64_t ne = 0;
    for (size_t h = 0; h < nh; ++h)
        if (t->opp[h] == GS_NONE || h < t->opp[h]) sum += t->len[h], ne++;
    s->h_mean = ne ? sum / (double)ne : 1.0;
    /* the time step's h: the mean edge length weighted by area (see the
     * header) */
    double area_sum = 0, hw = 0;
    for (uint32_t f = 0; f < t->nf; ++f) {
        const double *l = t->len + 3 * (size_t)f;
        double A = tri_area(l[0], l[1], l[2]);
        area_sum += A, hw += A * (l[0] + l[1] + l[2]) / 3;
    }
    s->h_time = area_sum > 0 ? hw / area_sum : s->h_mean;
    s->t_step = opt->heat_time * s->h_time * s->h_time;
    s->r_ball = HEAT_EXACT_START * s->h_mean;

    int rc = make_intrinsic_delaunay(s, err);
    if (rc) {
        heat_destroy(s);
        return rc;
    }
    build_geometry(s);
    build_divergence_geometry(s);
    /* intrinsic faces around each vertex */
    memset(s->vf_start, 0, ((size_t)s->nv + 1) * sizeof *s->vf_start);
    for (size_t h = 0; h < nh; ++h) s->vf_start[s->itri[h] + 1]++;
    for (uint32_t v = 0; v < s->nv; ++v) s->vf_start[v + 1] += s->vf_start[v];
    for (size_t h = 0; h < nh; ++h) s->vf[s->vf_start[s->itri[h]]++] = (uint32_t)(h / 3);
    for (uint32_t v = s->nv; v > 0; --v) s->vf_start[v] = s->vf_start[v - 1];
    s->vf_start[0] = 0;

    /* connected components (vertices sharing a face), union-find in comp */
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = v;
    for (uint32_t f = 0; f < s->nf; ++f) {
        uint32_t r0 = comp_find(s->comp, t->tri[3 * (size_t)f]);
        for (int i = 1; i < 3; ++i) {
            uint32_t r = comp_find(s->comp, t->tri[3 * (size_t)f + i]);
            if (r == r0) continue;
            uint32_t lo = r < r0 ? r : r0, hi = r < r0 ? r0 : r;
            s->comp[hi] = lo;
            r0 = lo;
        }
    }
    uint8_t *boundary = (uint8_t *)s->b; /* scratch: b holds 8*nv bytes */
    memset(boundary, 0, s->nv);
    for (size_t h = 0; h < nh; ++h)
        if (s->iopp[h] == GS_NONE) {
            boundary[s->itri[h]] = 1;
            boundary[s->itri[gs_next((uint32_t)h)]] = 1;
        }
    uint8_t *used = boundary + s->nv;
    memset(used, 0, s->nv);
    for (size_t h = 0; h < nh; ++h) used[t->tri[h]] = 1;
    uint32_t nn = 0, nd = 0, np = 0, nb = 0;
    /* unknowns: every referenced vertex (Neumann heat), the interior ones
     * (Dirichlet heat) */
    for (uint32_t v = 0; v < s->nv; ++v) {
        s->map_n[v] = s->map_d[v] = s->map_p[v] = GS_NONE;
        if (!used[v]) continue;
        s->map_n[v] = nn++;
        if (!boundary[v]) s->map_d[v] = nd++;
        else nb++;
    }
    /* compact component ids: roots are the smallest vertex of each set */
    uint32_t *cid = s->map_p; /* temporarily: root -> component id */
    for (uint32_t v = 0; v < s->nv; ++v) cid[v] = GS_NONE;
    s->n_comp = 0;
    for (uint32_t v = 0; v < s->nv; ++v) {
        if (!used[v]) continue;
        uint32_t r = comp_find(s->comp, v);
        if (cid[r] == GS_NONE) cid[r] = s->n_comp++;
    }
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = comp_find(s->comp, v);
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = used[v] ? cid[s->comp[v]] : GS_NONE;
    /* the Poisson pin of a component: its first vertex */
    uint8_t *pinned_comp = (uint8_t *)s->cmin; /* n_comp <= nv bytes */
    memset(pinned_comp, 0, s->nv);
    for (uint32_t v = 0; v < s->nv; ++v) {
        s->map_p[v] = GS_NONE;
        if (!used[v]) continue;
        if (!pinned_comp[s->comp[v]]) {
            pinned_comp[s->comp[v]] = 1;
            continue;
        }
        s->map_p[v] = np++;
    }

    gs_error e2 = {0, ""}, *e = err ? err : &e2;
    (void)nn, (void)nd, (void)np;
    double t2 = HEAT_T2_RATIO * s->t_step;
    s->heat_n = factor_system(s, s->map_n, 1.0, s->t_step, NULL, e);
    if (s->heat_n && nb > 0)
        s->heat_d = factor_system(s, s->map_d, 1.0, s->t_step, s->heat_n, e);
    if (s->heat_n && (nb == 0 || s->heat_d))
        s->heat_n2 = factor_system(s, s->map_n, 1.0, t2, s->heat_n, e);
    if (s->heat_n2 && nb > 0)
        s->heat_d2 = factor_system(s, s->map_d, 1.0, t2, s->heat_n, e);
    if (s->heat_n2 && (nb == 0 || s->heat_d2))
        s->poisson = factor_system(s, s->map_p, 0.0, 1.0, s->heat_n, e);
    if (!s->poisson) {
        heat_destroy(s);
        return e->status ? e->status : GS_EINTERNAL;
    }
    *state = s;
    return GS_OK;
}

/* A solver for another thread: the same fields, bit for bit, from base's
 * factorisations (views with their own workspace) and geometry; only the
 * work arrays are new. base must outlive it. */
static int heat_clone(const void *state, void **out, gs_error *err)
{
    const heat_state *src = state;
    heat_state *s = malloc(sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory cloning a heat solver");
    *s = *src;
    s->base = src->base ? src->base : src;
    s->heat_n = s->heat_d = s->poisson = s->heat_n2 = s->heat_d2 = NULL;
    s->b = s->x = s->u = s->w = s->div = s->phi = s->cmin = s->csum = NULL;
    s->kb = s->ku = s->kx = s->kw = NULL, s->kcap = 0;
    s->exact = NULL, s->edist = NULL, s->fmark = NULL, s->stamp = 0;
    s->ball_v = NULL, s->ball_d = NULL, s->ball_n = s->ball_cap = 0;
    s->rdist = NULL, s->rsrc = NULL, s->rcap = s->rsrc_cap = 0;
    if (!alloc_own(s)) {
        heat_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory cloning a heat solver");
    }
    gs_sparse_factor *const *from[5] = {&src->heat_n, &src->heat_d, &src->poisson, &src->heat_n2, &src->heat_d2};
    gs_sparse_factor **to[5] = {&s->heat_n, &s->heat_d, &s->poisson, &s->heat_n2, &s->heat_d2};
    for (int i = 0; i < 5; ++i)
        if (*from[i] && !(*to[i] = gs_sparse_factor_share(*from[i], err))) {
            heat_destroy(s);
            return err && err->status ? err->status : GS_ENOMEM;
        }
    *out = s;
    return GS_OK;
}

/* ---- solve -------------------------------------------------------------- */

/* Solve a system of factor_system: b on the free vertices of map, 0 on the
 * fixed ones; u (nv) receives the solution, 0 on the fixed vertices. */
static int heat_flow(heat_state *s, gs_sparse_factor *F, const uint32_t *map, const double *rhs,
                     double *u, gs_error *err)
{
    for (uint32_t v = 0; v < s->nv; ++v) s->x[v] = map[v] != GS_NONE ? rhs[v] : 0.0;
    int rc = gs_sparse_factor_solve(F, s->x, s->x, err);
    if (rc) return rc;
    for (uint32_t v = 0; v < s->nv; ++v) u[v] = map[v] != GS_NONE ? s->x[v] : 0.0;
    return GS_OK;
}

/* The potentials of a vertex from its heat values u (time t) and w (time
 * 4t): a = log u - log w and b = log w, NAN where undefined (u or w not a
 * normal positive number: a denormal has too few bits left for its
 * logarithm to give a direction). */
static void potentials(double u, double w, double *a, double *b)
{
    double lw = w >= DBL_MIN && w <= DBL_MAX ? log(w) : NAN;
    *b = lw;
    *a = u >= DBL_MIN && u <= DBL_MAX && !isnan(lw) ? log(u) - lw : NAN;
}

/* Unit direction of increasing distance X in a face (its 2D layout of
 * build_divergence_geometry, q) from the corner potentials: -grad a if the
 * three a are defined, else -grad b if the three b are; the gradient is
 * scaled by its largest component before normalising. Returns 0 if
 * neither (or a zero gradient): the face has no direction. */
static int face_direction(const double *q, const double a[3], const double b[3], double X[2])
{
    const double *p = a;
    if (isnan(a[0]) || isnan(a[1]) || isnan(a[2])) {
        if (isnan(b[0]) || isnan(b[1]) || isnan(b[2])) return 0;
        p = b;
    }
    double g0 = p[0] * q[0] + p[1] * q[2] + p[2] * q[4];
    double g1 = p[0] * q[1] + p[1] * q[3] + p[2] * q[5];
    double m = fmax(fabs(g0), fabs(g1));
    if (!(m > 0) || !isfinite(m)) return 0;
    g0 /= m, g1 /= m;
    double n = sqrt(g0 * g0 + g1 * g1);
    X[0] = -g0 / n, X[1] = -g1 / n;
    return 1;
}

/* Integrated divergence of X (face_direction) at every vertex, for k
 * fields at once stored vertex-major (A[v * k + c], B[v * k + c]: the
 * potentials a and b of field c at vertex v; div likewise): each face's
 * geometry is read once for all k. */
static void divergence(const heat_state *s, const double *A, const double *B, uint32_t k,
                       double *div)
{
    memset(div, 0, (size_t)s->nv * k * sizeof *div);
    for (uint32_t f = 0; f < s->nf; ++f) {
        if (!(s->area[f] > 0)) continue;
        const uint32_t *vi = s->itri + 3 * (size_t)f;
        const double *q = s->dgeo + 12 * (size_t)f;
        size_t i0 = (size_t)vi[0] * k, i1 = (size_t)vi[1] * k, i2 = (size_t)vi[2] * k;
        for (uint32_t i = 0; i < k; ++i) {
            double a[3] = {A[i0 + i], A[i1 + i], A[i2 + i]};
            double b[3] = {B[i0 + i], B[i1 + i], B[i2 + i]};
            double X[2];
            if (!face_direction(q, a, b, X)) continue;
            div[i0 + i] += q[6] * X[0] + q[7] * X[1];
            div[i1 + i] += q[8] * X[0] + q[9] * X[1];
            div[i2 + i] += q[10] * X[0] + q[11] * X[1];
        }
    }
}

/* The start ball of field c (of k, vertex-major A, B and div as in
 * divergence) for the sources src: every intrinsic face whose three
 * corners are within HEAT_EXACT_START mean edge lengths of the sources
 * (exact distances e) trades its heat direction's contribution to div for
 * that of grad e's linear interpolant, sum_i e_i * (rotated edge opposite
 * i) / (2 area). */
static int exact_start(heat_state *s, const gs_source *src, uint32_t n_src, const double *A,
                       const double *B, uint32_t k, uint32_t c, double *div, gs_error *err)
{
    const gs_topo *t = s->t;
    if (!s->exact) {
        int rc = gs_exact_ops.create(t, NULL, &s->exact, err);
        if (rc) return rc;
        s->edist = gs__malloc(s->nv ? s->nv : 1, sizeof *s->edist);
        s->fmark = gs__calloc(s->nf ? s->nf : 1, sizeof *s->fmark);
        if (!s->edist || !s->fmark)
            return gs__fail(err, GS_ENOMEM, "out of memory for the heat method's start ball");
    }
    double r = s->r_ball;
    gs_solve_stats es = {0, 0};
    int rc = gs_exact_ops.solve(s->exact, src, n_src, r, s->edist, &es, err);
    if (rc) return rc;
    if (++s->stamp == 0) { /* wrapped: clear the marks */
        memset(s->fmark, 0, s->nf * sizeof *s->fmark);
        s->stamp = 1;
    }
    const double *e = s->edist;
    for (uint32_t v = 0; v < s->nv; ++v) {
        if (!(e[v] <= r)) continue;
        if (s->ball_n == s->ball_cap) {
            uint32_t cap = s->ball_cap ? 2 * s->ball_cap : 256;
            uint32_t *bv = realloc(s->ball_v, cap * sizeof *bv);
            if (bv) s->ball_v = bv;
            double *bd = realloc(s->ball_d, cap * sizeof *bd);
            if (bd) s->ball_d = bd;
            if (!bv || !bd) return gs__fail(err, GS_ENOMEM, "out of memory for the heat method's start ball");
            s->ball_cap = cap;
        }
        s->ball_v[s->ball_n] = v;
        s->ball_d[s->ball_n++] = e[v];
        for (uint32_t j = s->vf_start[v]; j < s->vf_start[v + 1]; ++j) {
            uint32_t f = s->vf[j];
            if (s->fmark[f] == s->stamp) continue;
            s->fmark[f] = s->stamp;
            const uint32_t *wi = s->itri + 3 * (size_t)f;
            if (!(s->area[f] > 0) || !(e[wi[0]] <= r && e[wi[1]] <= r && e[wi[2]] <= r)) continue;
            const double *q = s->dgeo + 12 * (size_t)f;
            size_t i0 = (size_t)wi[0] * k + c, i1 = (size_t)wi[1] * k + c, i2 = (size_t)wi[2] * k + c;
            double a[3] = {A[i0], A[i1], A[i2]}, b[3] = {B[i0], B[i1], B[i2]}, X[2];
            if (face_direction(q, a, b, X)) {
                div[i0] -= q[6] * X[0] + q[7] * X[1];
                div[i1] -= q[8] * X[0] + q[9] * X[1];
                div[i2] -= q[10] * X[0] + q[11] * X[1];
            }
            double e0 = e[wi[0]], e1 = e[wi[1]], e2 = e[wi[2]], twice = 2 * s->area[f];
            X[0] = (e0 * q[0] + e1 * q[2] + e2 * q[4]) / twice;
            X[1] = (e0 * q[1] + e1 * q[3] + e2 * q[5]) / twice;
            div[i0] += q[6] * X[0] + q[7] * X[1];
            div[i1] += q[8] * X[0] + q[9] * X[1];
            div[i2] += q[10] * X[0] + q[11] * X[1];
        }
    }
    return GS_OK;
}

/* out[v * k + c] = in[c * nv + v] (column-major -> vertex-major) or back. */
static void transpose(const double *in, double *out, size_t nv, uint32_t k, int to_vertex_major)
{
    for (size_t v = 0; v < nv; ++v)
        for (uint32_t c = 0; c < k; ++c) {
            if (to_vertex_major)
                out[v * k + c] = in[c * nv + v];
            else
                out[c * nv + v] = in[v * k + c];
        }
}

/* dist = phi shifted per component (see the header): by the mean of phi -
 * e over the ball vertices bv, be (nb of them, exact distances e) that the
 * component holds, else so that its smallest value over the sources it
 * holds is 0. Vertex sources get 0, negative values 0; components without
 * a source +INFINITY. cmin and csum are scratch. */
static void shift_components(heat_state *s, const double *phi, const gs_source *src, uint32_t n_src,
                             const uint32_t *bv, const double *be, uint32_t nb, double *dist)
{
    const gs_topo *t = s->t;
    uint32_t nv = s->nv;
    double *sum = s->csum, *cnt = s->csum + s->n_comp;
    for (uint32_t c = 0; c < s->n_comp; ++c) s->cmin[c] = INFINITY, sum[c] = cnt[c] = 0;
    for (uint32_t i = 0; i < n_src; ++i) {
        double val;
        uint32_t c;
        if (src[i].face == GS_NONE) {
            val = phi[src[i].vertex];
            c = s->comp[src[i].vertex];
        } else {
            const uint32_t *fv = t->tri + 3 * (size_t)src[i].face;
            val = 0;
            for (int k = 0; k < 3; ++k) val += src[i].bary[k] * phi[fv[k]];
            c = s->comp[fv[0]];
        }
        if (c != GS_NONE && val < s->cmin[c]) s->cmin[c] = val;
    }
    for (uint32_t i = 0; i < nb; ++i) {
        uint32_t c = s->comp[bv[i]];
        if (c == GS_NONE || !isfinite(phi[bv[i]])) continue;
        sum[c] += phi[bv[i]] - be[i];
        cnt[c] += 1;
    }
    for (uint32_t c = 0; c < s->n_comp; ++c)
        if (isfinite(s->cmin[c]) && cnt[c] > 0) s->cmin[c] = sum[c] / cnt[c];
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t c = s->comp[v];
        double d = (c == GS_NONE || !isfinite(s->cmin[c])) ? INFINITY : phi[v] - s->cmin[c];
        if (!(d > 0)) d = isnan(d) ? INFINITY : 0.0;
        dist[v] = d;
    }
    for (uint32_t i = 0; i < n_src; ++i)
        if (src[i].face == GS_NONE) dist[src[i].vertex] = 0.0;
}

static int solve_one(heat_state *state, const gs_source *src, uint32_t n_src, double *dist,
                     gs_solve_stats *stats, gs_error *err)
{
    heat_state *s = state;
    const gs_topo *t = s->t;
    uint32_t nv = s->nv;
    /* delta: the sum of every source's unit impulse */
    memset(s->b, 0, nv * sizeof *s->b);
    for (uint32_t i = 0; i < n_src; ++i) {
        if (src[i].face == GS_NONE) {
            s->b[src[i].vertex] += 1.0;
            continue;
        }
        for (int k = 0; k < 3; ++k) s->b[t->tri[3 * (size_t)src[i].face + k]] += src[i].bary[k];
    }
    int rc = heat_flow(s, s->heat_n, s->map_n, s->b, s->u, err);
    if (!rc && s->heat_d) {
        rc = heat_flow(s, s->heat_d, s->map_d, s->b, s->phi, err);
        for (uint32_t v = 0; v < nv && !rc; ++v) s->u[v] = 0.5 * (s->u[v] + s->phi[v]);
    }
    if (!rc) rc = heat_flow(s, s->heat_n2, s->map_n, s->b, s->w, err);
    if (!rc && s->heat_d2) {
        rc = heat_flow(s, s->heat_d2, s->map_d, s->b, s->phi, err);
        for (uint32_t v = 0; v < nv && !rc; ++v) s->w[v] = 0.5 * (s->w[v] + s->phi[v]);
    }
    if (rc) return rc;
    for (uint32_t v = 0; v < nv; ++v) potentials(s->u[v], s->w[v], &s->u[v], &s->w[v]);
    divergence(s, s->u, s->w, 1, s->div);
    s->ball_n = 0;
    rc = exact_start(s, src, n_src, s->u, s->w, 1, 0, s->div, err);
    if (rc) return rc;
    /* L phi = -div on the free vertices of map_p (pins stay 0) */
    rc = heat_flow(s, s->poisson, s->map_p, s->div, s->phi, err);
    if (rc) return rc;
    for (uint32_t v = 0; v < nv; ++v) s->phi[v] = -s->phi[v];
    shift_components(s, s->phi, src, n_src, s->ball_v, s->ball_d, s->ball_n, dist);
    stats->windows_propagated += nv; /* vertices solved for (no windows here) */
    return GS_OK;
}

/* k systems of factor_system at once: out (nv x k, column-major) = the
 * solutions for the right-hand sides rhs (same layout; may alias out). */
static int heat_flow_many(heat_state *s, gs_sparse_factor *F, const uint32_t *map, const double *rhs,
                          double *out, uint32_t k, gs_error *err)
{
    size_t nv = s->nv;
    for (uint32_t c = 0; c < k; ++c)
        for (size_t v = 0; v < nv; ++v) out[c * nv + v] = map[v] != GS_NONE ? rhs[c * nv + v] : 0.0;
    int rc = gs_sparse_factor_solve_many(F, out, out, k, err);
    if (rc) return rc;
    for (uint32_t c = 0; c < k; ++c)
        for (size_t v = 0; v < nv; ++v)
            if (map[v] == GS_NONE) out[c * nv + v] = 0.0;
    return GS_OK;
}

/* One field per source (dist row i, nv doubles, for source i): the same
 * steps as heat_solve, each linear system solved for a batch of sources at
 * once. Equal to n single solves up to rounding. */
static int solve_each(heat_state *state, const gs_source *src, uint32_t n_src, double *dist,
                      gs_solve_stats *stats, gs_error *err)
{
    heat_state *s = state;
    const gs_topo *t = s->t;
    size_t nv = s->nv;
    uint32_t want = n_src < HEAT_BATCH ? n_src : HEAT_BATCH;
    if (want > s->kcap) {
        free(s->kb), free(s->ku), free(s->kx), free(s->kw);
        s->kcap = 0;
        s->kb = gs__malloc(nv * want + 1, sizeof *s->kb);
        s->ku = gs__malloc(nv * want + 1, sizeof *s->ku);
        s->kx = gs__malloc(nv * want + 1, sizeof *s->kx);
        s->kw = gs__malloc(nv * want + 1, sizeof *s->kw);
        if (!s->kb || !s->ku || !s->kx || !s->kw)
            return gs__fail(err, GS_ENOMEM, "out of memory for a batch of %u heat fields", want);
        s->kcap = want;
    }
    for (uint32_t i0 = 0; i0 < n_src; i0 += HEAT_BATCH) {
        uint32_t k = n_src - i0 < HEAT_BATCH ? n_src - i0 : HEAT_BATCH;
        memset(s->kb, 0, nv * k * sizeof *s->kb);
        for (uint32_t c = 0; c < k; ++c) {
            const gs_source *q = &src[i0 + c];
            double *b = s->kb + c * nv;
            if (q->face == GS_NONE)
                b[q->vertex] += 1.0;
            else
                for (int i = 0; i < 3; ++i) b[t->tri[3 * (size_t)q->face + i]] += q->bary[i];
        }
        /* ku = u (time t), kx = w (time 4t), kw scratch, kb = delta */
        int rc = heat_flow_many(s, s->heat_n, s->map_n, s->kb, s->ku, k, err);
        if (!rc && s->heat_d) {
            rc = heat_flow_many(s, s->heat_d, s->map_d, s->kb, s->kx, k, err);
            for (size_t v = 0; v < nv * k && !rc; ++v) s->ku[v] = 0.5 * (s->ku[v] + s->kx[v]);
        }
        if (!rc) rc = heat_flow_many(s, s->heat_n2, s->map_n, s->kb, s->kx, k, err);
        if (!rc && s->heat_d2) {
            rc = heat_flow_many(s, s->heat_d2, s->map_d, s->kb, s->kw, k, err);
            for (size_t v = 0; v < nv * k && !rc; ++v) s->kx[v] = 0.5 * (s->kx[v] + s->kw[v]);
        }
        if (rc) return rc;
        /* potentials (column-major, in place), then vertex-major copies:
         * kw = a, kb = b; divergence into ku (vertex-major), back to kx */
        for (size_t v = 0; v < nv * k; ++v) potentials(s->ku[v], s->kx[v], &s->ku[v], &s->kx[v]);
        transpose(s->ku, s->kw, nv, k, 1);
        transpose(s->kx, s->kb, nv, k, 1);
        divergence(s, s->kw, s->kb, k, s->ku);
        s->ball_n = 0;
        for (uint32_t c = 0; c < k; ++c) {
            s->ball_start[c] = s->ball_n;
            if ((rc = exact_start(s, &src[i0 + c], 1, s->kw, s->kb, k, c, s->ku, err))) return rc;
        }
        s->ball_start[k] = s->ball_n;
        transpose(s->ku, s->kx, nv, k, 0);
        rc = heat_flow_many(s, s->poisson, s->map_p, s->kx, s->kx, k, err);
        if (rc) return rc;
        for (uint32_t c = 0; c < k; ++c) {
            double *phi = s->kx + c * nv;
            for (size_t v = 0; v < nv; ++v) phi[v] = -phi[v];
            uint32_t b0 = s->ball_start[c], nb = s->ball_start[c + 1] - b0;
            shift_components(s, phi, &src[i0 + c], 1, s->ball_v + b0, s->ball_d + b0, nb,
                             dist + (size_t)(i0 + c) * nv);
        }
    }
    stats->windows_propagated += nv * n_src;
    return GS_OK;
}

/* Map n sources to the refined mesh (s->rsrc). */
static int map_sources(heat_state *s, const gs_source *src, uint32_t n, gs_error *err)
{
    if (n > s->rsrc_cap) {
        gs_source *p = gs__realloc(s->rsrc, n, sizeof *p);
        if (!p) return gs__fail(err, GS_ENOMEM, "out of memory for %u heat sources", n);
        s->rsrc = p, s->rsrc_cap = n;
    }
    for (uint32_t i = 0; i < n; ++i) s->rsrc[i] = refine_source(s, &src[i]);
    return GS_OK;
}

static int heat_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                      double *dist, gs_solve_stats *stats, gs_error *err)
{
    (void)max_d;
    heat_state *s = state;
    if (!s->refine) return solve_one(s, src, n_src, dist, stats, err);
    int rc = map_sources(s, src, n_src, err);
    if (!rc) rc = solve_one(s, s->rsrc, n_src, s->rdist, stats, err);
    if (!rc) memcpy(dist, s->rdist, s->nv0 * sizeof *dist);
    return rc;
}

static int heat_solve_each(void *state, const gs_source *src, uint32_t n_src, double *dist,
                           gs_solve_stats *stats, gs_error *err)
{
    heat_state *s = state;
    if (!s->refine) return solve_each(s, src, n_src, dist, stats, err);
    uint32_t want = n_src < HEAT_BATCH ? n_src : HEAT_BATCH;
    if (want > s->rcap) {
        free(s->rdist);
        s->rcap = 0;
        s->rdist = gs__malloc((size_t)s->nv * want + 1, sizeof *s->rdist);
        if (!s->rdist) return gs__fail(err, GS_ENOMEM, "out of memory for a batch of %u heat fields", want);
        s->rcap = want;
    }
    int rc = map_sources(s, src, n_src, err);
    for (uint32_t i0 = 0; i0 < n_src && !rc; i0 += HEAT_BATCH) {
        uint32_t k = n_src - i0 < HEAT_BATCH ? n_src - i0 : HEAT_BATCH;
        rc = solve_each(s, s->rsrc + i0, k, s->rdist, stats, err);
        for (uint32_t c = 0; c < k && !rc; ++c)
            memcpy(dist + (size_t)(i0 + c) * s->nv0, s->rdist + (size_t)c * s->nv, s->nv0 * sizeof *dist);
    }
    return rc;
}

const gs_method_ops gs_heat_ops = {"heat", heat_create, heat_destroy, heat_solve, heat_solve_each, heat_clone};
