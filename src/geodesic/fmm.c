/* fmm.c - first-order fast marching on triangle meshes (Kimmel & Sethian
 * 1998, "Computing geodesic paths on manifolds").
 *
 * Vertices are accepted in increasing order of their tentative distance
 * (a narrow band kept in an indexed min-heap, like Dijkstra). When a vertex
 * X is accepted, every face around X is revisited: each of its two other
 * corners C that is not yet accepted gets
 *   - the edge updates d_A + |AC| from its accepted neighbours A, and
 *   - the triangle update, computed in the plane of the triangle from the
 *     values d_A, d_B at its two other (accepted) corners. Kimmel-Sethian's
 *     update is the plane wave taking the values d_A, d_B; it is used only
 *     when its upwind direction at C lies inside the triangle (the
 *     back-traced characteristic through C crosses the segment AB),
 *     otherwise only the edge updates apply. This faithful first-order
 *     scheme is the default: it practically never underestimates (min
 *     FMM/exact >= 0.97 on all shared meshes), mean error 0.6-1.9%.
 *     Variant (build with -DFMM_POINT_SOURCE=1): a circular instead of a
 *     planar wavefront where possible, i.e. the virtual point source S with
 *     |SA| = d_A, |SB| = d_B on the far side of AB gives d_C = |SC| when the
 *     segment SC crosses AB (else the plane wave). It is exact on flat
 *     regions and 3-5x more accurate on average (0.13-0.6% on the shared
 *     meshes) but underestimates by up to ~4% where fronts that passed on
 *     both sides of a convex vertex meet (sphere:3, fandisk's sharp edges).
 *   - Triangle updates only combine corners reached by the same source's
 *     front (a per-vertex source label), so colliding fronts of several
 *     sources are never mixed into one (meaningless) wavefront.
 *
 * Obtuse corners (Kimmel & Sethian, section 4): an update through an obtuse
 * angle at C is not consistent. At create time, for every obtuse corner C of
 * a face (A, B the other corners) we unfold the faces beyond the edge AB into
 * the plane of the face, one at a time (at most MAX_UNFOLD faces, always
 * crossing the edge that the "acute section" of C's angle passes through),
 * until a vertex W appears inside the section, i.e. with both angles ACW and
 * WCB <= 90 degrees. The corner is then updated through the two virtual
 * acute triangles (C, A, W) and (C, W, B), with the planar (unfolded)
 * lengths |CW|, |AW|, |BW|. If the search fails (boundary, unfolded strip
 * not convex, MAX_UNFOLD reached) the plain triangle update is used.
 * Because W is not adjacent to C, every vertex keeps the list of corners
 * that use it as virtual vertex, so that its acceptance triggers them.
 *
 * Monotonicity: every triangle update is clamped below by max(d_A, d_B)
 * (causality), so a value only depends on smaller or equal values; hence
 * max_distance can simply stop the march.
 *
 * Safety: values are never NaN; when there are at most EUCLID_CLAMP_MAX
 * sources, every value is finally raised to at least the Euclidean distance
 * to the nearest source (a true lower bound of the geodesic distance), which
 * only removes rare underestimates of the approximation (unfolded lengths on
 * curved strips, bow-tie vertices). */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_UNFOLD 10
#define EUCLID_CLAMP_MAX 64
#ifndef FMM_POINT_SOURCE
#define FMM_POINT_SOURCE 0
#endif

typedef struct fmm_state {
    const gs__topo *t;
    gs__iheap heap;
    uint8_t *alive;    /* nv: 1 once accepted                                */
    uint32_t *label;   /* nv: index of the source whose front set dist[v]   */
    /* obtuse corners: virtual vertex and planar lengths (per corner h)      */
    uint32_t *virt;    /* 3nf: W or GS_NONE                                  */
    double *vlen;      /* 3*3nf: |CW|, |AW|, |BW| (C = tri[h], A = tri[next h], B = tri[prev h]) */
    uint32_t *rv_start;/* nv+1: CSR, corners whose virtual vertex is v       */
    uint32_t *rv;
    uint64_t n_virtual;/* obtuse corners with a virtual vertex               */
    uint64_t n_obtuse;
    double init_radius;/* exact start: ball radius (0: off)                 */
    void *exact;       /* exact solver for the start ball (lazily created)   */
    double *edist;     /* nv: its distances                                  */
} fmm_state;

/* ---- geometry ------------------------------------------------------------- */

/* Place a point at distances r1 from p and r2 from q, on the side of line pq
 * away from the origin. Returns 0 on a degenerate edge. */
static int place(const double p[2], const double q[2], double r1, double r2, double out[2])
{
    double ux = q[0] - p[0], uy = q[1] - p[1];
    double L = sqrt(ux * ux + uy * uy);
    if (!(L > 0) || !isfinite(L)) return 0;
    ux /= L;
    uy /= L;
    double along = (r1 * r1 - r2 * r2 + L * L) / (2 * L);
    double h2 = r1 * r1 - along * along;
    double h = h2 > 0 ? sqrt(h2) : 0.0;
    double nx = -uy, ny = ux;
    if (nx * p[0] + ny * p[1] < 0) { /* normal must point away from origin */
        nx = -nx;
        ny = -ny;
    }
    out[0] = p[0] + along * ux + h * nx;
    out[1] = p[1] + along * uy + h * ny;
    return isfinite(out[0]) && isfinite(out[1]);
}

/* Unfolding search for the obtuse corner hc (see the file comment). */
static uint32_t find_virtual(const gs__topo *t, uint32_t hc, double out_len[3])
{
    const double half_pi = 0.5 * M_PI;
    double theta = t->angle[hc];
    uint32_t c = t->tri[hc];
    double a_pos[2] = {t->len[hc], 0.0};
    double lb = t->len[gs__prev(hc)];
    double b_pos[2] = {lb * cos(theta), lb * sin(theta)};
    double lo = theta - half_pi, hi = half_pi; /* the acute section */
    /* current edge e runs from P to Q (directions phi_p < phi_q) */
    uint32_t e = gs__next(hc);
    double p[2] = {a_pos[0], a_pos[1]}, q[2] = {b_pos[0], b_pos[1]};
    double phi_p = 0.0, phi_q = theta;
    for (int k = 0; k < MAX_UNFOLD; ++k) {
        uint32_t tw = t->opp[e];
        if (tw == GS_NONE) return GS_NONE;
        if (t->tri[tw] != t->tri[gs__next(e)] || t->tri[gs__next(tw)] != t->tri[e]) return GS_NONE;
        uint32_t d = t->tri[gs__prev(tw)];
        double dp[2];
        if (!place(p, q, t->len[gs__next(tw)], t->len[gs__prev(tw)], dp)) return GS_NONE;
        double phi = atan2(dp[1], dp[0]);
        if (!(phi > phi_p && phi < phi_q)) return GS_NONE; /* strip not convex */
        if (d == c) return GS_NONE;
        if (phi >= lo && phi <= hi) {
            double r = sqrt(dp[0] * dp[0] + dp[1] * dp[1]);
            double ax = dp[0] - a_pos[0], ay = dp[1] - a_pos[1];
            double bx = dp[0] - b_pos[0], by = dp[1] - b_pos[1];
            out_len[0] = r;
            out_len[1] = sqrt(ax * ax + ay * ay);
            out_len[2] = sqrt(bx * bx + by * by);
            if (!(r > 0) || !(out_len[1] > 0) || !(out_len[2] > 0)) return GS_NONE;
            if (d == t->tri[gs__next(hc)] || d == t->tri[gs__prev(hc)]) return GS_NONE;
            return d;
        }
        if (phi < lo) { /* the section lies between D and Q: cross D->Q */
            e = gs__prev(tw);
            p[0] = dp[0];
            p[1] = dp[1];
            phi_p = phi;
        } else { /* between P and D: cross P->D */
            e = gs__next(tw);
            q[0] = dp[0];
            q[1] = dp[1];
            phi_q = phi;
        }
    }
    return GS_NONE;
}

/* Plane-wave update of C from A, B with values da, db; c = |AB|, b = |AC|,
 * a = |BC|. Returns +INFINITY when the upwind direction is not inside the
 * triangle (or the triangle is degenerate). */
static double tri_update(double da, double db, double c, double b, double a)
{
    if (!(c > 0) || !(b > 0) || !(a > 0)) return INFINITY;
    double u = db - da;
    if (!(fabs(u) < c)) return INFINITY;
    double cx = (b * b - a * a + c * c) / (2 * c);
    double cy2 = b * b - cx * cx;
    if (!(cy2 > 0)) return INFINITY;
    double cy = sqrt(cy2);
    double nx = u / c, ny = sqrt(1 - nx * nx);
    if (!(ny > 0)) return INFINITY;
    /* back-trace the characteristic from C to the line AB */
    double x = cx - cy * nx / ny;
    double tol = 1e-12 * c;
    if (x < -tol || x > c + tol) return INFINITY;
    double dc = da + nx * cx + ny * cy;
#if FMM_POINT_SOURCE
    /* circular wavefront: the virtual point source S with |SA| = da,
     * |SB| = db on the far side of AB; used when S exists and the segment
     * SC crosses AB (otherwise the plane wave above) */
    if (da + db > c) {
        double sx = (da * da - db * db + c * c) / (2 * c);
        double sy2 = da * da - sx * sx;
        if (sy2 >= 0) {
            double sy = -sqrt(sy2);
            double tcut = -sy / (cy - sy);
            double xc = sx + tcut * (cx - sx);
            if (xc >= -tol && xc <= c + tol) {
                double ex = cx - sx, ey = cy - sy;
                dc = sqrt(ex * ex + ey * ey);
            }
        }
    }
#endif
    double lo = da > db ? da : db;
    if (!(dc >= lo)) dc = lo; /* causality; also maps NaN to lo */
    return dc;
}

/* ---- state ------------------------------------------------------------------ */

static void fmm_destroy(void *state)
{
    fmm_state *s = state;
    if (!s) return;
    gs__iheap_free(&s->heap);
    free(s->alive);
    free(s->label);
    free(s->virt);
    free(s->vlen);
    free(s->rv_start);
    free(s->rv);
    if (s->exact) gs__exact_ops.destroy(s->exact);
    free(s->edist);
    free(s);
}

static int fmm_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    fmm_state *s = calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory creating a fast-marching solver");
    s->t = t;
    size_t nc = 3 * (size_t)t->nf;
    int bad = gs__iheap_init(&s->heap, t->nv);
    s->alive = calloc(t->nv ? t->nv : 1, 1);
    s->label = calloc(t->nv ? t->nv : 1, sizeof *s->label);
    s->virt = malloc((nc ? nc : 1) * sizeof *s->virt);
    s->vlen = malloc((nc ? 3 * nc : 1) * sizeof *s->vlen);
    s->rv_start = calloc((size_t)t->nv + 1, sizeof *s->rv_start);
    if (bad || !s->alive || !s->label || !s->virt || !s->vlen || !s->rv_start) {
        fmm_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a fast-marching solver");
    }
    for (size_t h = 0; h < nc; ++h) {
        s->virt[h] = GS_NONE;
        if (!(t->angle[h] > 0.5 * M_PI)) continue;
        s->n_obtuse++;
        uint32_t w = find_virtual(t, (uint32_t)h, s->vlen + 3 * h);
        s->virt[h] = w;
        if (w != GS_NONE) {
            s->n_virtual++;
            s->rv_start[w + 1]++;
        }
    }
    for (uint32_t v = 0; v < t->nv; ++v) s->rv_start[v + 1] += s->rv_start[v];
    s->rv = malloc((s->n_virtual ? s->n_virtual : 1) * sizeof *s->rv);
    if (!s->rv) {
        fmm_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a fast-marching solver");
    }
    /* fill (using rv_start as cursors, then shift back) */
    for (size_t h = 0; h < nc; ++h)
        if (s->virt[h] != GS_NONE) s->rv[s->rv_start[s->virt[h]]++] = (uint32_t)h;
    for (uint32_t v = t->nv; v > 0; --v) s->rv_start[v] = s->rv_start[v - 1];
    s->rv_start[0] = 0;
    double hsum = 0;
    uint64_t nh = 0;
    for (size_t h = 0; h < nc; ++h) hsum += t->len[h], ++nh;
    s->init_radius = (nh ? hsum / nh : 0) * opt->fmm_exact_start;
    *state = s;
    return GS_OK;
}

/* ---- solve ------------------------------------------------------------------ */

static void relax(fmm_state *s, double *dist, uint32_t v, double d, double max_d, uint32_t lab)
{
    if (s->alive[v] == 2) return; /* exact start value: final */
    if (d < dist[v] && d <= max_d) {
        dist[v] = d;
        s->label[v] = lab;
        gs__iheap_push_or_decrease(&s->heap, v, d);
    }
}

/* Triangle update(s) of the corner hc (whose vertex is not accepted). Only
 * corners reached by the same source's front are combined (labels): mixing
 * two fronts in one update has no meaning and can underestimate. */
static void update_corner(fmm_state *s, double *dist, uint32_t hc, double max_d)
{
    const gs__topo *t = s->t;
    uint32_t c = t->tri[hc], a = t->tri[gs__next(hc)], b = t->tri[gs__prev(hc)];
    const uint32_t *lab = s->label;
    double best = INFINITY;
    uint32_t best_lab = 0;
    uint32_t w = s->virt[hc];
    if (w != GS_NONE) {
        const double *vl = s->vlen + 3 * (size_t)hc; /* |CW|, |AW|, |BW| */
        if (s->alive[w]) {
            if (s->alive[a] && lab[a] == lab[w]) {
                double d = tri_update(dist[a], dist[w], vl[1], t->len[hc], vl[0]);
                if (d < best) best = d;
            }
            if (s->alive[b] && lab[b] == lab[w]) {
                double d = tri_update(dist[w], dist[b], vl[2], vl[0], t->len[gs__prev(hc)]);
                if (d < best) best = d;
            }
            double d = dist[w] + vl[0]; /* edge update along the virtual edge */
            if (d < best) best = d;
            best_lab = lab[w];
        }
    } else if (s->alive[a] && s->alive[b] && lab[a] == lab[b]) {
        double d = tri_update(dist[a], dist[b], t->len[gs__next(hc)], t->len[hc], t->len[gs__prev(hc)]);
        if (d < best) best = d;
        best_lab = lab[a];
    }
    if (best < INFINITY) relax(s, dist, c, best, max_d, best_lab);
}

static int fmm_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                     double *dist, gs__solve_stats *stats, gs_error *err)
{
    (void)err;
    fmm_state *s = state;
    const gs__topo *t = s->t;
    for (uint32_t v = 0; v < t->nv; ++v) dist[v] = INFINITY;
    memset(s->alive, 0, t->nv);
    gs__iheap_clear(&s->heap);
    for (uint32_t i = 0; i < n_src; ++i) {
        uint32_t sv[3];
        double sd[3];
        uint32_t ns = gs__source_seeds(t, &src[i], sv, sd);
        for (uint32_t k = 0; k < ns; ++k) relax(s, dist, sv[k], sd[k], max_d, i);
    }
    if (s->init_radius > 0) {
        if (!s->exact) {
            int rc = gs__exact_ops.create(t, NULL, &s->exact, err);
            if (rc) return rc;
            s->edist = malloc((t->nv ? t->nv : 1) * sizeof *s->edist);
            if (!s->edist) return gs__fail(err, GS_ENOMEM, "out of memory");
        }
        double r = s->init_radius < max_d ? s->init_radius : max_d;
        gs__solve_stats es = {0, 0}; /* the march's own statistics only */
        int rc = gs__exact_ops.solve(s->exact, src, n_src, r, s->edist, &es, err);
        if (rc) return rc;
        for (uint32_t v = 0; v < t->nv; ++v) {
            if (!(s->edist[v] <= r)) continue;
            uint32_t lab = 0;
            if (n_src > 1) { /* the nearest source in space labels the ball */
                double best = INFINITY, p[3];
                const double *q = t->xyz + 3 * (size_t)v;
                for (uint32_t i = 0; i < n_src; ++i) {
                    if (src[i].face == GS_NONE) memcpy(p, t->xyz + 3 * (size_t)src[i].vertex, sizeof p);
                    else gs__source_position(t, &src[i], p);
                    double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2], e = dx * dx + dy * dy + dz * dz;
                    if (e < best) best = e, lab = i;
                }
            }
            dist[v] = s->edist[v];
            s->label[v] = lab;
            gs__iheap_push_or_decrease(&s->heap, v, dist[v]);
            s->alive[v] = 2;
        }
    }
    while (s->heap.n) {
        double d;
        uint32_t x = gs__iheap_pop(&s->heap, &d);
        s->alive[x] = 1;
        stats->windows_propagated++;
        for (uint32_t k = t->vc_start[x]; k < t->vc_start[x + 1]; ++k) {
            uint32_t h = t->vc[k];
            uint32_t hn = gs__next(h), hp = gs__prev(h);
            uint32_t y = t->tri[hn], z = t->tri[hp];
            if (!s->alive[y]) {
                relax(s, dist, y, d + t->len[h], max_d, s->label[x]);
                update_corner(s, dist, hn, max_d);
            }
            if (!s->alive[z]) {
                relax(s, dist, z, d + t->len[hp], max_d, s->label[x]);
                update_corner(s, dist, hp, max_d);
            }
        }
        for (uint32_t k = s->rv_start[x]; k < s->rv_start[x + 1]; ++k) {
            uint32_t hc = s->rv[k];
            if (!s->alive[t->tri[hc]]) update_corner(s, dist, hc, max_d);
        }
    }
    /* raise to the Euclidean lower bound (see the file comment) */
    if (n_src <= EUCLID_CLAMP_MAX) {
        double pos[EUCLID_CLAMP_MAX][3];
        for (uint32_t i = 0; i < n_src; ++i) {
            if (src[i].face == GS_NONE)
                memcpy(pos[i], t->xyz + 3 * (size_t)src[i].vertex, sizeof pos[i]);
            else
                gs__source_position(t, &src[i], pos[i]);
        }
        for (uint32_t v = 0; v < t->nv; ++v) {
            if (!(dist[v] < INFINITY)) continue;
            const double *q = t->xyz + 3 * (size_t)v;
            double lb2 = INFINITY;
            for (uint32_t i = 0; i < n_src; ++i) {
                double dx = q[0] - pos[i][0], dy = q[1] - pos[i][1], dz = q[2] - pos[i][2];
                double e2 = dx * dx + dy * dy + dz * dz;
                if (e2 < lb2) lb2 = e2;
            }
            double lb = sqrt(lb2);
            if (dist[v] < lb) dist[v] = lb;
        }
    }
    return GS_OK;
}

const gs__method_ops gs__fmm_ops = {"fmm", fmm_create, fmm_destroy, fmm_solve, NULL, NULL};
