/* pair_min.c - the minimum over a curve of the sum of two separator
 * distance functions (paper sec. 3.2 eq. 4, sec. 4.3), which every query
 * runs: the robust minimiser (gs__fun_pair_min: a Chebyshev-Lobatto scan of
 * values and slopes, cells refined cheapest first by safeguarded Newton)
 * and the query's grid minimiser (gs__fun_pair_min_grid: the cell of the
 * minimum from the two functions' values on the curve's uniform grid,
 * src/query/pair_grid.c, refined from the series). */
#include "../fit/fun_internal.h"
#include "pair_grid.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

/* ---- the pair minimiser (the query hot path) -------------------------
 *
 * 1. Values and derivatives of both terms at the Chebyshev-Lobatto nodes of
 *    a's variable x: table dot products (same frame) or a vectorised
 *    Clenshaw for b's shifted abscissae (loops), then s = a + b, s' = a' + b'.
 *    A loop's seam of b (x = split) is a node on both sides.
 * 2. Candidates: a segment end where s' points outwards (the minimum there is
 *    the end value), a cell where s' changes sign from - to +, and a cell
 *    whose Hermite cubic (values and slopes at its ends) dips inside. Each
 *    gets an estimate e (the cubic's minimum) and a pessimistic lower guess
 *    L = e - DIP_SAFETY * (dip depth) - tiny.
 * 3. Cells are refined cheapest-first (lowest e), skipping every cell whose
 *    L is not below the best value found: safeguarded Newton on s' inside
 *    its sign bracket (secant / bisection fallback).
 * Sharp terms (a narrow dip near 0) add their own minimum as a candidate. */

#ifndef PAIR_SHARP
#define PAIR_SHARP 1
#endif
#define DIP_SAFETY 4.0 /* the true dip may be this many times the cubic's */
#define L_REL 1e-9     /* and this much lower, relative                   */

#ifdef __SSE2__
#include <emmintrin.h>
#endif

typedef double v2 __attribute__((vector_size(16)));
typedef long long v2i __attribute__((vector_size(16)));

#define GRID_PTS (((GS_CHEB_GRID_MAX + GS_CHEB_PAD) / GS_CHEB_PAD) * GS_CHEB_PAD)

static inline v2 ld2(const double *p)
{
    v2 v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}

static inline void st2(double *p, v2 v)
{
    __builtin_memcpy(p, &v, sizeof v);
}

static inline v2 sqrt2(v2 x)
{
#ifdef __SSE2__
    return (v2)_mm_sqrt_pd((__m128d)x);
#else
    return (v2){sqrt(x[0]), sqrt(x[1])};
#endif
}

/* p and p' of c (degree m <= rows-1) at the np padded grid nodes. */
static void tab_eval(const double *c, uint32_t m, const gs__cheb_grid *g, double *p, double *d)
{
    const uint32_t np = g->np;
    for (uint32_t j = 0; j < np; j += 8) {
        v2 p0 = {c[0], c[0]}, p1 = p0, p2 = p0, p3 = p0;
        v2 d0 = {0.0, 0.0}, d1 = d0, d2 = d0, d3 = d0;
        for (uint32_t k = 1; k <= m; k++) {
            const double *t = g->tp + (size_t)k * np + j, *u = g->dp + (size_t)k * np + j;
            v2 ck = {c[k], c[k]};
            p0 += ck * ld2(t), p1 += ck * ld2(t + 2), p2 += ck * ld2(t + 4), p3 += ck * ld2(t + 6);
            d0 += ck * ld2(u), d1 += ck * ld2(u + 2), d2 += ck * ld2(u + 4), d3 += ck * ld2(u + 6);
        }
        st2(p + j, p0), st2(p + j + 2, p1), st2(p + j + 4, p2), st2(p + j + 6, p3);
        st2(d + j, d0), st2(d + j + 2, d1), st2(d + j + 4, d2), st2(d + j + 6, d3);
    }
}

/* p and p' at n points t (n a multiple of 4): Clenshaw and its derivative. */
static void pts_eval(const double *c, uint32_t m, const double *t, uint32_t n, double *p, double *d)
{
    for (uint32_t j = 0; j < n; j += 4) {
        v2 x0 = ld2(t + j), x1 = ld2(t + j + 2), y0 = x0 + x0, y1 = x1 + x1;
        v2 z = {0.0, 0.0}, b10 = z, b20 = z, e10 = z, e20 = z, b11 = z, b21 = z, e11 = z, e21 = z;
        for (uint32_t k = m; k >= 1; k--) {
            v2 ck = {c[k], c[k]};
            v2 n0 = ck + y0 * b10 - b20, n1 = ck + y1 * b11 - b21;
            v2 f0 = (b10 + b10) + y0 * e10 - e20, f1 = (b11 + b11) + y1 * e11 - e21;
            b20 = b10, b10 = n0, b21 = b11, b11 = n1;
            e20 = e10, e10 = f0, e21 = e11, e11 = f1;
        }
        v2 c0 = {c[0], c[0]};
        st2(p + j, c0 + x0 * b10 - b20), st2(p + j + 2, c0 + x1 * b11 - b21);
        st2(d + j, b10 + x0 * e10 - e20), st2(d + j + 2, b11 + x1 * e11 - e21);
    }
}

/* (p, p') -> (v, v') of a term in place (0 where p <= 0), n even; with
 * accumulate, added to (s, s') instead. */
static void to_values(uint32_t sq, const double *p, const double *d, uint32_t n, double *s,
                      double *ds, int accumulate)
{
    const v2 zero = {0.0, 0.0}, one = {1.0, 1.0}, half = {0.5, 0.5};
    for (uint32_t j = 0; j < n; j += 2) {
        v2 pj = ld2(p + j), dj = ld2(d + j), v, dv;
        v2i pos = pj > zero;
        if (sq) {
            v2 r = sqrt2((v2)(((v2i)pj & pos) | ((v2i)one & ~pos)));
            v = (v2)((v2i)r & pos);
            dv = (v2)((v2i)(half * dj / r) & pos);
        } else {
            v = (v2)((v2i)pj & pos);
            dv = (v2)((v2i)dj & pos);
        }
        if (accumulate)
            v += ld2(s + j), dv += ld2(ds + j);
        st2(s + j, v), st2(ds + j, dv);
    }
}

/* Safeguarded Newton on s' in the bracket lo < x < hi with s'(lo) < 0 <
 * s'(hi) (slopes dlo, dhi); x is the start. */
static void refine_bracket(const pctx *c, int seg, double lo, double hi, double dlo, double dhi,
                           double x, best *bs)
{
    int side = 0, again = 0; /* the end that moved last; moved twice in a row */
    for (int it = 0; it < 100; it++) {
        STAT(6);
        double s1, s2, v = gs__fun_seg_eval3(c, seg, x, &s1, &s2);
        gs__fun_best_update(bs, x, v, seg);
        if (s1 == 0.0 || !(v > 0.0))
            return;
        int sd = s1 < 0.0 ? -1 : 1;
        again = sd == side, side = sd;
        if (s1 < 0.0)
            lo = x, dlo = s1;
        else
            hi = x, dhi = s1;
        double w = hi - lo;
        /* s' increasing in the bracket: nothing there is below the ends'
         * values by more than w * max|s'| */
        if (w <= 4e-16 * (1.0 + fabs(x)) || w * (dhi > -dlo ? dhi : -dlo) <= STOP_REL * bs->v)
            return;
        double t = s2 > 0.0 ? x - s1 / s2 : NAN;
        if (t > lo && t < hi && !(again && fabs(t - x) > 0.25 * w)) {
            if (fabs(t - x) * fabs(s1) <= STOP_REL * v) {
                gs__fun_best_update(bs, t, v - 0.5 * fabs(s1 * (t - x)), seg);
                return;
            }
        } else if (!again) {
            t = lo - dlo * w / (dhi - dlo); /* secant on s' */
            if (!(t > lo && t < hi))
                t = lo + 0.5 * w;
        } else {
            t = lo + 0.5 * w;
        }
        x = t;
    }
}

/* One candidate cell or end. */
typedef struct cand {
    double lower, est, x;
    int seg, kind; /* 0: end value; 1: sign bracket; 2: cubic dip */
    double lo, hi, dlo, dhi;
} cand;

#define MAXCAND 48

/* Minimum of the Hermite cubic on [x0, x0 + h] with values s0, s1 and
 * slopes d0, d1: returns 1 and (*tau in (0,1), *e) when it has an interior
 * local minimum. */
static int hermite_min(double s0, double s1, double d0, double d1, double h, double *tau,
                       double *e)
{
    double C = h * d0, D = h * d1, A = 3.0 * (C + D) - 6.0 * (s1 - s0), B = D - C - A;
    double t;
    if (A == 0.0) {
        if (!(B > 0.0))
            return 0;
        t = -C / B;
    } else {
        double disc = B * B - 4.0 * A * C;
        if (!(disc >= 0.0))
            return 0;
        double r = sqrt(disc), q = -0.5 * (B + (B >= 0.0 ? r : -r));
        double t1 = q / A, t2 = q != 0.0 ? C / q : NAN;
        /* the minimum: H'' = 2 A t + B > 0 */
        t = 2.0 * A * t1 + B > 0.0 ? t1 : t2;
    }
    if (!(t > 0.0 && t < 1.0))
        return 0;
    *tau = t;
    *e = s0 + t * (C + t * (0.5 * B + t * (A / 3.0)));
    return 1;
}

/* Candidates of one segment's nodes (xs, s, ds), n >= 2. */
static uint32_t segment_cands(const double *xs, const double *s, const double *ds, uint32_t n,
                              int seg, cand *cs, uint32_t nc, best *b)
{
    for (uint32_t i = 0; i < n; i++)
        gs__fun_best_update(b, xs[i], s[i], seg);
    for (uint32_t i = 0; i + 1 < n && nc < MAXCAND; i++) {
        double h = xs[i + 1] - xs[i], tau, e;
        if (!(h > 0.0))
            continue;
        int sign = ds[i] < 0.0 && ds[i + 1] > 0.0;
        if (!hermite_min(s[i], s[i + 1], ds[i], ds[i + 1], h, &tau, &e)) {
            if (!sign)
                continue;
            tau = 0.5, e = s[i] < s[i + 1] ? s[i] : s[i + 1];
        }
        double lo_end = s[i] < s[i + 1] ? s[i] : s[i + 1], dip = lo_end - e;
        if (!sign && !(dip > 0.0))
            continue;
        dip = dip > 0.0 ? dip : 0.0;
        cand *k = &cs[nc++];
        k->est = e < lo_end ? e : lo_end;
        k->lower = k->est - DIP_SAFETY * dip;
        if (sign) { /* a convex cell (a kink too) lies above its end tangents */
            double tan = s[i] + ds[i] * (s[i + 1] - s[i] - ds[i + 1] * h) / (ds[i] - ds[i + 1]);
            k->lower = tan < k->lower ? tan : k->lower;
        }
        k->lower -= L_REL * fabs(lo_end);
        k->x = xs[i] + tau * h, k->seg = seg, k->kind = sign ? 1 : 2;
        k->lo = xs[i], k->hi = xs[i + 1], k->dlo = ds[i], k->dhi = ds[i + 1];
    }
    return nc;
}

/* Refine the candidates, cheapest first, while they may beat the best. */
static void refine_cands(const pctx *c, cand *cs, uint32_t nc, double cut, best *b)
{
    for (uint32_t i = 1; i < nc; i++) { /* insertion sort by estimate */
        cand t = cs[i];
        uint32_t j = i;
        for (; j > 0 && cs[j - 1].est > t.est; j--)
            cs[j] = cs[j - 1];
        cs[j] = t;
    }
    for (uint32_t i = 0; i < nc; i++)
        STAT(5);
    for (uint32_t i = 0; i < nc; i++) {
        const cand *k = &cs[i];
        double bound = b->v < cut ? b->v : cut;
        if (!(k->lower < bound) || b->v <= 0.0)
            continue;
        STAT(k->kind);
        if (k->kind == 1)
            refine_bracket(c, k->seg, k->lo, k->hi, k->dlo, k->dhi, k->x, b);
        else
            gs__fun_refine(c, k->seg, k->lo, k->hi, k->x, b);
    }
}

/* Values and slopes of the sum at the grid nodes and the seam. */
static best pair_minimise(const pctx *c, const gs__cheb_grid *g, double cut)
{
    double pa[GRID_PTS], da[GRID_PTS], pb[GRID_PTS], db[GRID_PTS], s[GRID_PTS + 2],
        ds[GRID_PTS + 2], tb[GRID_PTS], xs[GRID_PTS + 2], xs2[GRID_PTS + 2], s2[GRID_PTS + 2],
        ds2[GRID_PTS + 2];
    const uint32_t np = g->np, n = g->g + 1;
    const double *x = g->x;
    best b = {INFINITY, 0.0, 0};
    cand cs[MAXCAND];
    uint32_t nc = 0;
    tab_eval(c->a.c, c->a.m, g, pa, da);
    to_values(c->a.sq, pa, da, np, s, ds, 0);
    if (c->b.c) {
        if (c->split > 1.0 && c->off[0] == 0.0) {
            tab_eval(c->b.c, c->b.m, g, pb, db);
        } else {
            for (uint32_t j = 0; j < np; j++) {
                double xj = x[j < n ? j : n - 1];
                tb[j] = gs__fun_clamp1(xj + c->off[xj < c->split ? 0 : 1]);
            }
            pts_eval(c->b.c, c->b.m, tb, np, pb, db);
        }
        to_values(c->b.sq, pb, db, np, s, ds, 1);
    }
    for (int i = 0; i < 2 && PAIR_SHARP; i++)
        if (c->sharp[i] && (i == 0 || c->b.c))
            gs__fun_sharp_candidates(c, i, g, i == 0 || (c->split > 1.0 && c->off[0] == 0.0) ? (i ? pb : pa) : NULL, &b);
    if (!(c->split < 1.0)) {
        nc = segment_cands(x, s, ds, n, 0, cs, nc, &b);
        if (!c->loop) { /* path ends: the minimum may sit there */
            if (ds[0] >= 0.0)
                gs__fun_best_update(&b, x[0], s[0], 0);
            if (ds[n - 1] <= 0.0)
                gs__fun_best_update(&b, x[n - 1], s[n - 1], 0);
        }
    } else { /* b's seam: [-1, split] (b at t -> 1) and [split, 1] (t from -1) */
        uint32_t j0 = 0, k = 1;
        while (j0 < n && x[j0] < c->split)
            j0++;
        double a1, a2, b1, b2, va = gs__fun_term_at3(&c->a, c->split, &a1, &a2);
        xs2[0] = c->split, s2[0] = va + gs__fun_term_at3(&c->b, -1.0, &b1, &b2), ds2[0] = a1 + b1;
        for (uint32_t j = j0; j < n; j++)
            if (!(j == j0 && x[j] == c->split))
                xs2[k] = x[j], s2[k] = s[j], ds2[k++] = ds[j];
        for (uint32_t j = 0; j < j0; j++)
            xs[j] = x[j];
        xs[j0] = c->split, s[j0] = va + gs__fun_term_at3(&c->b, 1.0, &b1, &b2), ds[j0] = a1 + b1;
        nc = segment_cands(xs, s, ds, j0 + 1, 0, cs, nc, &b);
        nc = segment_cands(xs2, s2, ds2, k, 1, cs, nc, &b);
    }
    refine_cands(c, cs, nc, cut, &b);
    return b;
}
static double pair_min_cut(const gs__fun *a, const gs__fun *b, double cut, double *u_at)
{
    if (u_at)
        *u_at = 0.0;
    if (gs__fun_unreachable(a) || gs__fun_unreachable(b))
        return INFINITY;
    if (a->kind == GS_FUN_SAMPLED || b->kind == GS_FUN_SAMPLED)
        return gs__fun_sampled_pair_min(a, b, u_at);
    pctx c;
    double comb[GS_FUN_MAX_DEGREE + 1];
    gs__fun_pair_setup(a, b, &c, comb);
    const gs__cheb_grid *g = gs__cheb_grid_for(a->degree > b->degree ? a->degree : b->degree);
    STAT(4);
    best r = pair_minimise(&c, g, cut);
    double u = gs__fun_finish(&c, &r);
    if (u_at)
        *u_at = u;
    /* the value as evaluated (sqrt near 0 amplifies rounding differences) */
    return gs__fun_value(a, u) + gs__fun_value(b, u);
}

double gs__fun_pair_min(const gs__fun *a, const gs__fun *b, double *u_at)
{
    return pair_min_cut(a, b, INFINITY, u_at);
}

double gs__fun_pair_min_below(const gs__fun *a, const gs__fun *b, double best, double *u_at)
{
    return pair_min_cut(a, b, best, u_at);
}


/* ---- the query's grid minimiser ------------------------------------------ */

#define GS_NONE_U32 0xFFFFFFFFu
_Static_assert(GS_NONE_U32 == GS_FUN_NO_CELL, "grid candidates: one \"none\" (gs__grid_marks_pick)");

static double grid_u(uint32_t j, uint32_t g, int closed)
{
    return closed ? -1.0 + 2.0 * j / g : -1.0 + 2.0 * j / (g - 1);
}

/* gs__fun_value(a, u) + gs__fun_value(b, u) for two Chebyshev functions, bit
 * for bit, with the two Clenshaw recurrences interleaved (a series of lower
 * degree starts with exact zeros). */
static double pair_value(const gs__fun *a, const gs__fun *b, double u)
{
    double ta = gs__fun_clamp1(a->closed ? gs__fun_wrap(u - a->shift) : u);
    double tb = gs__fun_clamp1(b->closed ? gs__fun_wrap(u - b->shift) : u);
    const double *ca = a->coef, *cb = b->coef;
    uint32_t ma = a->degree, mb = b->degree, m = ma > mb ? ma : mb, mn = ma < mb ? ma : mb;
    double a1 = 0.0, a2 = 0.0, b1 = 0.0, b2 = 0.0, sa = 2.0 * ta, sb = 2.0 * tb;
    /* above the lower degree the other recurrence stays exactly +0 */
    for (uint32_t k = m; k > mn; k--) {
        if (ma > mb) {
            double a0 = ca[k] + sa * a1 - a2;
            a2 = a1, a1 = a0;
        } else {
            double b0 = cb[k] + sb * b1 - b2;
            b2 = b1, b1 = b0;
        }
    }
    /* both at once, lane by lane the same operations */
    v2 s = {sa, sb}, r1 = {a1, b1}, r2 = {a2, b2};
    uint32_t k = mn;
    for (; k >= 2; k -= 2) { /* two steps a turn */
        v2 c1 = {ca[k], cb[k]}, c2 = {ca[k - 1], cb[k - 1]};
        r2 = c1 + s * r1 - r2;
        r1 = c2 + s * r2 - r1;
    }
    if (k == 1) {
        v2 ck = {ca[1], cb[1]};
        v2 r0 = ck + s * r1 - r2;
        r2 = r1, r1 = r0;
    }
    a1 = r1[0], b1 = r1[1], a2 = r2[0], b2 = r2[1];
    double pa = ma ? ca[0] + ta * a1 - a2 : ca[0], pb = mb ? cb[0] + tb * b1 - b2 : cb[0];
    term fa = {ca, ma, a->squared}, fb = {cb, mb, b->squared};
    return gs__fun_term_value(&fa, pa) + gs__fun_term_value(&fb, pb);
}

/* pair_value at two points u0, u1 at once (two independent pairs of
 * recurrences, each lane the same operations as pair_value: the same
 * values, bit for bit), for a path's two grid candidates: the second
 * evaluation need not wait for the first. */
static void pair_value2(const gs__fun *a, const gs__fun *b, double u0, double u1, double *v0, double *v1)
{
    const double *ca = a->coef, *cb = b->coef;
    uint32_t ma = a->degree, mb = b->degree, m = ma > mb ? ma : mb, mn = ma < mb ? ma : mb;
    double ta = gs__fun_clamp1(a->closed ? gs__fun_wrap(u0 - a->shift) : u0);
    double tb = gs__fun_clamp1(b->closed ? gs__fun_wrap(u0 - b->shift) : u0);
    double qa = gs__fun_clamp1(a->closed ? gs__fun_wrap(u1 - a->shift) : u1);
    double qb = gs__fun_clamp1(b->closed ? gs__fun_wrap(u1 - b->shift) : u1);
    v2 s = {2.0 * ta, 2.0 * tb}, S = {2.0 * qa, 2.0 * qb}, z = {0.0, 0.0};
    v2 r1 = z, r2 = z, R1 = z, R2 = z;
    for (uint32_t k = m; k > mn; k--) { /* the higher degree's own terms (the other lane stays +0) */
        if (ma > mb) {
            double x = ca[k] + s[0] * r1[0] - r2[0], y = ca[k] + S[0] * R1[0] - R2[0];
            r2[0] = r1[0], r1[0] = x, R2[0] = R1[0], R1[0] = y;
        } else {
            double x = cb[k] + s[1] * r1[1] - r2[1], y = cb[k] + S[1] * R1[1] - R2[1];
            r2[1] = r1[1], r1[1] = x, R2[1] = R1[1], R1[1] = y;
        }
    }
    uint32_t k = mn;
    for (; k >= 2; k -= 2) {
        v2 c1 = {ca[k], cb[k]}, c2 = {ca[k - 1], cb[k - 1]};
        r2 = c1 + s * r1 - r2;
        R2 = c1 + S * R1 - R2;
        r1 = c2 + s * r2 - r1;
        R1 = c2 + S * R2 - R1;
    }
    if (k == 1) {
        v2 ck = {ca[1], cb[1]};
        v2 r0 = ck + s * r1 - r2, R0 = ck + S * R1 - R2;
        r2 = r1, r1 = r0, R2 = R1, R1 = R0;
    }
    double pa = ma ? ca[0] + ta * r1[0] - r2[0] : ca[0], pb = mb ? cb[0] + tb * r1[1] - r2[1] : cb[0];
    double Pa = ma ? ca[0] + qa * R1[0] - R2[0] : ca[0], Pb = mb ? cb[0] + qb * R1[1] - R2[1] : cb[0];
    term fa = {ca, ma, a->squared}, fb = {cb, mb, b->squared};
    *v0 = gs__fun_term_value(&fa, pa) + gs__fun_term_value(&fb, pb);
    *v1 = gs__fun_term_value(&fa, Pa) + gs__fun_term_value(&fb, Pb);
}

/* term_at3 of the two functions at u (p, p', p'' by the forward recurrences
 * of gs__cheb_eval3, both series at once up to the lower degree): returns
 * the sum of the values, *s1 and *s2 the sums of the derivatives, bit for
 * bit term_at3 of each (wrapped, clamped) added. order (a constant at each
 * call, so that the compiler drops the rest) says how many of them are
 * wanted: 3 all, 2 the value and *s1 (the second derivatives' recurrence
 * skipped, *s2 meaningless), 1 the value alone (only the p recurrence; s1
 * and s2 untouched). The value is the same, bit for bit, at every order:
 * the same operations compute it. */
static inline double pair_at(const gs__fun *a, const gs__fun *b, double u, double *s1, double *s2, int order)
{
    double ta = gs__fun_clamp1(a->closed ? gs__fun_wrap(u - a->shift) : u);
    double tb = gs__fun_clamp1(b->closed ? gs__fun_wrap(u - b->shift) : u);
    const double *ca = a->coef, *cb = b->coef;
    uint32_t ma = a->degree, mb = b->degree;
    int first = order >= 2, second = order >= 3;
    double p[2], p1[2], p2[2];
    if (ma < 1 || mb < 1) {
        gs__cheb_eval3(ca, ma, ta, &p[0], &p1[0], &p2[0]);
        gs__cheb_eval3(cb, mb, tb, &p[1], &p1[1], &p2[1]);
    } else {
        uint32_t mn = ma < mb ? ma : mb;
        v2 t = {ta, tb}, t0 = {1.0, 1.0}, t1 = t, e0 = {0.0, 0.0}, e1 = {1.0, 1.0}, f0 = {0.0, 0.0},
           f1 = {0.0, 0.0}, t2 = 2.0 * t, c1 = {ca[1], cb[1]}, v = (v2){ca[0], cb[0]} + c1 * t, d1 = c1,
           d2 = {0.0, 0.0};
        uint32_t k = 2;
        for (; k + 1 <= mn; k += 2) { /* two steps a turn, the pairs' roles swapped */
            v2 ck = {ca[k], cb[k]}, cn = {ca[k + 1], cb[k + 1]};
            t0 = t2 * t1 - t0;
            if (first) e0 = 2.0 * t1 + t2 * e1 - e0;
            if (second) f0 = 4.0 * e1 + t2 * f1 - f0;
            v += ck * t0;
            if (first) d1 += ck * e0;
            if (second) d2 += ck * f0;
            t1 = t2 * t0 - t1;
            if (first) e1 = 2.0 * t0 + t2 * e0 - e1;
            if (second) f1 = 4.0 * e0 + t2 * f0 - f1;
            v += cn * t1;
            if (first) d1 += cn * e1;
            if (second) d2 += cn * f1;
        }
        if (k <= mn) {
            v2 ck = {ca[k], cb[k]};
            v2 tn = t2 * t1 - t0;
            v2 en = first ? 2.0 * t1 + t2 * e1 - e0 : e1;
            v2 fn = second ? 4.0 * e1 + t2 * f1 - f0 : f1;
            v += ck * tn;
            if (first) d1 += ck * en;
            if (second) d2 += ck * fn;
            t0 = t1, t1 = tn, e0 = e1, e1 = en, f0 = f1, f1 = fn;
        }
        for (int l = 0; l < 2; ++l) { /* the higher degree's rest */
            const double *c = l ? cb : ca;
            uint32_t m = l ? mb : ma;
            double x0 = t0[l], x1 = t1[l], y0 = e0[l], y1 = e1[l], z0 = f0[l], z1 = f1[l], x2 = t2[l];
            double vv = v[l], w1 = d1[l], w2 = d2[l];
            for (uint32_t j = mn + 1; j <= m; j++) {
                double tn = x2 * x1 - x0;
                double en = first ? 2.0 * x1 + x2 * y1 - y0 : y1;
                double fn = second ? 4.0 * y1 + x2 * z1 - z0 : z1;
                vv += c[j] * tn;
                if (first) w1 += c[j] * en;
                if (second) w2 += c[j] * fn;
                x0 = x1, x1 = tn, y0 = y1, y1 = en, z0 = z1, z1 = fn;
            }
            p[l] = vv, p1[l] = w1, p2[l] = w2;
        }
    }
    term fa = {ca, ma, a->squared}, fb = {cb, mb, b->squared};
    if (!first) return gs__fun_term_value(&fa, p[0]) + gs__fun_term_value(&fb, p[1]);
    double a1, a2, b1, b2;
    double v = gs__fun_term_post(&fa, p[0], p1[0], p2[0], &a1, &a2) + gs__fun_term_post(&fb, p[1], p1[1], p2[1], &b1, &b2);
    *s1 = a1 + b1, *s2 = a2 + b2;
    return v;
}

static double pair_at3(const gs__fun *a, const gs__fun *b, double u, double *s1, double *s2)
{
    return pair_at(a, b, u, s1, s2, 3);
}

/* pair_at3's value and slope alone: for the probes that use no curvature
 * (a loop's windows and dips). */
static double pair_at2(const gs__fun *a, const gs__fun *b, double u, double *s1)
{
    double s2;
    return pair_at(a, b, u, s1, &s2, 2);
}

/* pair_at3's value alone: Newton's last point needs no slopes. */
static double pair_at1(const gs__fun *a, const gs__fun *b, double u)
{
    return pair_at(a, b, u, NULL, NULL, 1);
}

/* Newton on the slope of the sum from u (steps kept within +-h, a cell),
 * `steps` times; updates (*best, *bu) with every point it evaluates. *exact
 * says whether *best is pair_value(a, b, *bu) (else it came from the
 * derivative recurrences and is evaluated again at the end). */
#define NEWTON_STEPS 2 /* from a sharp function's own minimiser          */
#define DIP_INSIDE 1e-7 /* zero-set edges: this fraction of the way in   */
static void newton_candidate(const gs__fun *a, const gs__fun *b, double u, double h, int closed,
                             int steps, double *best, double *bu, int *exact)
{
    if (steps == 0) { /* the value alone: two Clenshaw sums */
        double v = pair_value(a, b, u);
        if (v < *best) *best = v, *bu = u, *exact = 1;
        return;
    }
    for (int it = 0; it <= steps; ++it) {
        if (it == steps) { /* the last point: its value alone */
            double v = pair_at1(a, b, u);
            if (v < *best) *best = v, *bu = u, *exact = 0;
            return;
        }
        double s1, s2, v = pair_at3(a, b, u, &s1, &s2);
        if (v < *best) *best = v, *bu = u, *exact = 0;
        if (!(s2 > 0.0)) return;
        double step = -s1 / s2;
        step = step < -h ? -h : (step > h ? h : step);
        double w = closed ? gs__fun_wrap(u + step) : gs__fun_clamp1(u + step);
        if (fabs(w - u) <= 1e-12) return;
        u = w;
    }
}

/* The minimum of the sum over a window [lo, hi] of a loop (u may leave
 * [-1,1): the functions wrap it) where the grid's parabola cannot be
 * trusted: near a sharp dip (a hyperbola-like kink plus a slope) or beside
 * a seam (the fit jumps there). Values and slopes at WINDOW_PTS points; the
 * lowest one's neighbour in the downhill direction brackets the minimum
 * (the slope changes sign), where Newton on the slope, kept inside the
 * shrinking bracket (bisection when it would leave it), runs to |step| <=
 * 1e-10. Returns 0 when the samples bracket nothing clearly (the caller
 * then uses the robust minimiser), 1 otherwise (the window's minimum is
 * then a candidate, or lies at an end that slopes outward). */
#define WINDOW_PTS 5
#define BRACKET_ITERS 40
/* The minimum of the sum inside a bracket xl < xr of a loop's parameter
 * where its slope goes from dl < 0 to dr > 0: Newton on the slope from the
 * secant's root, kept inside the shrinking bracket (bisection when it would
 * leave it), to |step| <= 1e-10 or a predicted gain below STOP_REL. */
static void bracket_min(const gs__fun *a, const gs__fun *b, double xl, double xr, double dl, double dr, double *best,
                        double *bu, int *exact)
{
    double s2, t = xl - dl * (xr - xl) / (dr - dl); /* secant start */
    for (int it = 0; it < BRACKET_ITERS; ++it) {
        double s1, w = pair_at3(a, b, t, &s1, &s2);
        if (w < *best) *best = w, *bu = gs__fun_wrap(t), *exact = 0;
        if (s1 == 0.0) return;
        if (s1 < 0.0) xl = t;
        else xr = t;
        double y = s2 > 0.0 ? t - s1 / s2 : 0.5 * (xl + xr);
        if (!(y > xl && y < xr)) y = 0.5 * (xl + xr);
        else if (0.5 * fabs(s1 * (y - t)) <= STOP_REL * w) return; /* Newton's gain: tiny */
        if (fabs(y - t) <= 1e-10 || xr - xl <= 1e-10) return;
        t = y;
    }
}

static int window_min(const gs__fun *a, const gs__fun *b, double lo, double hi, double *best, double *bu,
                      int *exact)
{
    double x[WINDOW_PTS], v[WINDOW_PTS], d[WINDOW_PTS];
    int i = 0;
    for (int k = 0; k < WINDOW_PTS; ++k) {
        x[k] = lo + (hi - lo) * k / (WINDOW_PTS - 1);
        v[k] = pair_at2(a, b, x[k], &d[k]);
        if (v[k] < v[i]) i = k;
    }
    if (v[i] < *best) *best = v[i], *bu = gs__fun_wrap(x[i]), *exact = 0;
    for (int k = 0; k < WINDOW_PTS; ++k)
        if (d[k] != d[k]) return 0; /* slopes that are not numbers: the robust minimiser */
    if (d[i] == 0.0 || (i == 0 && d[i] > 0.0) || (i == WINDOW_PTS - 1 && d[i] < 0.0)) return 1;
    int l = d[i] < 0.0 ? i : i - 1, r = l + 1;
    if (!(d[l] < 0.0 && d[r] > 0.0)) return 0;
    bracket_min(a, b, x[l], x[r], d[l], d[r], best, bu, exact);
    return 1;
}

/* The minimum of the sum beside a's sharp dip at u (no zero set), within
 * lim either side: at u, a's slope is 0 and the sum's slope m is b's; on a
 * hyperbola sqrt(a(u)^2 + (L s)^2) (L = the dip's slope) a's slope reaches
 * -m at the offset s = a(u) m / (L sqrt(L^2 - m^2)) downhill. Probes there
 * (and twice as far while the slope keeps its sign, up to lim) bracket the
 * minimum for bracket_min. Returns 0 when the slopes are not numbers (the
 * caller then uses the robust minimiser), 1 otherwise (a minimum beyond
 * lim is the grid's to find). */
static int dip_min(const gs__fun *a, const gs__fun *b, double u, double L, double lim, double *best, double *bu,
                   int *exact)
{
    double s1, v = pair_at2(a, b, u, &s1);
    if (v < *best) *best = v, *bu = gs__fun_wrap(u), *exact = 0;
    if (s1 == 0.0) return 1;
    if (s1 != s1) return 0;
    double dir = s1 < 0.0 ? 1.0 : -1.0, m = fabs(s1);
    double am = a->minval > 0.0 ? a->minval : 0.0;
    double x = L > m ? 1.25 * am * m / (L * sqrt((L - m) * (L + m))) : lim;
    x = x < lim ? (x > 1e-9 * lim ? x : 1e-9 * lim) : lim;
    double xin = 0.0, din = -m; /* the bracket's inner end, along dir */
    for (;;) {
        double t = u + dir * x, t1;
        double w = pair_at2(a, b, t, &t1);
        if (w < *best) *best = w, *bu = gs__fun_wrap(t), *exact = 0;
        double dt = dir * t1; /* the slope along dir */
        if (dt != dt) return 0;
        if (dt >= 0.0) {
            if (dt == 0.0) return 1;
            if (dir > 0.0) bracket_min(a, b, u + xin, t, din, dt, best, bu, exact);
            else bracket_min(a, b, t, u - xin, -dt, -din, best, bu, exact);
            return 1;
        }
        if (x >= lim) return 1; /* still downhill at the window's end */
        xin = x, din = dt;
        x = 2.0 * x < lim ? 2.0 * x : lim;
    }
}

/* s = va + vb on the g grid points; returns min s. */
static float grid_sum(const float *va, const float *vb, uint32_t g, float *s)
{
    uint32_t j = 0;
    float mn = INFINITY;
#ifdef __SSE2__
    __m128 vm = _mm_set1_ps(INFINITY);
    for (; j + 4 <= g; j += 4) {
        __m128 v = _mm_add_ps(_mm_loadu_ps(va + j), _mm_loadu_ps(vb + j));
        _mm_storeu_ps(s + j, v);
        vm = _mm_min_ps(vm, v);
    }
    float m4[4];
    _mm_storeu_ps(m4, vm);
    mn = m4[0] < m4[1] ? m4[0] : m4[1];
    mn = mn < m4[2] ? mn : m4[2];
    mn = mn < m4[3] ? mn : m4[3];
#endif
    for (; j < g; ++j) {
        float v = va[j] + vb[j];
        s[j] = v;
        mn = v < mn ? v : mn;
    }
    return mn;
}

/* The grid's candidate points, s[j] = e[j + 1] for j < g with e[0] and
 * e[g + 1] the neighbours of the ends (a loop's other end, else INFINITY)
 * and e readable to e[g + 4]: *j1 the first j with s[j] <= thr and s[j] ==
 * mn; *j2 the first j != *j1 of the lowest s[j] <= thr that is a discrete
 * local minimum (ties included); GS_NONE_U32 when there is none. */
static void grid_minima(const float *e, uint32_t g, float mn, float thr, uint32_t *j1, uint32_t *j2)
{
    uint32_t a = GS_NONE_U32, b = GS_NONE_U32;
    float bv = 0.0f;
#ifdef __SSE2__
    __m128 t = _mm_set1_ps(thr), m = _mm_set1_ps(mn);
    for (uint32_t j = 0; j < g; j += 4) {
        __m128 c = _mm_loadu_ps(e + j + 1);
        unsigned le = (unsigned)_mm_movemask_ps(_mm_cmple_ps(c, t));
        if (!le) continue;
        if (g - j < 4) le &= (1u << (g - j)) - 1u;
        if (a == GS_NONE_U32) {
            unsigned eq = le & (unsigned)_mm_movemask_ps(_mm_cmpeq_ps(c, m));
            if (eq) a = j + (uint32_t)__builtin_ctz(eq);
        }
        unsigned lm = le & (unsigned)_mm_movemask_ps(_mm_cmple_ps(c, _mm_loadu_ps(e + j))) &
                      (unsigned)_mm_movemask_ps(_mm_cmple_ps(c, _mm_loadu_ps(e + j + 2)));
        for (; lm; lm &= lm - 1) {
            uint32_t i = j + (uint32_t)__builtin_ctz(lm);
            if (i != a && (b == GS_NONE_U32 || e[i + 1] < bv)) b = i, bv = e[i + 1];
        }
    }
#else
    for (uint32_t j = 0; j < g; ++j) {
        float c = e[j + 1];
        if (!(c <= thr)) continue;
        if (a == GS_NONE_U32 && c == mn) a = j;
        if (j != a && (b == GS_NONE_U32 || c < bv) && c <= e[j] && c <= e[j + 2]) b = j, bv = c;
    }
#endif
    *j1 = a, *j2 = b;
}

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
/* grid_minima eight points at a time (AVX2 hosts; e readable to e[g + 8]):
 * the same points, found in the same order. The comparisons of each vector
 * go into bit masks of the whole grid (g <= 96: two words) without a
 * branch; then j1 is the first bit of (<= thr and == mn), j2 the first of
 * the lowest among the other local minima <= thr (usually none or one). */
__attribute__((target("avx2"))) static void grid_minima8(const float *e, uint32_t g, float mn, float thr,
                                                         uint32_t *j1, uint32_t *j2)
{
    uint64_t eq[2] = {0, 0}, lm[2] = {0, 0};
    __m256 t = _mm256_set1_ps(thr), m = _mm256_set1_ps(mn);
    for (uint32_t j = 0; j < g; j += 8) {
        __m256 c = _mm256_loadu_ps(e + j + 1);
        uint64_t le = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(c, t, _CMP_LE_OQ));
        uint64_t q = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(c, m, _CMP_EQ_OQ));
        uint64_t n = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(c, _mm256_loadu_ps(e + j), _CMP_LE_OQ)) &
                     (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(c, _mm256_loadu_ps(e + j + 2), _CMP_LE_OQ));
        eq[j >> 6] |= (le & q) << (j & 63);
        lm[j >> 6] |= (le & n) << (j & 63);
    }
    /* the points beyond the grid */
    uint64_t v0 = g >= 64 ? ~0ull : (1ull << g) - 1, v1 = g > 64 ? (g >= 128 ? ~0ull : (1ull << (g - 64)) - 1) : 0;
    eq[0] &= v0, eq[1] &= v1, lm[0] &= v0, lm[1] &= v1;
    gs__grid_marks_pick(eq, lm, e + 1, j1, j2);
}
#endif

/* A loop's seam lies in (u_{j-1}, u_{j+1}] (closed grid, with a little
 * slack): there the fit may jump, and no parabola describes the sum. */
static int seam_near(const gs__fun *f, uint32_t j, uint32_t g)
{
    double sigma = (gs__fun_wrap(f->shift - 1.0) + 1.0) * 0.5 * g; /* seam in grid units */
    double d = sigma - ((double)j - 1.0);
    if (d < 0.0) d += g;
    if (d >= g) d -= g;
    return d <= 2.0 + 1e-9 * g || d >= g - 1e-9 * g;
}

/* Candidates of a sharp function's dip: near its own minimiser (Newton, or
 * for loops the window of DIP_WINDOW cells either side), and both edges of
 * its zero set (a little inside), where the sum of a clamped fit and a
 * smooth function has its kink. Returns window_min's verdict. */
#define DIP_WINDOW 1.5
static int dip_candidates(const gs__fun *a, const gs__fun *b, const gs__fun_dip *d, double h, int closed,
                          double *best, double *bu, int *exact)
{
    if (!d || d->u != d->u || !gs__fun_sharp_dip(a)) return 1;
    if (!closed) newton_candidate(a, b, d->u, h, closed, NEWTON_STEPS, best, bu, exact);
    else if (d->slope > 0.0) return dip_min(a, b, d->u, d->slope, DIP_WINDOW * h, best, bu, exact);
    else if (!window_min(a, b, d->u - DIP_WINDOW * h, d->u + DIP_WINDOW * h, best, bu, exact)) return 0;
    double pull = 0.5 * (d->hi - d->lo) * DIP_INSIDE;
    if (!(pull > 0.0)) return 1;
    /* the sum at both edges (a little inside), evaluated together */
    double x0 = d->lo + pull, x1 = d->hi - pull, v0, v1;
    x0 = closed ? gs__fun_wrap(x0) : gs__fun_clamp1(x0);
    x1 = closed ? gs__fun_wrap(x1) : gs__fun_clamp1(x1);
    pair_value2(a, b, x0, x1, &v0, &v1);
    if (v0 < *best) *best = v0, *bu = x0, *exact = 1;
    if (v1 < *best) *best = v1, *bu = x1, *exact = 1;
    return 1;
}

uint32_t gs__fun_seam_cell(const gs__fun *f, uint32_t g)
{
    double sigma = (gs__fun_wrap(f->shift - 1.0) + 1.0) * 0.5 * g; /* in [0, g]; NaN for a NaN shift */
    return sigma >= 0.0 && sigma < g ? (uint32_t)sigma : g - 1;
}

/* Whether f's seam (a loop's fit may jump there) may hold the minimum of
 * the sum: the lower of f's two one-sided limits there (p(1), p(-1)) plus
 * the other function's lower grid value beside the seam is not above thr.
 * The seam's cell comes from d when the caller kept it. */
static int seam_low(const gs__fun *f, const gs__fun_dip *d, const float *vo, uint32_t g, float thr)
{
    uint32_t j = d && d->seam_cell < g ? d->seam_cell : gs__fun_seam_cell(f, g);
    float q0 = vo[j], q1 = vo[j + 1 < g ? j + 1 : 0];
    float o = q0 < q1 ? q0 : q1;
    double v = d && d->seam == d->seam ? d->seam : gs__fun_seam_value(f);
    return v + o <= thr * (1.0 + 1e-6);
}

/* Both sides of f's seam (at u_s, where f's t = wrap(u - shift) passes
 * from 1 to -1): windows of SEAM_WINDOW cells on either side, ending
 * SEAM_EPS short of it, each searched by window_min (the one-sided limits
 * are their inner ends). They cover every grid cell beside the seam. */
#define SEAM_WINDOW 2.5
#define SEAM_EPS 1e-12
static int seam_windows(const gs__fun *f, const gs__fun *o, double h, double *best, double *bu, int *exact)
{
    double us = gs__fun_wrap(f->shift - 1.0), w = SEAM_WINDOW * h;
    return window_min(f, o, us - w, us - SEAM_EPS, best, bu, exact) &&
           window_min(f, o, us + SEAM_EPS, us + w, best, bu, exact);
}

/* Whether the grid minimiser takes the pair (else gs__fun_pair_min). */
static inline int grid_ok(const gs__fun *a, const gs__fun *b, uint32_t g)
{
    /* gs__fun_unreachable, inline */
    return !(!a->coef || !(a->minval < INFINITY) || !b->coef || !(b->minval < INFINITY) || g < 3 || g > GS_FUN_GRID_MAX ||
             a->kind == GS_FUN_SAMPLED || b->kind == GS_FUN_SAMPLED || a->closed != b->closed);
}

static double grid_core(const gs__fun *a, const gs__fun *b, float *e, float mn, const float *ga, const float *gb,
                        const uint32_t *jm, uint32_t g, const gs__fun_dip *da, const gs__fun_dip *db, double *u_at);

double gs__fun_pair_min_grid(const gs__fun *a, const gs__fun *b, const float *ga, const float *gb, uint32_t g,
                            const gs__fun_dip *da, const gs__fun_dip *db, double *u_at)
{
    if (!grid_ok(a, b, g)) return gs__fun_pair_min(a, b, u_at);
    float e[GS_FUN_GRID_MAX + 16]; /* s = e + 1 with its ends' neighbours (grid_minima) */
    float mn = grid_sum(ga, gb, g, e + 1);
    return grid_core(a, b, e, mn, ga, gb, NULL, g, da, db, u_at);
}

double gs__fun_pair_min_grid_sum(const gs__fun *a, const gs__fun *b, float *e, float mn, uint32_t g,
                                const uint32_t *jm, const gs__fun_dip *da, const gs__fun_dip *db, double *u_at)
{
    if (!grid_ok(a, b, g) || a->closed) return gs__fun_pair_min(a, b, u_at);
    return grid_core(a, b, e, mn, NULL, NULL, jm, g, da, db, u_at);
}

/* The grid minimiser on the sum s = e + 1 of the two functions' grid
 * values (min mn); ga, gb: each function's own values (loops only); jm:
 * the grid's candidate points when the caller found them (paths only),
 * else NULL. */
static double grid_core(const gs__fun *a, const gs__fun *b, float *e, float mn, const float *ga, const float *gb,
                        const uint32_t *jm, uint32_t g, const gs__fun_dip *da, const gs__fun_dip *db, double *u_at)
{
    int closed = a->closed != 0;
    float *s = e + 1;
    if (!(mn <= FLT_MAX)) return gs__fun_pair_min(a, b, u_at); /* beyond float range (or NaN) */
    /* j1: the lowest grid value (a discrete local minimum); j2: the lowest
     * other discrete local minimum when the grid cannot tell it from j1 */
    uint32_t j1 = GS_NONE_U32, j2 = GS_NONE_U32;
    float thr = mn * 1.02f;
    /* loops: a seam that may hold the minimum (the fit jumps there) is
     * searched on both sides below; two such seams close to each other go
     * to the robust minimiser */
    int sa = closed && seam_low(a, da, gb, g, thr), sb = closed && seam_low(b, db, ga, g, thr);
    if (sa && sb && fabs(gs__fun_wrap(a->shift - b->shift + 1.0) - 1.0) < 4.0 * SEAM_WINDOW * 2.0 / g)
        return gs__fun_pair_min(a, b, u_at);
    if (jm) {
        j1 = jm[0], j2 = jm[1];
    } else {
        e[0] = closed ? s[g - 1] : INFINITY;
        e[g + 1] = closed ? s[0] : INFINITY;
        e[g + 2] = e[g + 3] = e[g + 4] = 0.0f;
#if defined(__x86_64__) && defined(__GNUC__)
        if (__builtin_cpu_supports("avx2")) {
            for (uint32_t j = g + 2; j < g + 9; ++j) e[j] = 0.0f;
            grid_minima8(e, g, mn, thr, &j1, &j2);
        } else
#endif
            grid_minima(e, g, mn, thr, &j1, &j2);
    }
    if (j1 == GS_NONE_U32) return gs__fun_pair_min(a, b, u_at); /* cannot happen */
    double h = closed ? 2.0 / g : 2.0 / (g - 1), best = INFINITY, bu = 0.0;
    /* loops whose pairs went to the robust minimiser before (a dip or a
     * seam): Newton from the parabola's vertex too */
    int dipped = closed && ((da && da->u == da->u) || (db && db->u == db->u) || sa || sb);
    int exact = 1;
    double pts[4]; /* paths: the candidates' points (an end cell: two each), evaluated in pairs below */
    int npts = 0;
    for (int c = 0; c < 2; ++c) {
        uint32_t jb = c ? j2 : j1;
        if (jb == GS_NONE_U32) continue;
        /* a loop's seam beside the minimum: the robust minimiser */
        int na = closed && seam_near(a, jb, g), nb = closed && seam_near(b, jb, g);
        if ((na && !sa) || (nb && !sb)) return gs__fun_pair_min(a, b, u_at);
        if (na || nb) continue; /* inside a seam's window */
        double u0 = grid_u(jb, g, closed);
        if (!closed && (jb == 0 || jb + 1 == g) && g >= 3) { /* a path's end: the end, or inside its cell */
            uint32_t m = jb ? g - 2 : 1;
            double sl = s[m - 1], sc = s[m], sr = s[m + 1], den = sl - 2.0 * sc + sr;
            double t = den > 0.0 ? 0.5 * (sl - sr) / den : 0.0;
            if (jb ? t > 0.0 && t < 1.0 : t < 0.0 && t > -1.0) pts[npts++] = grid_u(m, g, 0) + t * h;
        } else { /* parabola through the neighbours */
            double sl = s[jb ? jb - 1 : g - 1], sc = s[jb], sr = s[jb + 1 < g ? jb + 1 : 0];
            double den = sl - 2.0 * sc + sr;
            if (den > 0.0) {
                double t = 0.5 * (sl - sr) / den;
#ifndef NO_CUBIC
                /* the cubic through a fourth point on t's side (paths);
                 * t's sign is (sl - sr)'s (exact for floats in double; a
                 * finite den > 0), so the side is known without waiting
                 * for the division (an infinite den: t is NaN, not > 0) */
                int fin = den < INFINITY, right = fin && sl > sr;
                if (!closed && (!fin || sl != sr) && (right ? jb + 2 < g : jb >= 2)) {
                    double dir = right ? 1.0 : -1.0, ym = right ? sl : sr, yp = right ? sr : sl;
                    double y2 = s[right ? jb + 2 : jb - 2];
                    /* p(x) = sc + aq x + bq x^2 + c3 x^3 through the four
                     * points (x = -1, 0, 1, 2 along dir); its minimum is the
                     * root of p' = aq + 2 bq x + 3 c3 x^2 where p'' = 2 bq +
                     * 6 c3 x > 0. With q = -(bq + sign(bq) r), r = sqrt(disc),
                     * the roots are q / (3 c3) and aq / q, and p'' at the
                     * first is -2 sign(bq) r: the minimum is the first only
                     * for bq < 0 < r. c6 = 6 c3 without a division (on the
                     * latency chain of every refined pair). */
                    double bq = 0.5 * (yp + ym) - sc, c6 = (y2 - sc - 4.0 * bq) - (yp - ym);
                    double aq = 0.5 * (yp - ym) - c6 * (1.0 / 6.0), disc = bq * bq - 0.5 * aq * c6, x;
                    if (fabs(c6) <= 6e-12 * fabs(bq)) x = -aq / (2.0 * bq);
                    else if (disc >= 0.0) {
                        double r = sqrt(disc), q = -(bq + (bq >= 0.0 ? r : -r));
                        x = bq < 0.0 && r > 0.0 ? 2.0 * q / c6 : (q != 0.0 ? aq / q : 2.0 * q / c6);
                    } else x = dir * t;
                    if (x >= -1.0 && x <= 1.5) t = dir * x;
                }
#endif
                u0 += (t < -1.0 ? -1.0 : (t > 1.0 ? 1.0 : t)) * h;
                u0 = closed ? gs__fun_wrap(u0) : gs__fun_clamp1(u0);
            }
        }
        if (!closed) pts[npts++] = u0;
        else newton_candidate(a, b, u0, h, closed, dipped ? NEWTON_STEPS : 0, &best, &bu, &exact);
    }
    /* newton_candidate's value-only update for each, in the same order */
    for (int i = 0; i < npts; i += 2) {
        if (i + 1 == npts) {
            newton_candidate(a, b, pts[i], h, 0, 0, &best, &bu, &exact);
            break;
        }
        double v0, v1;
        pair_value2(a, b, pts[i], pts[i + 1], &v0, &v1);
        if (v0 < best) best = v0, bu = pts[i], exact = 1;
        if (v1 < best) best = v1, bu = pts[i + 1], exact = 1;
    }
    /* a vertex close to the curve gives its function a sharp dip, which the
     * grid may step over: the dip's own minimiser is a candidate too */
    if ((da && da->u == da->u && !dip_candidates(a, b, da, h, closed, &best, &bu, &exact)) ||
        (db && db->u == db->u && !dip_candidates(b, a, db, h, closed, &best, &bu, &exact)) ||
        (sa && !seam_windows(a, b, h, &best, &bu, &exact)) ||
        (sb && !seam_windows(b, a, h, &best, &bu, &exact)))
        return gs__fun_pair_min(a, b, u_at);
    if (u_at) *u_at = bu;
    return exact && best < INFINITY ? best : pair_value(a, b, bu); /* the value as evaluated */
}
