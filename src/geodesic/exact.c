/* exact.c - GS_METHOD_EXACT: exact polyhedral geodesic distances by window
 * propagation (MMP/ICH family), processed triangle by triangle in order of
 * distance (as in VTP), with sound pruning by the current vertex distances. */
/*
 * Model. A window lives on a half-edge h and carries a family of straight
 * rays that enter face h/3 through the interval [b0, b1] of h. Coordinates
 * are local to h: tri[h] at (0,0), tri[next(h)] at (len,0), the face h/3 on
 * the side y > 0; the (pseudo-)source the rays come from is (sx, sy) with
 * sy <= 0, at surface distance sigma from the nearest source. The distance
 * at a point q of the window is sigma + |q - (sx,sy)|.
 *
 * Propagation. Faces wait in a min-heap keyed by the smallest distance of the
 * windows pending on their half-edges. Popping a face consumes all of them:
 *   1. every window that sees the opposite vertex updates its distance;
 *   2. every window is split at the ray through the opposite vertex into at
 *      most two children, one per other edge, expressed in the frames of the
 *      twin half-edges and queued on the neighbouring faces.
 * A window is trimmed when it is created against the current distances of
 * the two end vertices of its edge (exact: sigma + |q - s| - d(v) - |q - v|
 * is monotone along the edge, so each end vertex cuts off one end).
 * Vertices where geodesics can bend (saddles: total angle > 2 pi; boundary
 * and non-manifold vertices) become pseudo-sources: they sit in a second
 * heap keyed by distance and, when popped, emit windows on the opposite
 * edges of their faces, but only into the directions at an angle >= pi
 * (both ways round) from the one their shortest path arrived from: every
 * other direction can be shortcut inside the star of the vertex (the shadow
 * rule of MMP). Vertex sources emit everything at distance 0; a surface
 * point source emits windows on the twins of its face's edges.
 *
 * Soundness. Every vertex distance is the length of a real path, so a part
 * of a window that is beaten by d(v) + |q - v| by more than a relative
 * tolerance cannot carry a shortest path and may be dropped; parts that tie
 * are kept. Pruning is therefore independent of the processing order, which
 * only affects speed. Distances are never below the exact ones beyond
 * rounding (coverage slack of 1e-10 edge lengths changes a distance by a
 * second-order amount only).
 */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* relative tolerance in distance comparisons: a window is pruned only where
 * it is beaten by more than TOL_REL * distance (rounding is ~1e-14) */
#define TOL_REL 1e-11
/* slack, in edge lengths, when deciding that a window covers a vertex */
#define COVER_REL 1e-10
/* slack, in radians, on the directions a pseudo-source must serve */
#define ANGLE_SLACK 1e-9

/* The most window propagations of one solve: base + per face (see ex_solve). */
#define EX_MAX_WINDOWS_BASE 10000000ull
#define EX_MAX_WINDOWS_PER_FACE 10000ull

typedef struct ex_win {
    double b0, b1; /* interval on the half-edge, 0 <= b0 <= b1 <= len     */
    double sx, sy; /* pseudo-source in the half-edge frame, sy <= 0       */
    double sigma;  /* distance of the pseudo-source                       */
    uint32_t next; /* next window pending on the same half-edge / free list */
    uint32_t tag;  /* index of the surface-point source its rays come from, */
                   /* GS_NONE when they come from a vertex (for paths)     */
} ex_win;

typedef struct ex_state {
    const gs__topo *t;
    uint32_t nv, nf;
    double *hl, *hc, *hs; /* per half-edge: length, cos and sin of the corner */
    uint8_t *pseudo;      /* per vertex: geodesics may bend here             */
    double *off;          /* per corner: angle of its first edge in its fan  */
    uint32_t *fan;        /* per corner: first corner of its fan             */
    double *ftot;         /* per fan (first corner): total angle             */
    uint8_t *fclosed;     /* per fan (first corner): 1 if it closes up       */
    uint32_t *in_c;       /* per vertex: corner its best path arrived in     */
    double *in_a;         /* per vertex: angle of that path in the corner    */
    uint32_t *head;       /* per half-edge: pending windows                  */
    double *fired;        /* per vertex: distance it last emitted windows at */
    ex_win *win;          /* window pool                                     */
    uint32_t n_win, cap_win, free_win;
    gs__iheap fheap, vheap;
    /* what the last solve's vertex distances came from (path.c backtracks
     * through it; gs__exact_trace in geodesic_internal.h) */
    gs__exact_trace tr;
    uint32_t src_cap;
    uint32_t tface; /* face of the target point of the next solves, or GS_NONE */
    int has_goal;   /* the next solves need only paths to goal within max_d */
    double goal[3];
    /* local solves (gs__exact_solve_local): what the last one touched */
    uint32_t *tv, ntv;    /* vertices given a distance                        */
    uint32_t *th, nth;    /* half-edges given windows                         */
    uint8_t *hmark;       /* per half-edge: listed in th                      */
    int local_clean;      /* state arrays reset but for tv / th               */
    int direct_only;      /* local solves: no pseudo-source windows           */
    /* per solve */
    double *d;
    double max_d;
    int oom;
    uint64_t created, propagated;
} ex_state;

static void ex_destroy(void *state)
{
    ex_state *s = state;
    if (!s) return;
    free(s->hl);
    free(s->hc);
    free(s->hs);
    free(s->pseudo);
    free(s->off);
    free(s->fan);
    free(s->ftot);
    free(s->fclosed);
    free(s->in_c);
    free(s->in_a);
    free(s->head);
    free(s->fired);
    free(s->win);
    free(s->tv);
    free(s->th);
    free(s->hmark);
    free(s->tr.kind);
    free(s->tr.ref);
    free(s->tr.tag);
    free(s->tr.sxy);
    free(s->tr.dist);
    free(s->tr.src);
    gs__iheap_free(&s->fheap);
    gs__iheap_free(&s->vheap);
    free(s);
}

static int ex_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    (void)opt;
    ex_state *s = gs__calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory creating an exact solver");
    s->t = t;
    s->nv = t->nv;
    s->nf = t->nf;
    size_t nh = 3 * (size_t)t->nf;
    s->hl = gs__malloc(nh, sizeof *s->hl);
    s->hc = gs__malloc(nh, sizeof *s->hc);
    s->hs = gs__malloc(nh, sizeof *s->hs);
    s->pseudo = gs__malloc(t->nv, 1);
    s->head = gs__malloc(nh, sizeof *s->head);
    s->fired = gs__malloc(t->nv, sizeof *s->fired);
    s->off = gs__malloc(nh, sizeof *s->off);
    s->fan = gs__malloc(nh, sizeof *s->fan);
    s->ftot = gs__malloc(nh, sizeof *s->ftot);
    s->fclosed = gs__malloc(nh, 1);
    s->in_c = gs__malloc(t->nv, sizeof *s->in_c);
    s->in_a = gs__malloc(t->nv, sizeof *s->in_a);
    s->tr.kind = gs__malloc(t->nv, 1);
    s->tr.ref = gs__malloc(t->nv, sizeof *s->tr.ref);
    s->tr.tag = gs__malloc(t->nv, sizeof *s->tr.tag);
    s->tr.sxy = gs__malloc(2 * (size_t)t->nv, sizeof *s->tr.sxy);
    s->tr.dist = gs__malloc(t->nv, sizeof *s->tr.dist);
    s->tr.target.face = GS_NONE;
    s->tface = GS_NONE;
    s->cap_win = 1024;
    s->win = gs__malloc(s->cap_win, sizeof *s->win);
    int hf = gs__iheap_init(&s->fheap, t->nf);
    int hv = gs__iheap_init(&s->vheap, t->nv);
    if (!s->hl || !s->hc || !s->hs || !s->pseudo || !s->head || !s->fired || !s->win || hf ||
        hv || !s->off || !s->fan || !s->ftot || !s->fclosed || !s->in_c || !s->in_a || !s->tr.kind ||
        !s->tr.ref || !s->tr.tag || !s->tr.sxy || !s->tr.dist) {
        ex_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating an exact solver");
    }
    for (size_t h = 0; h < nh; ++h) {
        s->hl[h] = t->len[h];
        s->hc[h] = cos(t->angle[h]);
        s->hs[h] = sin(t->angle[h]);
        s->head[h] = GS_NONE;
        s->fan[h] = GS_NONE;
    }
    /* fans: corners of a vertex in counter-clockwise order (c, then the
     * corner across the edge v -> tri[prev(c)]), angles accumulated from the
     * first corner (open fans start at a boundary edge) */
    for (size_t h0 = 0; h0 < nh; ++h0) {
        if (s->fan[h0] != GS_NONE) continue;
        uint32_t start = (uint32_t)h0, x = (uint32_t)h0;
        int closed = 0;
        for (;;) { /* clockwise to the first corner */
            uint32_t tw = t->opp[x];
            if (tw == GS_NONE) break;
            x = gs__next(tw);
            if (x == h0) {
                closed = 1;
                break;
            }
        }
        if (!closed) start = x;
        double acc = 0;
        x = start;
        for (;;) {
            s->off[x] = acc;
            s->fan[x] = start;
            acc += t->angle[x];
            uint32_t tw = t->opp[gs__prev(x)];
            if (tw == GS_NONE || tw == start) break;
            x = tw;
        }
        s->ftot[start] = acc;
        s->fclosed[start] = (uint8_t)closed;
    }
    for (uint32_t v = 0; v < t->nv; ++v)
        s->pseudo[v] = (t->vflag[v] & (GS_V_SADDLE | GS_V_BOUNDARY | GS_V_NONMANIFOLD)) != 0;
    *state = s;
    return GS_OK;
}

/* ---- vertex distances ---------------------------------------------------- */

/* Lower d(v) to val, reached by a path arriving in corner c at angle a from
 * the corner's first edge (for pseudo-sources, which only need to emit
 * windows into the directions that path cannot reach straight). The path's
 * last straight piece is recorded for backtracking: kind and ref as in
 * gs__exact_trace, (sx, sy) the window's source, tag its point source. */
static inline void ex_update_vertex(ex_state *s, uint32_t v, double val, uint32_t c, double a,
                                    uint8_t kind, uint32_t ref, double sx, double sy, uint32_t tag)
{
    if (val < s->d[v]) {
        if (s->tv && s->d[v] == INFINITY) s->tv[s->ntv++] = v;
        s->d[v] = val;
        s->tr.kind[v] = kind;
        s->tr.ref[v] = ref;
        s->tr.tag[v] = tag;
        s->tr.sxy[2 * (size_t)v] = sx;
        s->tr.sxy[2 * (size_t)v + 1] = sy;
        if (s->pseudo[v]) {
            s->in_c[v] = c;
            s->in_a[v] = a;
            if (val <= s->max_d && !s->direct_only) gs__iheap_push_or_decrease(&s->vheap, v, val);
        }
    }
}

/* ---- trimming ------------------------------------------------------------ */

/* Shrink [*pb0, *pb1] (a window with source (sx,sy), sigma, on an edge of
 * length len) to the part that is not beaten, by more than the tolerance,
 * by the vertex at x = 0 (distance dA) or at x = len (distance dB). Returns 0
 * when nothing is left. Exact up to rounding: sigma + |q - s| - (dA + x) is
 * non-increasing in x and sigma + |q - s| - (dB + len - x) non-decreasing, so
 * each vertex cuts off one end; a cut is verified before it is applied. */
static int ex_trim(double sx, double sy, double sigma, double len, double dA, double dB,
                   double *pb0, double *pb1)
{
    double b0 = *pb0, b1 = *pb1;
    double sy2 = sy * sy;
    if (dA < INFINITY) {
        double tol = TOL_REL * (dA + len);
        double k = dA + tol - sigma; /* kept where |q - s| <= x + k */
        double m = b1 + k;
        double dx = b1 - sx;
        if (m < 0 || dx * dx + sy2 > m * m) return 0;
        m = b0 + k;
        dx = b0 - sx;
        if (m < 0 || dx * dx + sy2 > m * m) {
            double k2 = k + tol; /* aim a little inside the beaten part */
            double den = 2 * (sx + k2);
            if (den > 0) {
                double x = (sx * sx + sy2 - k2 * k2) / den;
                if (x > b0) {
                    if (x > b1) x = b1;
                    m = x + k;
                    dx = x - sx;
                    if (m < 0 || dx * dx + sy2 > m * m) b0 = x;
                }
            }
        }
    }
    if (dB < INFINITY) {
        double tol = TOL_REL * (dB + len);
        double k = dB + tol - sigma; /* kept where |q - s| <= len - x + k */
        double m = len - b0 + k;
        double dx = b0 - sx;
        if (m < 0 || dx * dx + sy2 > m * m) return 0;
        m = len - b1 + k;
        dx = b1 - sx;
        if (m < 0 || dx * dx + sy2 > m * m) {
            double k2 = k + tol;
            double tx = len - sx; /* source measured from the far end */
            double den = 2 * (tx + k2);
            if (den > 0) {
                double x = len - (tx * tx + sy2 - k2 * k2) / den;
                if (x < b1) {
                    if (x < b0) x = b0;
                    m = len - x + k;
                    dx = x - sx;
                    if (m < 0 || dx * dx + sy2 > m * m) b1 = x;
                }
            }
        }
    }
    *pb0 = b0;
    *pb1 = b1;
    return 1;
}

/* ---- window pool --------------------------------------------------------- */

static uint32_t ex_alloc(ex_state *s)
{
    if (s->free_win != GS_NONE) {
        uint32_t w = s->free_win;
        s->free_win = s->win[w].next;
        return w;
    }
    if (s->n_win == s->cap_win) {
        if (s->cap_win >= UINT32_MAX / 2) {
            s->oom = 1;
            return GS_NONE;
        }
        uint32_t nc = s->cap_win * 2;
        ex_win *nw = gs__realloc(s->win, nc, sizeof *nw);
        if (!nw) {
            s->oom = 1;
            return GS_NONE;
        }
        s->win = nw;
        s->cap_win = nc;
    }
    return s->n_win++;
}

/* Queue a window on half-edge h (after trimming against the end vertices of
 * h). Windows on boundary half-edges are never created: callers pass twins. */
static void ex_push(ex_state *s, uint32_t h, double b0, double b1, double sx, double sy,
                    double sigma, uint32_t tag)
{
    const gs__topo *t = s->t;
    double len = s->hl[h];
    if (sy > 0) sy = 0;
    if (b0 < 0) b0 = 0;
    if (b1 > len) b1 = len;
    if (!(b0 <= b1)) return;
    if (!ex_trim(sx, sy, sigma, len, s->d[t->tri[h]], s->d[t->tri[gs__next(h)]], &b0, &b1))
        return;
    double dx = sx < b0 ? b0 - sx : (sx > b1 ? sx - b1 : 0);
    double dmin = sigma + sqrt(dx * dx + sy * sy);
    if (dmin > s->max_d) return;
    if (s->has_goal) { /* every path through the window to the goal is longer than max_d: dropped */
        const double *a = t->xyz + 3 * (size_t)t->tri[h], *b = t->xyz + 3 * (size_t)t->tri[gs__next(h)];
        double e[3], w[3], ee = 0, we = 0;
        for (int k = 0; k < 3; ++k) e[k] = b[k] - a[k], w[k] = s->goal[k] - a[k], ee += e[k] * e[k], we += w[k] * e[k];
        double u = ee > 0 ? we / ee : 0, lo = b0 / len, hi = b1 / len, g2 = 0;
        u = u < lo ? lo : u > hi ? hi : u;
        for (int k = 0; k < 3; ++k) g2 += (w[k] - u * e[k]) * (w[k] - u * e[k]);
        if (dmin + sqrt(g2) > s->max_d) return;
    }
    uint32_t w = ex_alloc(s);
    if (w == GS_NONE) return;
    ex_win *p = &s->win[w];
    p->b0 = b0;
    p->b1 = b1;
    p->sx = sx;
    p->sy = sy;
    p->sigma = sigma;
    p->tag = tag;
    p->next = s->head[h];
    s->head[h] = w;
    if (s->hmark && !s->hmark[h]) {
        s->hmark[h] = 1;
        s->th[s->nth++] = h;
    }
    s->created++;
    gs__iheap_push_or_decrease(&s->fheap, h / 3, dmin);
}

/* ---- sources ------------------------------------------------------------- */

/* Emit the windows of vertex v at its current distance (a source or a
 * pseudo-source): on the twin of the opposite edge of each face, restricted
 * to the rays that leave v at an angle >= pi (both ways round) from the
 * direction its shortest path came from; any other ray can be shortcut
 * inside the star of v. Sources (no incoming path) emit everything. */
static void ex_fire_vertex(ex_state *s, uint32_t v)
{
    const gs__topo *t = s->t;
    double dv = s->d[v];
    s->fired[v] = dv;
    for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
        uint32_t c = t->vc[k], cn = gs__next(c), cp = gs__prev(c);
        ex_update_vertex(s, t->tri[cn], dv + s->hl[c], cn, t->angle[cn], GS_EXTR_EDGE, c, 0, 0, GS_NONE);
        ex_update_vertex(s, t->tri[cp], dv + s->hl[cp], cp, 0.0, GS_EXTR_EDGE, c, 0, 0, GS_NONE);
    }
    uint32_t cin = s->in_c[v], fin = GS_NONE;
    double b = 0, tot = 0;
    int closed = 0;
    if (cin != GS_NONE) {
        fin = s->fan[cin];
        b = s->off[cin] + s->in_a[v];
        tot = s->ftot[fin];
        closed = s->fclosed[fin];
    }
    for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
        uint32_t c = t->vc[k];
        uint32_t ho = gs__next(c), tw = t->opp[ho];
        if (tw == GS_NONE) continue;
        double a = t->angle[c], lo = 0, hi = a;
        if (s->fan[c] == fin) {
            /* needed directions of this corner, relative to its first edge */
            double o = s->off[c];
            if (closed) {
                double w = tot - 2 * M_PI, n0 = fmod(b + M_PI, tot);
                if (n0 < 0) n0 += tot;
                lo = INFINITY;
                hi = -INFINITY;
                for (int r = -1; r <= 1; ++r) {
                    double p0 = n0 + r * tot - o, p1 = p0 + w;
                    if (p0 < 0) p0 = 0;
                    if (p1 > a) p1 = a;
                    if (p0 <= p1) {
                        if (p0 < lo) lo = p0;
                        if (p1 > hi) hi = p1;
                    }
                }
            } else {
                double l1 = b - M_PI - o, l2 = b + M_PI - o; /* [0,l1] and [l2,tot] */
                lo = INFINITY;
                hi = -INFINITY;
                if (l1 >= 0) {
                    lo = 0;
                    hi = l1 < a ? l1 : a;
                }
                if (l2 <= a) {
                    if (l2 < lo) lo = l2 > 0 ? l2 : 0;
                    hi = a;
                }
            }
            lo -= ANGLE_SLACK;
            hi += ANGLE_SLACK;
            if (!(lo <= hi)) continue;
            if (lo < 0) lo = 0;
            if (hi > a) hi = a;
        }
        /* v in the frame of ho is len[c] * (cos, sin) of the corner at ho */
        double lv = s->hl[c], L = s->hl[ho];
        double x = lv * s->hc[ho], y = lv * s->hs[ho];
        double x0 = 0, x1 = L; /* on tw: x = L - |B X| for the ray at angle th */
        if (lo > 0 || hi < a) {
            /* sine rule in (v, B, X): |BX| = |vB| sin th / sin(th + beta) */
            double beta = t->angle[ho];
            if (hi < a) x0 = L - lv * sin(hi) / sin(hi + beta);
            if (lo > 0) x1 = L - lv * sin(lo) / sin(lo + beta);
        }
        s->propagated++;
        ex_push(s, tw, x0, x1, L - x, -y, dv, GS_NONE);
    }
}

/* A point of face f: the corners get their straight distances, and each edge
 * emits a window into the face across it (rays from the point). */
static void ex_fire_point(ex_state *s, const gs_source *src, uint32_t isrc)
{
    const gs__topo *t = s->t;
    uint32_t f = src->face;
    for (int i = 0; i < 3; ++i) {
        uint32_t h = 3 * f + (uint32_t)i;
        double len = s->hl[h], lac = s->hl[gs__prev(h)];
        double cx = lac * s->hc[h], cy = lac * s->hs[h];
        double w1 = src->bary[(i + 1) % 3], w2 = src->bary[(i + 2) % 3];
        double px = w1 * len + w2 * cx, py = w2 * cy;
        /* distance to the corner at the start of h */
        ex_update_vertex(s, t->tri[h], sqrt(px * px + py * py), h, atan2(py, px), GS_EXTR_POINT, isrc, 0, 0,
                         isrc);
        uint32_t tw = t->opp[h];
        if (tw == GS_NONE) continue;
        s->propagated++;
        ex_push(s, tw, 0, len, len - px, -py, 0.0, isrc);
    }
}

/* ---- propagation --------------------------------------------------------- */

/* The path target point (gs__exact_set_target) lies in the face of half-edge
 * h: let the windows from wi on entering that face offer it their distance. */
static void ex_target_windows(ex_state *s, uint32_t h, uint32_t wi)
{
    gs__exact_target *q = &s->tr.target;
    uint32_t i = h % 3;
    double len = s->hl[h], lac = s->hl[gs__prev(h)];
    double cx = lac * s->hc[h], cy = lac * s->hs[h];
    double w1 = q->bary[(i + 1) % 3], w2 = q->bary[(i + 2) % 3];
    double qx = w1 * len + w2 * cx, qy = w2 * cy;
    double slack = COVER_REL * len;
    for (; wi != GS_NONE; wi = s->win[wi].next) {
        const ex_win *w = &s->win[wi];
        if (!(qy - w->sy > 0)) continue; /* along the edge: a corner's path is as short */
        double xq = w->sx + (qx - w->sx) * (-w->sy) / (qy - w->sy);
        if (xq < w->b0 - slack || xq > w->b1 + slack) continue;
        double ex = qx - w->sx, ey = qy - w->sy;
        double val = w->sigma + sqrt(ex * ex + ey * ey);
        if (val < q->dist) {
            q->dist = val;
            q->h = h;
            q->sx = w->sx;
            q->sy = w->sy;
            q->tag = w->tag;
        }
    }
}

static void ex_process_face(ex_state *s, uint32_t f)
{
    const gs__topo *t = s->t;
    double *d = s->d;
    /* pass 1: let the pending windows update the opposite vertices first, so
     * that their children are trimmed against the best distances there.
     * (Re-trimming the windows against their own edge ends here, with the
     * distances of now, was measured to cost more than it saves.) */
    for (int i = 0; i < 3; ++i) {
        uint32_t h = 3 * f + (uint32_t)i;
        uint32_t wi = s->head[h];
        if (wi == GS_NONE) continue;
        uint32_t hp = gs__prev(h), C = t->tri[hp];
        double len = s->hl[h], lac = s->hl[hp];
        double cx = lac * s->hc[h], cy = lac * s->hs[h];
        double slack = COVER_REL * len;
        if (f == s->tface) ex_target_windows(s, h, wi);
        for (; wi != GS_NONE; wi = s->win[wi].next) {
            const ex_win *w = &s->win[wi];
            double xc = w->sx + (cx - w->sx) * (-w->sy) / (cy - w->sy);
            if (xc >= w->b0 - slack && xc <= w->b1 + slack) {
                double ex = w->sx - cx, ey = w->sy - cy; /* C -> source */
                double val = w->sigma + sqrt(ex * ex + ey * ey);
                if (val < d[C]) {
                    /* direction back to the source, from the edge C -> A (for
                     * firing C as a pseudo-source: never in direct-only runs) */
                    double a = s->pseudo[C] && !s->direct_only ? atan2(cy * ex - cx * ey, -cx * ex - cy * ey) : 0;
                    ex_update_vertex(s, C, val, hp, a, GS_EXTR_WINDOW, h, w->sx, w->sy, w->tag);
                }
            }
        }
    }
    /* pass 2: split every window at the ray through the opposite vertex and
     * send the parts across the two other edges */
    for (int i = 0; i < 3; ++i) {
        uint32_t h = 3 * f + (uint32_t)i;
        uint32_t wi = s->head[h];
        if (wi == GS_NONE) continue;
        s->head[h] = GS_NONE;
        uint32_t hn = gs__next(h), hp = gs__prev(h);
        uint32_t tl = t->opp[hp], tr = t->opp[hn]; /* twins of A->C side, C->B side */
        double lac = s->hl[hp], lbc = s->hl[hn];
        double ca = s->hc[h], sa = s->hs[h], cb = s->hc[hn], sb = s->hs[hn];
        double cx = lac * ca, cy = lac * sa;
        double lmc = lbc * cb; /* len - cx, without cancellation */
        while (wi != GS_NONE) {
            ex_win w = s->win[wi];
            /* free the slot first: ex_push may reuse (and move) the pool */
            s->win[wi].next = s->free_win;
            s->free_win = wi;
            uint32_t nx = w.next;
            s->propagated++;
            double sx = w.sx, sy = w.sy;
            double xc = sx + (cx - sx) * (-sy) / (cy - sy);
            if (tl != GS_NONE && w.b0 < xc) {
                /* rays through (b,0) meet A->C at t*C, t = b sy / (sy cx + cy (b - sx)) */
                double t0 = w.b0 * sy / (sy * cx + cy * (w.b0 - sx));
                double t1 = 1.0;
                if (w.b1 < xc) t1 = w.b1 * sy / (sy * cx + cy * (w.b1 - sx));
                if (!(t0 >= 0)) t0 = 0;
                if (!(t1 <= 1)) t1 = 1;
                if (t0 > 1) t0 = 1;
                if (t1 < 0) t1 = 0;
                /* frame of tl: origin A, x towards C */
                double nsx = sx * ca + sy * sa, nsy = sy * ca - sx * sa;
                ex_push(s, tl, t0 * lac, t1 * lac, nsx, nsy, w.sigma, w.tag);
            }
            if (tr != GS_NONE && w.b1 > xc) {
                /* rays through (b,0) meet C->B at C + u (B - C) */
                double ex = sx - cx, ey = sy - cy;
                double u0 = 0.0, u1;
                if (w.b0 > xc) {
                    double bx = w.b0 - sx;
                    u0 = (-ex * sy - ey * bx) / (-lmc * sy + cy * bx);
                }
                {
                    double bx = w.b1 - sx;
                    u1 = (-ex * sy - ey * bx) / (-lmc * sy + cy * bx);
                }
                if (!(u0 >= 0)) u0 = 0;
                if (!(u1 <= 1)) u1 = 1;
                if (u0 > 1) u0 = 1;
                if (u1 < 0) u1 = 0;
                /* frame of tr: origin C, x towards B */
                double nsx = ex * cb - ey * sb, nsy = ey * cb + ex * sb;
                ex_push(s, tr, u0 * lbc, u1 * lbc, nsx, nsy, w.sigma, w.tag);
            }
            wi = nx;
        }
    }
}

/* Needle triangles (aspect ratio up to 1e12 passes mesh validation) make
 * windows bounce along them some aspect-ratio times before their distances
 * grow past the vertices' (an octahedron with one vertex moved to 4e9:
 * hours). Real meshes need far fewer windows per face (homer-60k: 59,
 * stanford-bunny: 47); past this many a solve fails instead. */
static uint64_t ex_cap(const gs__topo *t)
{
    return EX_MAX_WINDOWS_BASE + EX_MAX_WINDOWS_PER_FACE * (uint64_t)t->nf;
}

/* Fire the sources and propagate up to s->max_d (state reset by the caller). */
static void ex_run(ex_state *s, const gs_source *src, uint32_t n_src)
{
    double *dist = s->d;
    double max_d = s->max_d;
    for (uint32_t i = 0; i < n_src; ++i)
        if (src[i].face == GS_NONE) {
            if (s->tv && dist[src[i].vertex] == INFINITY) s->tv[s->ntv++] = src[i].vertex;
            dist[src[i].vertex] = 0;
        }
    for (uint32_t i = 0; i < n_src; ++i)
        if (src[i].face == GS_NONE) {
            if (s->fired[src[i].vertex] != 0) ex_fire_vertex(s, src[i].vertex);
        } else {
            ex_fire_point(s, &src[i], i);
        }
    uint64_t cap = ex_cap(s->t);
    while (!s->oom && s->propagated <= cap) {
        int have_f = s->fheap.n > 0, have_v = s->vheap.n > 0;
        if (!have_f && !have_v) break;
        double kf = have_f ? s->fheap.key[s->fheap.ids[0]] : INFINITY;
        double kv = have_v ? s->vheap.key[s->vheap.ids[0]] : INFINITY;
        if (kv <= kf) {
            if (kv > max_d) break;
            uint32_t v = gs__iheap_pop(&s->vheap, NULL);
            if (dist[v] < s->fired[v]) ex_fire_vertex(s, v);
        } else {
            if (kf > max_d) break;
            uint32_t f = gs__iheap_pop(&s->fheap, NULL);
            ex_process_face(s, f);
        }
    }
}

int gs__exact_solve_local(void *state, const gs_source *src, double max_d, double *dist,
                          const uint32_t **touched, uint32_t *n_touched, gs_error *err)
{
    return gs__exact_solve_local_ex(state, src, max_d, 0, dist, touched, n_touched, err);
}

int gs__exact_solve_local_ex(void *state, const gs_source *src, double max_d, int direct_only, double *dist,
                             const uint32_t **touched, uint32_t *n_touched, gs_error *err)
{
    ex_state *s = state;
    s->direct_only = direct_only;
    const gs__topo *t = s->t;
    size_t nh = 3 * (size_t)t->nf;
    if (!s->tv) {
        s->tv = gs__malloc(t->nv ? t->nv : 1, sizeof *s->tv);
        s->th = gs__malloc(nh ? nh : 1, sizeof *s->th);
        s->hmark = gs__calloc(nh ? nh : 1, 1);
        if (!s->tv || !s->th || !s->hmark) {
            free(s->tv), free(s->th), free(s->hmark);
            s->tv = s->th = NULL, s->hmark = NULL;
            return gs__fail(err, GS_ENOMEM, "out of memory in the exact solver");
        }
        s->local_clean = 0;
    }
    if (!s->local_clean) {
        for (uint32_t v = 0; v < t->nv; ++v) {
            s->fired[v] = INFINITY;
            s->in_c[v] = GS_NONE;
            s->tr.kind[v] = GS_EXTR_NONE;
        }
        for (size_t h = 0; h < nh; ++h) s->head[h] = GS_NONE, s->hmark[h] = 0;
        s->local_clean = 1;
    } else {
        for (uint32_t i = 0; i < s->ntv; ++i) {
            uint32_t v = s->tv[i];
            s->fired[v] = INFINITY;
            s->in_c[v] = GS_NONE;
            s->tr.kind[v] = GS_EXTR_NONE;
        }
        for (uint32_t i = 0; i < s->nth; ++i) s->head[s->th[i]] = GS_NONE, s->hmark[s->th[i]] = 0;
    }
    s->ntv = s->nth = 0;
    s->tr.valid = 0;
    s->tr.target.face = GS_NONE;
    s->tface = GS_NONE;
    s->d = dist;
    s->max_d = max_d;
    s->oom = 0;
    s->created = s->propagated = 0;
    s->n_win = 0;
    s->free_win = GS_NONE;
    gs__iheap_clear(&s->fheap);
    gs__iheap_clear(&s->vheap);
    ex_run(s, src, 1);
    s->d = NULL;
    *touched = s->tv;
    *n_touched = s->ntv;
    if (s->oom) return gs__fail(err, GS_ENOMEM, "out of memory in the exact solver");
    if (s->propagated > ex_cap(t))
        return gs__fail(err, GS_EINTERNAL, "exact solver: gave up after %llu window propagations on %u faces "
                        "(needle triangles? see the mesh report's min angle)", (unsigned long long)s->propagated, t->nf);
    return GS_OK;
}

int gs__exact_straight(const void *state, uint32_t source_vertex, uint32_t u, double du)
{
    const ex_state *s = state;
    const gs__topo *t = s->t;
    switch (s->tr.kind[u]) {
    case GS_EXTR_NONE: return 1;
    case GS_EXTR_POINT: return 1;
    case GS_EXTR_EDGE: return t->tri[s->tr.ref[u]] == source_vertex;
    default: break;
    }
    uint32_t h = s->tr.ref[u];
    double lac = s->hl[gs__prev(h)];
    double cx = lac * s->hc[h], cy = lac * s->hs[h];
    double ex = cx - s->tr.sxy[2 * (size_t)u], ey = cy - s->tr.sxy[2 * (size_t)u + 1];
    double sigma = du - sqrt(ex * ex + ey * ey);
    return sigma <= 1e-9 * du;
}

static int ex_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                    double *dist, gs__solve_stats *stats, gs_error *err)
{
    ex_state *s = state;
    const gs__topo *t = s->t;
    size_t nh = 3 * (size_t)t->nf;
    s->d = dist;
    s->max_d = max_d;
    s->oom = 0;
    s->created = s->propagated = 0;
    s->n_win = 0;
    s->free_win = GS_NONE;
    for (uint32_t v = 0; v < t->nv; ++v) {
        dist[v] = INFINITY;
        s->fired[v] = INFINITY;
        s->in_c[v] = GS_NONE;
        s->tr.kind[v] = GS_EXTR_NONE;
    }
    s->tr.valid = 0;
    s->tr.target.dist = INFINITY;
    s->tr.target.h = GS_NONE;
    if (s->tface == GS_NONE) s->tr.target.face = GS_NONE;
    if (n_src > s->src_cap) {
        gs_source *ns = gs__realloc(s->tr.src, n_src, sizeof *ns);
        if (!ns) return gs__fail(err, GS_ENOMEM, "out of memory in the exact solver");
        s->tr.src = ns;
        s->src_cap = n_src;
    }
    memcpy(s->tr.src, src, n_src * sizeof *src);
    s->tr.n_src = n_src;
    for (size_t h = 0; h < nh; ++h) s->head[h] = GS_NONE;
    gs__iheap_clear(&s->fheap);
    gs__iheap_clear(&s->vheap);

    uint32_t *tv = s->tv;
    uint8_t *hmark = s->hmark;
    s->tv = NULL, s->hmark = NULL; /* no touched lists in full solves */
    s->direct_only = 0;
    ex_run(s, src, n_src);
    s->tv = tv, s->hmark = hmark;
    stats->windows_created = s->created;
    stats->windows_propagated = s->propagated;
    s->d = NULL;
    if (!s->oom && s->propagated <= ex_cap(t)) {
        memcpy(s->tr.dist, dist, t->nv * sizeof *dist);
        s->tr.valid = 1;
        s->tr.max_d = max_d;
    }
    s->local_clean = 0;
    if (s->oom) return gs__fail(err, GS_ENOMEM, "out of memory in the exact solver");
    if (s->propagated > ex_cap(t))
        return gs__fail(err, GS_EINTERNAL, "exact solver: gave up after %llu window propagations on %u faces "
                        "(needle triangles? see the mesh report's min angle)", (unsigned long long)s->propagated, t->nf);
    return GS_OK;
}

const gs__method_ops gs__exact_ops = {"exact", ex_create, ex_destroy, ex_solve, NULL, NULL};

void gs__exact_set_target(void *state, const gs_source *target)
{
    ex_state *s = state;
    if (target && target->face != GS_NONE) {
        s->tface = target->face;
        s->tr.target.face = target->face;
        memcpy(s->tr.target.bary, target->bary, sizeof s->tr.target.bary);
    } else {
        s->tface = GS_NONE; /* the last result stays readable */
    }
}

void gs__exact_set_goal(void *state, const double *goal)
{
    ex_state *s = state;
    s->has_goal = goal != NULL;
    if (goal) memcpy(s->goal, goal, sizeof s->goal);
}

const gs__exact_trace *gs__exact_get_trace(const void *state)
{
    const ex_state *s = state;
    return s->tr.valid ? &s->tr : NULL;
}
