/* heat.c - the heat method's solves: heat flows, the unit directions and
 * their divergence, the exact start ball, the Poisson solve and the shifts,
 * one field or a batch at a time (the method: heat_internal.h). */
#include "heat_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- solve -------------------------------------------------------------- */

/* Solve a system of factor_system: b on the free vertices of map, 0 on the
 * fixed ones; u (nv) receives the solution, 0 on the fixed vertices. */
static int heat_flow(heat_state *s, gs__sparse_factor *F, const uint32_t *map, const double *rhs,
                     double *u, gs_error *err)
{
    for (uint32_t v = 0; v < s->nv; ++v) s->x[v] = map[v] != GS_NONE ? rhs[v] : 0.0;
    int rc = gs__sparse_factor_solve(F, s->x, s->x, err);
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
    const gs__topo *t = s->t;
    if (!s->exact) {
        int rc = gs__exact_ops.create(t, NULL, &s->exact, err);
        if (rc) return rc;
        s->edist = gs__malloc(s->nv ? s->nv : 1, sizeof *s->edist);
        s->fmark = gs__calloc(s->nf ? s->nf : 1, sizeof *s->fmark);
        if (!s->edist || !s->fmark)
            return gs__fail(err, GS_ENOMEM, "out of memory for the heat method's start ball");
    }
    double r = s->r_ball;
    gs__solve_stats es = {0, 0};
    int rc = gs__exact_ops.solve(s->exact, src, n_src, r, s->edist, &es, err);
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

/* dist = phi shifted per component (see heat_internal.h): by the mean of phi -
 * e over the ball vertices bv, be (nb of them, exact distances e) that the
 * component holds, else so that its smallest value over the sources it
 * holds is 0. Vertex sources get 0, negative values 0; components without
 * a source +INFINITY. cmin and csum are scratch. */
static void shift_components(heat_state *s, const double *phi, const gs_source *src, uint32_t n_src,
                             const uint32_t *bv, const double *be, uint32_t nb, double *dist)
{
    const gs__topo *t = s->t;
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
                     gs__solve_stats *stats, gs_error *err)
{
    heat_state *s = state;
    const gs__topo *t = s->t;
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
static int heat_flow_many(heat_state *s, gs__sparse_factor *F, const uint32_t *map, const double *rhs,
                          double *out, uint32_t k, gs_error *err)
{
    size_t nv = s->nv;
    for (uint32_t c = 0; c < k; ++c)
        for (size_t v = 0; v < nv; ++v) out[c * nv + v] = map[v] != GS_NONE ? rhs[c * nv + v] : 0.0;
    int rc = gs__sparse_factor_solve_many(F, out, out, k, err);
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
                      gs__solve_stats *stats, gs_error *err)
{
    heat_state *s = state;
    const gs__topo *t = s->t;
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


static int heat_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                      double *dist, gs__solve_stats *stats, gs_error *err)
{
    (void)max_d;
    heat_state *s = state;
    if (!s->refine) return solve_one(s, src, n_src, dist, stats, err);
    int rc = gs__heat_map_sources(s, src, n_src, err);
    if (!rc) rc = solve_one(s, s->rsrc, n_src, s->rdist, stats, err);
    if (!rc) memcpy(dist, s->rdist, s->nv0 * sizeof *dist);
    return rc;
}

static int heat_solve_each(void *state, const gs_source *src, uint32_t n_src, double *dist,
                           gs__solve_stats *stats, gs_error *err)
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
    int rc = gs__heat_map_sources(s, src, n_src, err);
    for (uint32_t i0 = 0; i0 < n_src && !rc; i0 += HEAT_BATCH) {
        uint32_t k = n_src - i0 < HEAT_BATCH ? n_src - i0 : HEAT_BATCH;
        rc = solve_each(s, s->rsrc + i0, k, s->rdist, stats, err);
        for (uint32_t c = 0; c < k && !rc; ++c)
            memcpy(dist + (size_t)(i0 + c) * s->nv0, s->rdist + (size_t)c * s->nv, s->nv0 * sizeof *dist);
    }
    return rc;
}

const gs__method_ops gs__heat_ops = {"heat", gs__heat_create, gs__heat_destroy, heat_solve,
                                 heat_solve_each, gs__heat_clone};
