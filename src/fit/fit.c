/* fit.c - fitting separator distance functions (paper sec. 4.2): weighted
 * least squares (weights 1/d) of d and d^2 in the Chebyshev basis by one
 * Householder QR per target, degree escalation m_min..m_max; SEPsam. */
#include "fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cheb.h"

#define RANK_TOL 1e-13 /* |R_jj| below this times max |R_ii|: column dropped */

struct gs__fit_work {
    gs__fit_options opt;
    uint32_t cap;        /* rows: max_samples + 1 (a loop's closing row)      */
    double *t, *y;       /* abscissae and normalised distances, per row       */
    double *basis;       /* column-major T_j(t_r), cap x (m_max + 1)          */
    double *qa, *qb;     /* the weighted d and d^2 systems, factorised (QR)   */
    double *ra, *rb;     /* their right-hand sides, Q^T applied               */
    double *val;         /* scratch: fitted values at the rows                */
    double *va, *vb;     /* reflection data of qa / qb (see householder)      */
    double *wt;          /* row weights 1/d                                    */
    double ulen;         /* the current curve's arc length per unit of u,     */
                         /*   over dmax (normalised units); 0: no certificate */
};

/* One candidate fit (coefficients on normalised distances). */
typedef struct cand {
    double c[GS_FUN_MAX_DEGREE + 1];
    uint32_t m, sq;
    double mean, max;
    double viol;         /* the certificate: largest relative step outside   */
                         /*   the samples' Lipschitz band between samples    */
    double amax, aviol;  /* the same two, absolute (in units of dmax)       */
} cand;

void gs__fit_options_default(gs__fit_options *o)
{
    o->m_min = 2;
    o->m_max = 12;
    o->tol = 0.005;
}

double gs__fit_tol_at_depth(double tol, uint32_t depth)
{
    double cap = tol > GS_FIT_TOL_CAP ? tol : GS_FIT_TOL_CAP, t = tol;
    for (uint32_t d = 0; d < depth && t < cap; d++)
        t *= GS_FIT_TOL_GROWTH;
    return t < cap ? t : cap;
}

void gs__fit_work_free(gs__fit_work *w)
{
    if (!w)
        return;
    free(w->t), free(w->y), free(w->basis), free(w->qa), free(w->qb);
    free(w->ra), free(w->rb), free(w->val), free(w->va), free(w->vb), free(w->wt);
    free(w);
}

int gs__fit_work_create(uint32_t max_samples, const gs__fit_options *o, gs__fit_work **out,
                       gs_error *err)
{
    gs__fit_options def;
    gs__fit_options_default(&def);
    if (!o)
        o = &def;
    if (!out || max_samples == 0 || max_samples > (1u << 26) || o->m_min > o->m_max ||
        o->m_max > GS_FUN_MAX_DEGREE || !(o->tol >= 0.0 && o->tol < INFINITY))
        return gs__fail(err, GS_EARG, "gs__fit_work_create: bad arguments (samples %u, m %u..%u)",
                        max_samples, o->m_min, o->m_max);
    gs__fit_work *w = gs__calloc(1, sizeof *w);
    size_t cap = (size_t)max_samples + 1, cols = o->m_max + 1;
    if (w) {
        w->opt = *o, w->cap = (uint32_t)cap;
        w->t = gs__malloc(cap, sizeof(double)), w->y = gs__malloc(cap, sizeof(double));
        w->basis = gs__malloc(cap * cols, sizeof(double));
        w->qa = gs__malloc(cap * cols, sizeof(double)), w->qb = gs__malloc(cap * cols, sizeof(double));
        w->ra = gs__malloc(cap, sizeof(double)), w->rb = gs__malloc(cap, sizeof(double));
        w->val = gs__malloc(cap, sizeof(double));
        w->va = gs__malloc(2 * cap, sizeof(double)), w->vb = gs__malloc(2 * cap, sizeof(double));
        w->wt = gs__malloc(cap, sizeof(double));
    }
    if (!w || !w->t || !w->y || !w->basis || !w->qa || !w->qb || !w->ra || !w->rb || !w->val || !w->va ||
        !w->vb || !w->wt) {
        gs__fit_work_free(w);
        return gs__fail(err, GS_ENOMEM, "gs__fit_work_create: out of memory");
    }
    *out = w;
    return GS_OK;
}

static int check_samples(const double *u, const double *d, uint32_t n, int closed, gs_error *err)
{
    for (uint32_t k = 0; k < n; k++) {
        if (!isfinite(u[k]) || !isfinite(d[k]) || d[k] < 0.0)
            return gs__fail(err, GS_EARG, "gs__fit_distance: sample %u not finite or negative", k);
        if (u[k] < -1.0 || u[k] > 1.0 || (closed && u[k] >= 1.0) || (k > 0 && u[k] <= u[k - 1]))
            return gs__fail(err, GS_EARG, "gs__fit_distance: parameter %u out of order or range", k);
    }
    return GS_OK;
}

/* Rows in fitting order; returns the row count. Loops start at the largest
 * distance (t = -1) and repeat it at t = 1 so the fit closes up. */
static uint32_t prepare_rows(gs__fit_work *w, const double *u, const double *d, uint32_t n,
                             int closed, double dmax, double *shift)
{
    uint32_t kmax = 0;
    for (uint32_t k = 1; k < n; k++)
        if (d[k] > d[kmax])
            kmax = k;
    *shift = closed ? gs__fun_wrap(u[kmax] + 1.0) : 0.0; /* t(u[kmax]) = -1 */
    for (uint32_t r = 0; r < n; r++) {
        uint32_t k = closed ? (kmax + r) % n : r;
        w->t[r] = closed ? (r == 0 ? -1.0 : gs__fun_wrap(u[k] - *shift)) : u[k];
        w->y[r] = d[k] / dmax;
    }
    if (!closed)
        return n;
    w->t[n] = 1.0, w->y[n] = d[kmax] / dmax;
    return n + 1;
}

/* Row weights and right-hand sides of the two weighted systems (d: 1/d,
 * d^2: 1/d^2); the weights 1/d go to wt for the columns. */
static void build_rhs(gs__fit_work *w, uint32_t rows)
{
    for (uint32_t r = 0; r < rows; r++) {
        double wa = 1.0 / fmax(w->y[r], GS_FIT_DFLOOR), wb = wa * wa;
        w->wt[r] = wa;
        w->ra[r] = w->y[r] * wa;
        w->rb[r] = w->y[r] * w->y[r] * wb;
    }
}

/* Basis columns [from, to) (Chebyshev recurrence down each column) and the
 * same columns of the two weighted systems; built when degree escalation
 * first needs them. Uses the weights build_rhs left in wt. */
static void build_columns(gs__fit_work *w, uint32_t rows, uint32_t from, uint32_t to)
{
    for (uint32_t j = from; j < to; j++) {
        double *bj = w->basis + (size_t)j * rows;
        const double *b1 = bj - rows, *b0 = bj - 2 * (size_t)rows;
        for (uint32_t r = 0; r < rows; r++) {
            double tj = j == 0 ? 1.0 : (j == 1 ? w->t[r] : 2.0 * w->t[r] * b1[r] - b0[r]);
            double wa = w->wt[r];
            bj[r] = tj;
            w->qa[(size_t)j * rows + r] = tj * wa;
            w->qb[(size_t)j * rows + r] = tj * (wa * wa);
        }
    }
}

/* In-place Householder QR of the rows x cols column-major A, one column at
 * a time (left-looking): extend from `from` factored columns to `to`. Each
 * new column receives the earlier reflections in order, then its own, which
 * is also applied to y; R is left in the upper triangle, reflection j's
 * first entry in vd[j] (0: none). The operations on every column are those
 * of the usual right-looking order, so the result is the same to the bit,
 * but degree escalation only pays for the columns it uses. */
static void householder(double *a, double *y, double *vd, uint32_t rows, uint32_t from, uint32_t to)
{
    for (uint32_t j = from; j < to && j < rows; j++) {
        double *aj = a + (size_t)j * rows;
        for (uint32_t p = 0; p < j; p++) { /* earlier reflections, in order */
            if (vd[p] == 0.0) continue;
            const double *ap = a + (size_t)p * rows;
            double dot = vd[p] * aj[p];
            for (uint32_t i = p + 1; i < rows; i++)
                dot += ap[i] * aj[i];
            double f = 2.0 * dot / vd[rows + p];
            aj[p] -= f * vd[p];
            for (uint32_t i = p + 1; i < rows; i++)
                aj[i] -= f * ap[i];
        }
        double nrm = 0.0;
        for (uint32_t i = j; i < rows; i++)
            nrm += aj[i] * aj[i];
        nrm = sqrt(nrm);
        vd[j] = 0.0;
        if (nrm == 0.0)
            continue;
        double alpha = aj[j] > 0.0 ? -nrm : nrm;
        double vv = 2.0 * nrm * (nrm + fabs(aj[j]));
        aj[j] -= alpha;
        double dot = 0.0;
        for (uint32_t i = j; i < rows; i++)
            dot += aj[i] * y[i];
        double f = 2.0 * dot / vv;
        for (uint32_t i = j; i < rows; i++)
            y[i] -= f * aj[i];
        vd[j] = aj[j];
        vd[rows + j] = vv;
        aj[j] = alpha;
    }
}

/* Least-squares coefficients of degree m from the factorised system. */
static void solve_degree(const double *a, const double *y, uint32_t rows, uint32_t m, double *c)
{
    double rmax = 0.0;
    for (uint32_t j = 0; j <= m; j++)
        rmax = fmax(rmax, fabs(a[(size_t)j * rows + j]));
    for (uint32_t jj = m + 1; jj-- > 0;) {
        double s = y[jj], rjj = a[(size_t)jj * rows + jj];
        for (uint32_t k = jj + 1; k <= m; k++)
            s -= a[(size_t)k * rows + jj] * c[k];
        c[jj] = fabs(rjj) > RANK_TOL * rmax ? s / rjj : 0.0;
    }
}

/* Mean and max relative error of candidate f on the first n rows. */
static void measure(gs__fit_work *w, uint32_t rows, uint32_t n, cand *f)
{
    double *v = w->val, sum = 0.0, mx = 0.0, amx = 0.0;
    for (uint32_t r = 0; r < n; r++)
        v[r] = f->c[0];
    for (uint32_t j = 1; j <= f->m; j++) {
        const double cj = f->c[j], *col = w->basis + (size_t)j * rows;
        for (uint32_t r = 0; r < n; r++)
            v[r] += cj * col[r];
    }
    for (uint32_t r = 0; r < n; r++) {
        double p = v[r] > 0.0 ? v[r] : 0.0, q = f->sq ? sqrt(p) : p;
        double a = fabs(q - w->y[r]), e = a / fmax(w->y[r], GS_FIT_DFLOOR);
        sum += e;
        mx = e > mx ? e : mx;
        amx = a > amx ? a : amx;
    }
    f->mean = sum / n, f->max = mx, f->amax = amx;
}

/* The certificate between samples. Along the curve, d(x, .) is 1-Lipschitz
 * in arc length (|d(x,a) - d(x,b)| <= d(a,b) <= the arc between them), so
 * at a point at arcs da, db from the samples k, k+1 around it the true
 * distance lies in the band [max(d_k - da, d_k+1 - db), min(d_k + da,
 * d_k+1 + db)]. The fit is evaluated at GS_FIT_CERT_POINTS points inside
 * every interval; f->viol receives its largest step outside the band,
 * relative to the band's edge (floored like the errors). 0 without ulen. */
static void certify(const gs__fit_work *w, uint32_t rows, cand *f)
{
    f->viol = f->aviol = 0.0;
    if (!(w->ulen > 0.0))
        return;
    double mx = 0.0, amx = 0.0;
    for (uint32_t r = 0; r + 1 < rows; r++) {
        double t0 = w->t[r], t1 = w->t[r + 1], y0 = w->y[r], y1 = w->y[r + 1];
        for (uint32_t q = 1; q <= GS_FIT_CERT_POINTS; q++) {
            double t = t0 + (t1 - t0) * q / (GS_FIT_CERT_POINTS + 1);
            double da = (t - t0) * w->ulen, db = (t1 - t) * w->ulen;
            double lo = fmax(y0 - da, y1 - db), hi = fmin(y0 + da, y1 + db);
            double p = gs__cheb_eval(f->c, f->m, t);
            p = p > 0.0 ? p : 0.0;
            double v = f->sq ? sqrt(p) : p, e = 0.0, a = 0.0;
            if (v < lo) a = lo - v, e = a / fmax(lo, GS_FIT_DFLOOR);
            else if (v > hi) a = v - hi, e = a / fmax(hi, GS_FIT_DFLOOR);
            mx = e > mx ? e : mx;
            amx = a > amx ? a : amx;
        }
    }
    f->viol = mx, f->aviol = amx;
}

/* How far a candidate is from being trusted: its largest error at the
 * samples or outside the band between them. */
static double worst(const cand *f)
{
    return f->max > f->viol ? f->max : f->viol;
}

/* Degree escalation, d and d^2 at each degree: the first degree where a
 * candidate has mean error below tol and, at the samples and between them
 * (certify), no error above GS_FIT_MAX_ERR wins (of two, the lower mean);
 * else the candidate with the smallest such worst error seen. */
static void escalate(gs__fit_work *w, uint32_t rows, uint32_t n, uint32_t mlo, uint32_t mhi,
                     cand *best)
{
    cand ca, cb;
    best->mean = INFINITY;
    best->max = best->viol = INFINITY;
    uint32_t done = 0; /* columns factored */
    build_columns(w, rows, 0, mlo);
    for (uint32_t m = mlo; m <= mhi; m++) {
        build_columns(w, rows, m, m + 1);
        householder(w->qa, w->ra, w->va, rows, done, m + 1);
        householder(w->qb, w->rb, w->vb, rows, done, m + 1);
        done = m + 1;
        ca.m = cb.m = m, ca.sq = 0, cb.sq = 1;
        solve_degree(w->qa, w->ra, rows, m, ca.c);
        solve_degree(w->qb, w->rb, rows, m, cb.c);
        measure(w, rows, n, &ca);
        measure(w, rows, n, &cb);
        certify(w, rows, &ca);
        certify(w, rows, &cb);
        int oka = ca.mean < w->opt.tol && worst(&ca) < GS_FIT_MAX_ERR;
        int okb = cb.mean < w->opt.tol && worst(&cb) < GS_FIT_MAX_ERR;
        if (oka || okb) {
            *best = (oka && okb) ? (cb.mean < ca.mean ? cb : ca) : (oka ? ca : cb);
            return;
        }
        const cand *c = worst(&cb) < worst(&ca) ? &cb : &ca;
        if (worst(c) < worst(best) || (worst(c) == worst(best) && c->mean < best->mean))
            *best = *c;
    }
}

static int store_result(const cand *b, double dmax, double shift, int closed, gs__fit_result *res,
                        gs_error *err)
{
    double scale = b->sq ? dmax * dmax : dmax;
    memset(res->coef, 0, sizeof res->coef);
    for (uint32_t k = 0; k <= b->m; k++) {
        res->coef[k] = b->c[k] * scale;
        if (!isfinite(res->coef[k]))
            return gs__fail(err, GS_EINTERNAL, "gs__fit_distance: non-finite coefficient");
    }
    res->fun = (gs__fun){GS_FUN_CHEBYSHEV, b->m, b->sq, closed ? 1u : 0u, shift, 0.0, res->coef};
    res->fun.minval = gs__fun_min(&res->fun, NULL);
    res->mean_rel_err = b->mean, res->max_rel_err = b->max, res->cert_err = b->viol;
    res->abs_err = (b->amax > b->aviol ? b->amax : b->aviol) * dmax;
    res->cost = gs__fun_cost(&res->fun);
    return GS_OK;
}

int gs__fit_distance(gs__fit_work *w, const double *u, const double *d, uint32_t n, int closed,
                    double ulen, gs__fit_result *res, gs_error *err)
{
    if (!w || !u || !d || !res || n == 0 || n + 1 > w->cap)
        return gs__fail(err, GS_EARG, "gs__fit_distance: bad arguments (n = %u)", n);
    int rc = check_samples(u, d, n, closed, err);
    if (rc)
        return rc;
    double dmax = 0.0, shift = 0.0;
    for (uint32_t k = 0; k < n; k++)
        dmax = fmax(dmax, d[k]);
    cand best = {{0.0}, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (!(ulen >= 0.0) || !isfinite(ulen))
        return gs__fail(err, GS_EARG, "gs__fit_distance: arc length per unit %g is not finite and >= 0", ulen);
    if (dmax == 0.0) /* every sample on the curve: d = 0 */
        return store_result(&best, 1.0, closed ? u[0] : 0.0, closed, res, err);
    uint32_t rows = prepare_rows(w, u, d, n, closed, dmax, &shift);
    w->ulen = ulen / dmax;
    uint32_t mhi = w->opt.m_max < n - 1 ? w->opt.m_max : n - 1;
    uint32_t mlo = w->opt.m_min < mhi ? w->opt.m_min : mhi;
    build_rhs(w, rows);
    escalate(w, rows, n, mlo, mhi, &best);
    return store_result(&best, dmax, shift, closed, res, err);
}

int gs__fun_make_sampled(const double *d, uint32_t n, int closed, double *coef, gs__fun *out,
                        gs_error *err)
{
    if (!d || !coef || !out || n == 0)
        return gs__fail(err, GS_EARG, "gs__fun_make_sampled: bad arguments (n = %u)", n);
    double mn = INFINITY;
    for (uint32_t k = 0; k < n; k++) {
        if (!isfinite(d[k]) || d[k] < 0.0)
            return gs__fail(err, GS_EARG, "gs__fun_make_sampled: sample %u not finite or negative", k);
        mn = fmin(mn, d[k]);
    }
    memmove(coef, d, (size_t)n * sizeof *coef);
    *out = (gs__fun){GS_FUN_SAMPLED, n - 1, 0, closed ? 1u : 0u, 0.0, mn, coef};
    return GS_OK;
}
