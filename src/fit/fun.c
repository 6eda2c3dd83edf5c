/* fun.c - a separator distance function alone (paper sec. 4.2, 4.3): its
 * value, its minimum (a coarse Chebyshev-Lobatto scan, then safeguarded
 * Newton on the analytic derivative), its dip and cost; and the parts of
 * the minimisation that the queries' pair minimisers share
 * (fun_internal.h; the pair minimisers: src/query/pair_min.c). */
#include "fun_internal.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#ifdef GS_FUN_STATS
long gs__fun_stat[8];
#endif



double gs__fun_term_at(const term *f, double t)
{
    return gs__fun_term_value(f, gs__cheb_eval(f->c, f->m, gs__fun_clamp1(t)));
}

/* Value, first and second derivative of one term (0 where clamped). */
double gs__fun_term_post(const term *f, double p, double p1, double p2, double *v1, double *v2)
{
    if (!(p > 0.0)) {
        *v1 = *v2 = 0.0;
        return 0.0;
    }
    if (!f->sq) {
        *v1 = p1, *v2 = p2;
        return p;
    }
    double s = sqrt(p);
    *v1 = 0.5 * p1 / s;
    *v2 = (0.5 * p2 - *v1 * *v1) / s;
    return s;
}

double gs__fun_term_at3(const term *f, double t, double *v1, double *v2)
{
    double p, p1, p2;
    gs__cheb_eval3(f->c, f->m, gs__fun_clamp1(t), &p, &p1, &p2);
    return gs__fun_term_post(f, p, p1, p2, v1, v2);
}



double gs__fun_seg_eval3(const pctx *c, int seg, double x, double *s1, double *s2)
{
    STAT(0);
    double v = gs__fun_term_at3(&c->a, x, s1, s2);
    if (c->b.c) {
        double b1, b2;
        v += gs__fun_term_at3(&c->b, x + c->off[seg], &b1, &b2);
        *s1 += b1, *s2 += b2;
    }
    return v;
}

/* out[j] (+)= term value at the n points t[j], or at the grid nodes through
 * the table tk (rows >= m+1, stride n) when tk != NULL. */
static void term_points(const term *f, const double *tk, const double *t, uint32_t n,
                        double *out, int accumulate)
{
    double p[NPTS_MAX];
    if (tk) {
        for (uint32_t j = 0; j < n; j++)
            p[j] = f->c[0] * tk[j];
        for (uint32_t k = 1; k <= f->m; k++) {
            const double ck = f->c[k], *row = tk + (size_t)k * n;
            for (uint32_t j = 0; j < n; j++)
                p[j] += ck * row[j];
        }
    } else {
        for (uint32_t j = 0; j < n; j++)
            p[j] = gs__cheb_eval(f->c, f->m, t[j]);
    }
    for (uint32_t j = 0; j < n; j++) {
        double v = gs__fun_term_value(f, p[j]);
        out[j] = accumulate ? out[j] + v : v;
    }
}


/* Local minimum inside the bracket a <= m <= b (s(m) <= s(a), s(b); m may
 * equal an end when s'(m) points inside): Newton trial points from m, or a
 * step into the descending half; the bracket invariant is kept throughout.
 * A Newton step whose predicted gain is negligible is taken without a new
 * evaluation (the caller evaluates the final minimiser). */
static void refine_from(const pctx *c, int seg, double a, double b, double m, double sm,
                        double s1, double s2, best *bs)
{
    gs__fun_best_update(bs, m, sm, seg);
    for (int it = 0; it < 64 && sm > 0.0 && s1 != 0.0 && b - a > 4e-16; it++) {
        double t = s2 > 0.0 ? m - s1 / s2 : NAN;
        if (!(t > a && t < b) || (t - m) * s1 > 0.0) {
            t = s1 < 0.0 ? m + 0.5 * (b - m) : m - 0.5 * (m - a);
        } else if (fabs(t - m) * fabs(s1) <= STOP_REL * sm) {
            gs__fun_best_update(bs, t, sm - 0.5 * fabs(s1 * (t - m)), seg);
            return;
        }
        if (t == m)
            return;
        double t1, t2, st = gs__fun_seg_eval3(c, seg, t, &t1, &t2);
        gs__fun_best_update(bs, t, st, seg);
        if (st < sm) {
            (t > m ? (a = m) : (b = m));
            m = t, sm = st, s1 = t1, s2 = t2;
        } else {
            (t > m ? (b = t) : (a = t));
        }
    }
}

void gs__fun_refine(const pctx *c, int seg, double a, double b, double m, best *bs)
{
    double s1, s2, sm = gs__fun_seg_eval3(c, seg, m, &s1, &s2);
    refine_from(c, seg, a, b, m, sm, s1, s2, bs);
}

/* Interior discrete minimum i: start at the vertex of the parabola through
 * the three samples when it improves on sample i. */
static void refine_interior(const pctx *c, int seg, const double *x, const double *v, uint32_t i,
                            best *bs)
{
    double a = x[i - 1], m = x[i], b = x[i + 1];
    double p = (m - a) * (v[i] - v[i + 1]), q = (m - b) * (v[i] - v[i - 1]);
    double den = 2.0 * (p - q), xv = den != 0.0 ? m - ((m - a) * p - (m - b) * q) / den : m;
    if (xv > a && xv < b && xv != m) {
        double s1, s2, sv = gs__fun_seg_eval3(c, seg, xv, &s1, &s2);
        if (sv <= v[i]) {
            refine_from(c, seg, xv < m ? a : m, xv < m ? m : b, xv, sv, s1, s2, bs);
            return;
        }
        (xv < m ? (a = xv) : (b = xv));
    }
    gs__fun_refine(c, seg, a, b, m, bs);
}

/* Refine every discrete local minimum of the n samples (xs, vs) of one
 * segment; the samples themselves are candidates too. */
static void scan_segment(const pctx *c, int seg, const double *xs, const double *vs, uint32_t n,
                         best *b)
{
    for (uint32_t i = 0; i < n; i++)
        gs__fun_best_update(b, xs[i], vs[i], seg);
    for (uint32_t i = 0; i < n && n > 1; i++) {
        double v = vs[i];
        if ((i > 0 && vs[i - 1] < v) || (i + 1 < n && vs[i + 1] <= v))
            continue;
        if (b->v <= 0.0)
            return;
        if (i == 0 || i + 1 == n) /* segment end: a minimum there, or inside */
            gs__fun_refine(c, seg, i ? xs[i - 1] : xs[0], i ? xs[i] : xs[1], xs[i], b);
        else
            refine_interior(c, seg, xs, vs, i, b);
    }
}

/* Minimum of the raw series p near t in [lo, hi]: safeguarded Newton on p'. */
double gs__fun_poly_min(const term *f, double lo, double hi, double t, double *p0)
{
    for (int it = 0; it < 40; it++) {
        STAT(7);
        double p1, p2;
        gs__cheb_eval3(f->c, f->m, t, p0, &p1, &p2);
        if (p1 > 0.0)
            hi = t;
        else
            lo = t;
        double tn = p2 > 0.0 ? t - p1 / p2 : NAN;
        if (!(tn > lo && tn < hi))
            tn = 0.5 * (lo + hi);
        if (fabs(tn - t) < 1e-15)
            break;
        t = tn;
    }
    return t;
}

/* A root of p by Newton from t, kept inside [lo, hi]. */
double gs__fun_poly_root(const term *f, double lo, double hi, double t)
{
    for (int it = 0; it < 30; it++) {
        double p, p1, p2;
        gs__cheb_eval3(f->c, f->m, t, &p, &p1, &p2);
        double tn = p1 != 0.0 ? t - p / p1 : t;
        tn = tn < lo ? lo : (tn > hi ? hi : tn);
        if (fabs(tn - t) < 1e-15)
            return tn;
        t = tn;
    }
    return t;
}

/* Refine the sum from t, a parameter of term a or b, within +-h. */
static void add_candidate(const pctx *c, int is_b, double t, double h, best *bs)
{
    int seg = 0;
    double x = is_b ? t - c->off[0] : t;
    if (c->split < 1.0 && (x > c->split || x < -1.0 || (!is_b && x == c->split)))
        x = is_b ? t - c->off[1] : x, seg = 1;
    double lo = seg ? c->split : -1.0, hi = c->split < 1.0 && !seg ? c->split : 1.0;
    x = x < lo ? lo : (x > hi ? hi : x);
    if (c->eval_only) { /* the pair minimiser's cells refine the rest */
        double s1, s2;
        gs__fun_best_update(bs, x, gs__fun_seg_eval3(c, seg, x, &s1, &s2), seg);
        return;
    }
    gs__fun_refine(c, seg, x - h > lo ? x - h : lo, x + h < hi ? x + h : hi, x, bs);
}

/* A sharp term (a vertex near the curve) has a dip narrower than the coarse
 * grid: refine the sum from its own minimum t0 and, where the fit dips
 * below 0 (value clamped), from the edges of that zero set. */
void gs__fun_sharp_candidates(const pctx *c, int is_b, const gs__cheb_grid *gp, const double *pg,
                             best *bs)
{
    const term *f = is_b ? &c->b : &c->a;
    STAT(3);
    const gs__cheb_grid *g = pg ? gp : gs__cheb_grid_for(f->m);
    uint32_t n = g->g + 1, j = 0;
    double pbuf[NPTS_MAX], h = 2.0 / g->g, p0, p1, p2;
    const double *p = pg;
    if (!p) {
        term raw = {f->c, f->m, 0};
        term_points(&raw, g->tk, g->x, n, pbuf, 0);
        p = pbuf;
    }
    for (uint32_t i = 1; i < n; i++)
        j = p[i] < p[j] ? i : j;
    double t0 = gs__fun_poly_min(f, g->x[j ? j - 1 : 0], g->x[j + 1 < n ? j + 1 : j], g->x[j], &p0);
    if (p0 > 0.0) {
        add_candidate(c, is_b, t0, h, bs);
        return;
    }
    gs__cheb_eval3(f->c, f->m, t0, &p0, &p1, &p2);
    double w = p2 > 0.0 ? sqrt(-2.0 * p0 / p2) : h;
    double r1 = gs__fun_poly_root(f, -1.0, t0, t0 - w), r2 = gs__fun_poly_root(f, t0, 1.0, t0 + w);
    add_candidate(c, is_b, r1 + ZERO_NUDGE < t0 ? r1 + ZERO_NUDGE : t0, h, bs);
    add_candidate(c, is_b, r2 - ZERO_NUDGE > t0 ? r2 - ZERO_NUDGE : t0, h, bs);
}

/* Minimise over x in [-1,1] from the n grid nodes x (table tk or NULL). */
best gs__fun_minimise(const pctx *c, const double *x, const double *tk, uint32_t n)
{
    double s[NPTS_MAX], tb[NPTS_MAX], xs[NPTS_MAX], vs[NPTS_MAX];
    best b = {INFINITY, 0.0, 0};
    term_points(&c->a, tk, x, n, s, 0);
    if (c->b.c) {
        if (c->split > 1.0 && c->off[0] == 0.0) {
            term_points(&c->b, tk, x, n, s, 1);
        } else {
            for (uint32_t j = 0; j < n; j++)
                tb[j] = gs__fun_clamp1(x[j] + c->off[x[j] < c->split ? 0 : 1]);
            term_points(&c->b, NULL, tb, n, s, 1);
        }
    }
    for (int i = 0; i < 2; i++)
        if (c->sharp[i] && (i == 0 || c->b.c))
            gs__fun_sharp_candidates(c, i, NULL, NULL, &b);
    if (!(c->split < 1.0)) {
        scan_segment(c, 0, x, s, n, &b);
        return b;
    }
    uint32_t j0 = 0;
    while (j0 < n && x[j0] < c->split)
        j0++;
    double va = gs__fun_term_at(&c->a, c->split);
    for (uint32_t j = 0; j < j0; j++)
        xs[j] = x[j], vs[j] = s[j];
    xs[j0] = c->split, vs[j0] = va + gs__fun_term_at(&c->b, 1.0);
    scan_segment(c, 0, xs, vs, j0 + 1, &b);
    uint32_t k = 0;
    if (j0 == n || x[j0] > c->split)
        xs[0] = c->split, vs[0] = va + gs__fun_term_at(&c->b, -1.0), k = 1;
    for (uint32_t j = j0; j < n; j++, k++)
        xs[k] = x[j], vs[k] = s[j];
    scan_segment(c, 1, xs, vs, k, &b);
    return b;
}

/* Move a loop's minimiser off the seams; returns the parameter u. */
double gs__fun_finish(const pctx *c, best *b)
{
    double x = b->x;
    if (c->loop) {
        double lo = -1.0, hi = 1.0;
        if (c->split < 1.0)
            (b->seg ? (lo = c->split) : (hi = c->split));
        if (x < lo + NUDGE)
            x = lo + NUDGE;
        if (x > hi - NUDGE)
            x = hi - NUDGE;
        return gs__fun_wrap(x + c->frame);
    }
    return x;
}

int gs__fun_unreachable(const gs__fun *f)
{
    return f->coef == NULL || !(f->minval < INFINITY);
}

static double sampled_value(const gs__fun *f, double u)
{
    uint32_t n = f->degree + 1, k, k1;
    const double *c = f->coef;
    if (n == 1)
        return c[0];
    double x;
    if (f->closed) {
        x = (gs__fun_wrap(u) + 1.0) * 0.5 * n;
        k = x >= n ? n - 1 : (uint32_t)x;
        k1 = k + 1 == n ? 0 : k + 1;
    } else {
        x = (gs__fun_clamp1(u) + 1.0) * 0.5 * (n - 1);
        k = x >= n - 1 ? n - 2 : (uint32_t)x;
        k1 = k + 1;
    }
    double fr = x - k;
    return c[k] + fr * (c[k1] - c[k]);
}

static double sample_u(const gs__fun *f, uint32_t k)
{
    uint32_t n = f->degree + 1;
    if (n == 1)
        return 0.0;
    return f->closed ? -1.0 + 2.0 * k / n : -1.0 + 2.0 * k / (n - 1);
}

double gs__fun_value(const gs__fun *f, double u)
{
    if (gs__fun_unreachable(f))
        return INFINITY;
    if (f->kind == GS_FUN_SAMPLED)
        return sampled_value(f, u);
    term t = {f->coef, f->degree, f->squared};
    return gs__fun_term_at(&t, f->closed ? gs__fun_wrap(u - f->shift) : u);
}

/* Candidates: every sample of either function (exact for two SEPsam
 * functions: a piecewise-linear sum is minimal at a breakpoint); a mix with
 * a Chebyshev function adds a uniform scan of 512 points. */
double gs__fun_sampled_pair_min(const gs__fun *a, const gs__fun *b, double *u_at)
{
    double bv = INFINITY, bu = 0.0;
    if (a->kind == b->kind && a->degree == b->degree && a->closed == b->closed) {
        for (uint32_t k = 0; k <= a->degree; k++)
            if (a->coef[k] + b->coef[k] < bv)
                bv = a->coef[k] + b->coef[k], bu = sample_u(a, k);
    } else {
        const gs__fun *f[2] = {a, b};
        for (int i = 0; i < 2; i++)
            for (uint32_t k = 0; f[i]->kind == GS_FUN_SAMPLED && k <= f[i]->degree; k++) {
                double u = sample_u(f[i], k), v = gs__fun_value(a, u) + gs__fun_value(b, u);
                if (v < bv)
                    bv = v, bu = u;
            }
        for (int k = 0; k <= 512 && (a->kind != b->kind); k++) {
            double u = -1.0 + k / 256.0, v = gs__fun_value(a, u) + gs__fun_value(b, u);
            if (v < bv)
                bv = v, bu = u;
        }
    }
    if (u_at)
        *u_at = bu;
    return bv;
}

/* A narrow dip: the minimum is small against the typical value. */

int gs__fun_is_sharp(const gs__fun *f)
{
    return f->coef && f->kind == GS_FUN_CHEBYSHEV && gs__fun_sharp_dip(f);
}

int gs__fun_sharp_dip(const gs__fun *f)
{
    double typ = f->squared ? sqrt(fabs(f->coef[0])) : fabs(f->coef[0]);
    return !(f->minval > SHARP * typ);
}

/* Set up a + b in a's frame; combines the coefficients when the sum is
 * one polynomial (same frame, both plain d and positive everywhere). */
void gs__fun_pair_setup(const gs__fun *a, const gs__fun *b, pctx *c, double *comb)
{
    double sa = a->closed ? a->shift : 0.0, sb = b->closed ? b->shift : 0.0;
    double d0 = gs__fun_wrap(sa - sb);
    c->loop = a->closed || b->closed;
    c->frame = sa;
    c->a = (term){a->coef, a->degree, a->squared};
    c->b = (term){b->coef, b->degree, b->squared};
    c->split = 2.0;
    c->off[0] = c->off[1] = 0.0;
    c->sharp[0] = gs__fun_sharp_dip(a), c->sharp[1] = gs__fun_sharp_dip(b);
    c->eval_only = 0; /* 1 (cheaper) misses minima beside zero-set edges */
    if (d0 != 0.0) {
        c->split = d0 > 0.0 ? 1.0 - d0 : -1.0 - d0;
        c->off[0] = d0 > 0.0 ? d0 : d0 + 2.0;
        c->off[1] = c->off[0] - 2.0;
        return;
    }
    if (a->squared || b->squared || c->sharp[0] || c->sharp[1])
        return;
    uint32_t m = a->degree > b->degree ? a->degree : b->degree;
    for (uint32_t k = 0; k <= m; k++)
        comb[k] = (k <= a->degree ? a->coef[k] : 0.0) + (k <= b->degree ? b->coef[k] : 0.0);
    c->a = (term){comb, m, 0};
    c->b.c = NULL;
}

/* v lowered by a bound on the rounding error of evaluating the series
 * (Clenshaw: a few (m+1) eps sum |c_k|), so that it bounds every value as
 * evaluated: sqrt near 0 amplifies that error. */
static double lower_bound(const term *t, double v)
{
    double sum = 0.0;
    for (uint32_t k = 0; k <= t->m; k++)
        sum += fabs(t->c[k]);
    double p = (t->sq ? v * v : v) - 4.0 * (t->m + 1) * DBL_EPSILON * sum;
    return gs__fun_term_value(t, p);
}

double gs__fun_min(const gs__fun *f, double *u_at)
{
    if (u_at)
        *u_at = 0.0;
    if (f->coef == NULL)
        return INFINITY;
    if (f->kind == GS_FUN_SAMPLED) {
        double bv = INFINITY;
        for (uint32_t k = 0; k <= f->degree; k++)
            if (f->coef[k] < bv) {
                bv = f->coef[k];
                if (u_at)
                    *u_at = sample_u(f, k);
            }
        return bv;
    }
    pctx c = {{f->coef, f->degree, f->squared}, {NULL, 0, 0}, 2.0, {0.0, 0.0},
              f->closed ? f->shift : 0.0, (int)f->closed, {1, 0}, 0};
    best r = gs__fun_minimise(&c, gs__cheb_fine_grid(), NULL, GS_CHEB_FINE + 1);
    double u = gs__fun_finish(&c, &r);
    if (u_at)
        *u_at = u;
    term t = {f->coef, f->degree, f->squared};
    double v = gs__fun_term_at(&t, f->closed ? gs__fun_wrap(u - f->shift) : u);
    return lower_bound(&t, v < r.v ? v : r.v);
}

uint32_t gs__fun_cost(const gs__fun *f)
{
    if (f->coef == NULL || !(f->minval < INFINITY))
        return 0;
    return f->degree + 1 + (f->kind == GS_FUN_CHEBYSHEV && f->closed ? 1u : 0u);
}



/* The lower of a loop's one-sided limits at its seam: its series at t = 1
 * and t = -1 (sums of the coefficients), as term values. */
double gs__fun_seam_value(const gs__fun *f)
{
    double p1 = 0.0, pm = 0.0;
    for (uint32_t k = 0; k <= f->degree; k++) p1 += f->coef[k], pm += k & 1 ? -f->coef[k] : f->coef[k];
    term t = {f->coef, f->degree, f->squared};
    double v1 = gs__fun_term_value(&t, p1), vm = gs__fun_term_value(&t, pm);
    return v1 < vm ? v1 : vm;
}

void gs__fun_dip_find(const gs__fun *f, gs__fun_dip *d)
{
    d->u = d->lo = d->hi = NAN;
    d->slope = 0.0;
    d->seam_cell = GS_FUN_NO_CELL;
    d->seam = f->coef && f->kind == GS_FUN_CHEBYSHEV && f->closed ? gs__fun_seam_value(f) : NAN;
    if (!gs__fun_is_sharp(f)) return;
    double u;
    gs__fun_min(f, &u);
    d->u = d->lo = d->hi = u;
    term t = {f->coef, f->degree, f->squared};
    double t0 = f->closed ? gs__fun_wrap(u - f->shift) : u, p0, p1, p2;
    /* the raw series' own minimum near t0 (t0 may sit on a zero set's edge) */
    double tm = gs__fun_poly_min(&t, t0 - 0.1 > -1.0 ? t0 - 0.1 : -1.0, t0 + 0.1 < 1.0 ? t0 + 0.1 : 1.0, t0, &p0);
    if (p0 > 0.0) { /* no zero set: the hyperbola's slope from the curvature at u */
        double v1, v2, v = gs__fun_term_at3(&t, t0, &v1, &v2);
        d->slope = v > 0.0 && v2 > 0.0 ? sqrt(v * v2) : 0.0;
        return;
    }
    /* the fit dips below 0 (clamped): the edges of that zero set */
    gs__cheb_eval3(t.c, t.m, tm, &p0, &p1, &p2);
    double w = p2 > 0.0 ? sqrt(-2.0 * p0 / p2) : 0.01;
    double r1 = gs__fun_poly_root(&t, -1.0, tm, tm - w), r2 = gs__fun_poly_root(&t, tm, 1.0, tm + w);
    d->lo = u + (r1 < t0 ? r1 - t0 : 0.0);
    d->hi = u + (r2 > t0 ? r2 - t0 : 0.0);
}
