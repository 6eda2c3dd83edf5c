/* test_fit.c - separator distance functions (paper sec. 4.2, 4.3): Chebyshev
 * kernels, fitting (d / d^2, escalation, loops, near-zero), pair minimum
 * against a dense 20,000-point scan on real-looking data, SEPsam, errors. */
#include "check.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/cheb.h"
#include "fit/fit.h"
#include "fit/fun.h"
#include "query/pair_grid.h"

#define DENSE 20000
#define MAXN 1024

static uint64_t g_rng = 12345;

static double rnd(void) /* uniform [0,1) */
{
    uint64_t z = (g_rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static double urand(double a, double b)
{
    return a + (b - a) * rnd();
}

static double dense_u(int k)
{
    return -1.0 + 2.0 * k / (DENSE - 1);
}

static void uniform_u(double *u, uint32_t n, int closed)
{
    for (uint32_t k = 0; k < n; k++)
        u[k] = closed ? -1.0 + 2.0 * k / n : (n == 1 ? -1.0 : -1.0 + 2.0 * k / (n - 1));
}

static gs_fit_work *make_work(uint32_t m_min, uint32_t m_max, double tol)
{
    gs_fit_options o;
    gs_fit_options_default(&o);
    o.m_min = m_min, o.m_max = m_max, o.tol = tol;
    gs_fit_work *w = NULL;
    CHECK(gs_fit_work_create(MAXN, &o, &w, NULL) == GS_OK);
    return w;
}

/* gs_fun_wrap's shortcuts ([-1,1) as it is, one period either side by
 * +-2) give what the floor rule gives, bit for bit: at 2,000 doubles either
 * side of every shortcut's edge, random values over +-5 at all scales, and
 * the special values. */
static double wrap_rule(double u)
{
    double t = u - 2.0 * floor((u + 1.0) * 0.5);
    return t < -1.0 ? -1.0 : (t >= 1.0 ? -1.0 : t);
}

static void test_wrap(void)
{
    static const double edges[] = {-3.0, -2.0, -1.0, -0.0, 0.0, 1.0, 2.0, 3.0};
    long bad = 0, n = 0;
    for (int e = 0; e < 8; e++) {
        double lo = edges[e], hi = edges[e];
        for (int k = 0; k < 2000; k++, lo = nextafter(lo, -INFINITY), hi = nextafter(hi, INFINITY)) {
            double a = gs_fun_wrap(lo), b = wrap_rule(lo), c = gs_fun_wrap(hi), d = wrap_rule(hi);
            bad += memcmp(&a, &b, sizeof a) != 0, bad += memcmp(&c, &d, sizeof c) != 0, n += 2;
        }
    }
    for (long i = 0; i < 2000000; i++) {
        double u = ldexp(urand(-5.0, 5.0), -(int)(i % 60));
        double a = gs_fun_wrap(u), b = wrap_rule(u);
        bad += memcmp(&a, &b, sizeof a) != 0, n++;
    }
    static const double special[] = {INFINITY, -INFINITY, 1e300, -1e300, 0x1.fffffffffffffp-1, NAN};
    for (int i = 0; i < 6; i++) {
        double a = gs_fun_wrap(special[i]), b = wrap_rule(special[i]);
        bad += !(memcmp(&a, &b, sizeof a) == 0 || (a != a && b != b)), n++;
    }
    CHECK_MSG(bad == 0, "gs_fun_wrap differs from the floor rule at %ld of %ld values", bad, n);
    printf("  wrap: %ld values, %ld unlike the floor rule\n", n, bad);
}

/* ---- Chebyshev kernels ---------------------------------------------- */

static void test_cheb(void)
{
    double c[GS_FUN_MAX_DEGREE + 1], maxerr = 0.0, maxd = 0.0;
    for (int trial = 0; trial < 200; trial++) {
        uint32_t m = (uint32_t)(rnd() * (GS_FUN_MAX_DEGREE + 1));
        for (uint32_t k = 0; k <= m; k++)
            c[k] = urand(-1, 1);
        for (int i = 0; i < 20; i++) {
            double u = i == 0 ? -1.0 : (i == 1 ? 1.0 : urand(-1, 1)), ref = 0.0;
            for (uint32_t k = 0; k <= m; k++)
                ref += c[k] * cos(k * acos(u));
            maxerr = fmax(maxerr, fabs(gs_cheb_eval(c, m, u) - ref));
            double p, p1, p2, h = 1e-5, x = fmax(-1 + h, fmin(1 - h, u));
            gs_cheb_eval3(c, m, x, &p, &p1, &p2);
            double fd1 = (gs_cheb_eval(c, m, x + h) - gs_cheb_eval(c, m, x - h)) / (2 * h);
            double fd2 = (gs_cheb_eval(c, m, x + h) - 2 * p + gs_cheb_eval(c, m, x - h)) / (h * h);
            maxd = fmax(maxd, fabs(p1 - fd1) / (1 + fabs(p1)) + fabs(p2 - fd2) / (1e3 + fabs(p2)));
            CHECK_NEAR(p, gs_cheb_eval(c, m, x), 1e-12);
        }
    }
    CHECK_MSG(maxerr < 1e-13, "clenshaw vs cos(k acos u): %g", maxerr);
    CHECK_MSG(maxd < 1e-4, "derivatives vs finite differences: %g", maxd);
    printf("  clenshaw max error %.2e, derivative check %.2e\n", maxerr, maxd);
}

/* ---- fitting --------------------------------------------------------- */

static void test_poly_reproduction(void)
{
    gs_fit_work *w = make_work(2, 12, 1e-10);
    double u[MAXN], d[MAXN], c[13];
    gs_fit_result r;
    for (uint32_t m = 2; m <= 12; m++) {
        for (uint32_t k = 1; k <= m; k++)
            c[k] = urand(-0.3, 0.3) / m;
        c[m] = 0.05, c[0] = 2.0; /* positive on [-1,1], exact degree m */
        uniform_u(u, 100, 0);
        for (int k = 0; k < 100; k++)
            d[k] = gs_cheb_eval(c, m, u[k]);
        CHECK(gs_fit_distance(w, u, d, 100, 0, 0, &r, NULL) == GS_OK);
        CHECK_MSG(r.fun.degree == m && !r.fun.squared, "m %u: got %u sq %u", m, r.fun.degree,
                  r.fun.squared);
        for (uint32_t k = 0; k <= m && r.fun.degree == m; k++)
            CHECK_NEAR(r.coef[k], c[k], 1e-11);
        CHECK(r.mean_rel_err < 1e-12 && r.cost == m + 1);
    }
    gs_fit_work_free(w);
}

/* Distance from (a, b) to the straight segment y = 0, x = u: d^2 is exact. */
static void test_segment(void)
{
    gs_fit_work *w = make_work(2, 12, 0.005);
    double u[MAXN], d[MAXN];
    gs_fit_result r;
    for (int trial = 0; trial < 50; trial++) {
        double a = urand(-1.5, 1.5), b = urand(0.01, 1.0);
        uniform_u(u, 60, 0);
        for (int k = 0; k < 60; k++)
            d[k] = hypot(u[k] - a, b);
        CHECK(gs_fit_distance(w, u, d, 60, 0, 0, &r, NULL) == GS_OK);
        CHECK_MSG(r.fun.degree == 2 && r.fun.squared == 1, "deg %u sq %u", r.fun.degree,
                  r.fun.squared);
        CHECK(r.mean_rel_err < 1e-12);
        for (int i = 0; i < 20; i++) {
            double x = urand(-1, 1);
            CHECK_NEAR(gs_fun_value(&r.fun, x), hypot(x - a, b), 1e-12);
        }
        double exact = fabs(a) <= 1 ? b : hypot(fabs(a) - 1, b);
        CHECK_NEAR(r.fun.minval, exact, 1e-12);
    }
    gs_fit_work_free(w);
}

static void circle_samples(double px, double py, double R, uint32_t n, double *u, double *d)
{
    uniform_u(u, n, 1);
    for (uint32_t k = 0; k < n; k++) {
        double th = M_PI * (u[k] + 1.0);
        d[k] = hypot(px - R * cos(th), py - R * sin(th));
    }
}

static void test_loops(void)
{
    gs_fit_work *w = make_work(2, 12, 0.005);
    double u[MAXN], d[MAXN], worst = 0.0;
    gs_fit_result r;
    for (int trial = 0; trial < 100; trial++) {
        double rad = trial % 2 ? urand(0.0, 0.7) : urand(1.3, 3.0), ang = urand(0, 2 * M_PI);
        uint32_t n = 64 + (uint32_t)(rnd() * 200);
        circle_samples(rad * cos(ang), rad * sin(ang), 1.0, n, u, d);
        CHECK(gs_fit_distance(w, u, d, n, 1, 0, &r, NULL) == GS_OK);
        uint32_t kmax = 0;
        for (uint32_t k = 1; k < n; k++)
            kmax = d[k] > d[kmax] ? k : kmax;
        CHECK(r.fun.closed == 1 && fabs(gs_fun_wrap(u[kmax] - r.fun.shift) + 1.0) < 1e-15);
        CHECK(r.cost == r.fun.degree + 2);
        /* the largest distance sits at the interval ends: t = -1 and t -> 1 */
        CHECK_NEAR(gs_fun_value(&r.fun, u[kmax] + 1e-9), d[kmax], 0.03 * d[kmax]);
        CHECK_NEAR(gs_fun_value(&r.fun, u[kmax] - 1e-9), d[kmax], 0.03 * d[kmax]);
        CHECK(r.mean_rel_err < 0.005);
        for (uint32_t k = 0; k < n; k++) {
            double e = fabs(gs_fun_value(&r.fun, u[k]) - d[k]) / d[k];
            worst = fmax(worst, e);
            /* periodic: u and u + 2 agree (away from the seam) */
            if (k != kmax)
                CHECK_NEAR(gs_fun_value(&r.fun, u[k] + 2.0), gs_fun_value(&r.fun, u[k]), 1e-12);
        }
    }
    printf("  circle loops: worst sample relative error %.3g\n", worst);
    gs_fit_work_free(w);
}

/* A bumpy planar path: the first degree below tol is the one kept. */
static void test_escalation(void)
{
    double u[MAXN], d[MAXN];
    gs_fit_result r, r2;
    int checked = 0;
    for (int trial = 0; trial < 40; trial++) {
        double px = urand(-1, 1), py = urand(0.3, 1.0), f = urand(1.5, 3.0);
        uniform_u(u, 200, 0);
        for (int k = 0; k < 200; k++)
            d[k] = hypot(px - u[k], py - 0.2 * sin(f * u[k]));
        gs_fit_work *w = make_work(2, 12, 0.002);
        CHECK(gs_fit_distance(w, u, d, 200, 0, 0, &r, NULL) == GS_OK);
        gs_fit_work_free(w);
        if (r.mean_rel_err >= 0.002 || r.fun.degree <= 2)
            continue;
        w = make_work(2, r.fun.degree - 1, 0.002);
        CHECK(gs_fit_distance(w, u, d, 200, 0, 0, &r2, NULL) == GS_OK);
        CHECK_MSG(r2.mean_rel_err >= 0.002, "degree %u already below tol", r2.fun.degree);
        gs_fit_work_free(w);
        checked++;
    }
    CHECK(checked > 10);
}

/* Vertex on the curve: d = 0 at a sample. */
static void test_near_zero(void)
{
    gs_fit_work *w = make_work(2, 12, 0.005);
    double u[MAXN], d[MAXN];
    gs_fit_result r;
    for (int closed = 0; closed <= 1; closed++)
        for (int trial = 0; trial < 20; trial++) {
            uint32_t n = 101, k0 = (uint32_t)(rnd() * n);
            uniform_u(u, n, closed);
            double off = trial % 2 ? 0.0 : 1e-9;
            for (uint32_t k = 0; k < n; k++)
                d[k] = closed ? hypot(cos(M_PI * u[k]) - cos(M_PI * u[k0]) * (1 + off),
                                      sin(M_PI * u[k]) - sin(M_PI * u[k0]) * (1 + off))
                              : hypot(u[k] - u[k0], off);
            CHECK(gs_fit_distance(w, u, d, n, closed, 0, &r, NULL) == GS_OK);
            for (uint32_t k = 0; k <= r.fun.degree; k++)
                CHECK(isfinite(r.coef[k]));
            CHECK(r.fun.minval >= 0.0 && r.fun.minval < 0.02);
            CHECK(gs_fun_value(&r.fun, u[k0]) < 0.02);
            CHECK(isfinite(r.mean_rel_err));
        }
    gs_fit_work_free(w);
}

static void test_tiny_and_bad(void)
{
    gs_fit_work *w = make_work(2, 12, 0.005);
    double u[4] = {-1, -0.2, 0.5, 1}, d[4] = {1, 2, 1.5, 3}, ul[3] = {-1, -1.0 / 3, 1.0 / 3};
    gs_fit_result r;
    for (uint32_t n = 1; n <= 4; n++) {
        double uu[4] = {-1, 1};
        CHECK(gs_fit_distance(w, n == 2 ? uu : u, d, n, 0, 0, &r, NULL) == GS_OK);
        CHECK(r.fun.degree <= n - 1 && isfinite(r.fun.minval));
        if (n <= 3) {
            CHECK(gs_fit_distance(w, ul, d, n, 1, 0, &r, NULL) == GS_OK);
            CHECK(r.fun.degree <= n - 1 && isfinite(r.fun.minval));
        }
    }
    double zero[4] = {0, 0, 0, 0};
    CHECK(gs_fit_distance(w, u, zero, 4, 0, 0, &r, NULL) == GS_OK);
    CHECK(r.fun.minval == 0.0 && gs_fun_value(&r.fun, 0.3) == 0.0);
    gs_error err;
    double bad[4] = {1, NAN, 1, 1}, neg[4] = {1, -1, 1, 1}, uinf[4] = {-1, INFINITY, 0, 1};
    double unord[4] = {-1, 0.5, 0.2, 1};
    CHECK(gs_fit_distance(w, u, bad, 4, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(w, u, neg, 4, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(w, uinf, d, 4, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(w, unord, d, 4, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(w, u, d, 0, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(w, u, d, 4, 1, 0, &r, &err) == GS_EARG); /* loop: u = 1 */
    CHECK(gs_fit_distance(w, u, d, MAXN + 5, 0, 0, &r, &err) == GS_EARG);
    CHECK(gs_fit_distance(NULL, u, d, 4, 0, 0, &r, &err) == GS_EARG);
    gs_fit_options o = {5, 3, 0.005};
    gs_fit_work *w2 = NULL;
    CHECK(gs_fit_work_create(100, &o, &w2, &err) == GS_EARG && w2 == NULL);
    o = (gs_fit_options){2, GS_FUN_MAX_DEGREE + 1, 0.005};
    CHECK(gs_fit_work_create(100, &o, &w2, &err) == GS_EARG);
    CHECK(gs_fit_work_create(0, NULL, &w2, &err) == GS_EARG);
    gs_fit_work_free(w);
}

/* ---- real-looking data: curves in the plane and on a bumpy surface --- */

typedef struct curve {
    int closed, bumpy;
    uint32_t n;
    double x[MAXN], y[MAXN];
} curve;

static double bump(double x, double y)
{
    return 0.25 * sin(3.0 * x) * cos(2.5 * y) + 0.1 * sin(5.0 * x + y);
}

static void shape(int id, double s, double *x, double *y)
{
    double th = 2 * M_PI * s;
    switch (id) {
    case 0: *x = 2.4 * s - 1.2, *y = 0.4 * sin(3.0 * s); break;
    case 1: *x = 1.6 * s - 0.8, *y = 0.3 * cos(4.0 * s) + 0.2 * s * s; break;
    case 2: *x = (1 + 0.15 * cos(3 * th)) * cos(th), *y = 0.8 * (1 + 0.15 * cos(3 * th)) * sin(th); break;
    default: *x = 0.9 * cos(th), *y = 0.7 * sin(th); break;
    }
}

/* Samples at uniform arc length (planar length; good enough on the bumps). */
static void make_curve(curve *c, int id, uint32_t n)
{
    enum { F = 4096 };
    static double cx[F + 1], cy[F + 1], len[F + 1];
    c->closed = id >= 2, c->bumpy = id % 2, c->n = n;
    for (int i = 0; i <= F; i++) {
        shape(id, (double)i / F, &cx[i], &cy[i]);
        len[i] = i ? len[i - 1] + hypot(cx[i] - cx[i - 1], cy[i] - cy[i - 1]) : 0.0;
    }
    uint32_t den = c->closed ? n : n - 1;
    for (uint32_t k = 0, i = 0; k < n; k++) {
        double L = len[F] * k / den;
        while (i < F - 1 && len[i + 1] < L)
            i++;
        double f = (L - len[i]) / (len[i + 1] - len[i]);
        c->x[k] = cx[i] + f * (cx[i + 1] - cx[i]), c->y[k] = cy[i] + f * (cy[i + 1] - cy[i]);
    }
}

/* Planar: Euclidean. Bumpy: length of the lifted straight segment. */
static double dist(const curve *c, double px, double py, uint32_t k)
{
    if (!c->bumpy)
        return hypot(px - c->x[k], py - c->y[k]);
    double L = 0.0, zp = bump(px, py);
    for (int i = 1; i <= 16; i++) {
        double f = i / 16.0, x = px + f * (c->x[k] - px), y = py + f * (c->y[k] - py), z = bump(x, y);
        L += sqrt(pow((c->x[k] - px) / 16, 2) + pow((c->y[k] - py) / 16, 2) + (z - zp) * (z - zp));
        zp = z;
    }
    return L;
}

typedef struct fset {
    uint32_t nf;
    gs_fit_result *r;
    double *dense; /* nf x DENSE values */
} fset;

/* nf functions of vertices around curve c: random points, a quarter close
 * to the curve (d^2 fits), a few exactly on it. */
static void make_fset(const curve *c, uint32_t nf, uint32_t m_max, fset *s, double *mean_err,
                      uint32_t *n_sq)
{
    gs_fit_work *w = make_work(2, m_max, 0.005);
    double u[MAXN], d[MAXN];
    uniform_u(u, c->n, c->closed);
    s->nf = nf;
    s->r = malloc(nf * sizeof *s->r);
    s->dense = malloc((size_t)nf * DENSE * sizeof(double));
    *mean_err = 0.0;
    for (uint32_t i = 0; i < nf; i++) {
        double px = urand(-2, 2), py = urand(-2, 2);
        if (i % 4 == 0) {
            uint32_t k = (uint32_t)(rnd() * c->n);
            double e = i % 16 == 0 ? 0.0 : urand(-0.05, 0.05);
            px = c->x[k] + e, py = c->y[k] - e;
        }
        for (uint32_t k = 0; k < c->n; k++)
            d[k] = dist(c, px, py, k);
        CHECK(gs_fit_distance(w, u, d, c->n, c->closed, 0, &s->r[i], NULL) == GS_OK);
        s->r[i].fun.coef = s->r[i].coef;
        *mean_err += s->r[i].mean_rel_err / nf;
        *n_sq += s->r[i].fun.squared;
        for (int k = 0; k < DENSE; k++)
            s->dense[(size_t)i * DENSE + k] = gs_fun_value(&s->r[i].fun, dense_u(k));
    }
    gs_fit_work_free(w);
}

/* The dense minimum of the samples v (at dense_u), refined by two local
 * scans of 2,000 points around it with eval(i, u): the "true" minimum. */
static double true_min(const double *v, double (*eval)(const void *, double), const void *ctx)
{
    int kb = 0;
    for (int k = 1; k < DENSE; k++)
        kb = v[k] < v[kb] ? k : kb;
    double best = v[kb], lo = dense_u(kb > 0 ? kb - 1 : 0), hi = dense_u(kb < DENSE - 1 ? kb + 1 : kb);
    for (int pass = 0; pass < 2; pass++) {
        double bu = lo;
        for (int k = 0; k <= 2000; k++) {
            double u = lo + (hi - lo) * k / 2000, e = eval(ctx, u);
            if (e < best)
                best = e, bu = u;
        }
        double h = (hi - lo) / 2000;
        lo = bu - h, hi = bu + h;
    }
    return best;
}

static double eval_one(const void *f, double u)
{
    return gs_fun_value((const gs_fun *)f, u);
}

/* minval is a (tight) lower bound of the function as evaluated. */
static void check_minval(const fset *s, double *worst_gap)
{
    for (uint32_t i = 0; i < s->nf; i++) {
        const gs_fun *f = &s->r[i].fun;
        double dm = true_min(s->dense + (size_t)i * DENSE, eval_one, f), mv = f->minval;
        CHECK_MSG(mv <= dm * (1 + 1e-12) + 1e-300, "minval %.17g above true min %.17g", mv, dm);
        CHECK_MSG(mv >= dm - 1e-8 * dm - 1e-8, "minval %.17g far below true min %.17g", mv, dm);
        *worst_gap = fmax(*worst_gap, (mv - dm) / fmax(dm, 1e-300));
    }
}

typedef struct pstats {
    long pairs, above, inconsistent, better, kinds[3], below_bad;
    double worst_above, worst_incons;
    long grid_off, grid_incons; /* the cached-grid minimiser of queries  */
    double grid_worst, grid_sum;
    long loop_sharp, loop_sharp_off; /* loops with a sharp dip: grid vs gs_fun_pair_min */
    double loop_sharp_worst;
} pstats;

static long cell_diff, cell_loops; /* grid_pair_min with and without the seam cells */

/* The query engine's minimiser: grid values as the query computes them.
 * For loops it also runs with the seam cells given, as the cache gives
 * them, and counts any answer or minimiser that is not the same bit for
 * bit (cell_diff). */
static double grid_pair_min(const gs_fun *a, const gs_fun *b, double *u)
{
    uint32_t m = a->degree > b->degree ? a->degree : b->degree, g = gs_fun_grid_points(m);
    float ga[GS_FUN_GRID_MAX], gb[GS_FUN_GRID_MAX];
    gs__grid_values(a, g, ga);
    gs__grid_values(b, g, gb);
    gs_fun_dip da, db;
    gs_fun_dip_find(a, &da), gs_fun_dip_find(b, &db);
    CHECK(da.seam_cell == GS_FUN_NO_CELL && db.seam_cell == GS_FUN_NO_CELL);
    double r = gs_fun_pair_min_grid(a, b, ga, gb, g, &da, &db, u);
    if (a->closed && b->closed) {
        double u2 = 0.0;
        da.seam_cell = gs_fun_seam_cell(a, g), db.seam_cell = gs_fun_seam_cell(b, g);
        double r2 = gs_fun_pair_min_grid(a, b, ga, gb, g, &da, &db, &u2);
        cell_diff += memcmp(&r, &r2, sizeof r) != 0 || (u && memcmp(u, &u2, sizeof u2) != 0);
        cell_loops++;
    }
    return r;
}

/* A loop's seam cell: the grid cell [u_j, u_{j+1}) (u_j = -1 + 2j/g) that
 * holds the seam wrap(shift - 1), for shifts all around the loop, on its
 * edges and beyond one period. */
static void test_seam_cell(void)
{
    static const uint32_t gs[] = {33, 57, 89, 96};
    double c[2] = {1.0, 0.25};
    long bad = 0;
    for (size_t i = 0; i < sizeof gs / sizeof *gs; ++i)
        for (int k = -4000; k <= 4000; ++k) {
            uint32_t g = gs[i];
            double shift = k < -3000 || k > 3000 ? k / 1000.0 : k / 3000.0 + (k % 7) * 1e-17;
            gs_fun f = {GS_FUN_CHEBYSHEV, 1, 0, 1, shift, 0.0, c};
            uint32_t j = gs_fun_seam_cell(&f, g);
            double us = gs_fun_wrap(shift - 1.0), lo = -1.0 + 2.0 * j / g, hi = -1.0 + 2.0 * (j + 1) / g;
            bad += !(j < g && us >= lo - 1e-12 && us < hi + 1e-12);
        }
    CHECK_MSG(bad == 0, "%ld seam cells outside their grid cell", bad);
    gs_fun f = {GS_FUN_CHEBYSHEV, 1, 0, 1, 1.0, 0.0, c}; /* seam at u = 0: the cell starting there */
    CHECK(gs_fun_seam_cell(&f, 96) == 48 && gs_fun_seam_cell(&f, 33) == 16);
}

static void check_pairs(const fset *s, long npairs, pstats *st)
{
    for (long p = 0; p < npairs; p++) {
        uint32_t i = (uint32_t)(rnd() * s->nf), j = (uint32_t)(rnd() * s->nf);
        const gs_fun *a = &s->r[i].fun, *b = &s->r[j].fun;
        double ua, r = gs_fun_pair_min(a, b, &ua), dm = INFINITY;
        const double *da = s->dense + (size_t)i * DENSE, *db = s->dense + (size_t)j * DENSE;
        for (int k = 0; k < DENSE; k++)
            dm = fmin(dm, da[k] + db[k]);
        double ev = gs_fun_value(a, ua) + gs_fun_value(b, ua);
        /* the early-exit variant: the same answer when it is below best,
         * otherwise a value >= best, consistent with its u */
        double ub, rb = gs_fun_pair_min_below(a, b, r * (1 + 1e-9) + 1e-300, &ub);
        st->below_bad += !(rb == r && ub == ua);
        double uc, rc = gs_fun_pair_min_below(a, b, r * (1 - 1e-3), &uc);
        st->below_bad += !(rc >= r * (1 - 1e-3) && rc == gs_fun_value(a, uc) + gs_fun_value(b, uc));
        double ug, rg = grid_pair_min(a, b, &ug), eg = gs_fun_value(a, ug) + gs_fun_value(b, ug);
        double ge = fmax(0.0, (rg - fmin(dm, r)) / fmax(dm, 1e-300)); /* lower is fine */
        st->grid_worst = fmax(st->grid_worst, ge);
        st->grid_sum += ge;
        st->grid_off += ge > 1e-3;
        st->grid_incons += !(fabs(rg - eg) <= 1e-12 * eg + 1e-15);
        if (a->closed && (gs_fun_is_sharp(a) || gs_fun_is_sharp(b))) { /* searched in a window */
            double ex = (rg - r) / fmax(r, 1e-300);
            st->loop_sharp++;
            st->loop_sharp_off += ex > 1e-6;
            st->loop_sharp_worst = fmax(st->loop_sharp_worst, ex);
        }
        double above = (r - dm) / fmax(dm, 1e-300), inc = fabs(r - ev) / fmax(ev, 1e-300);
        st->pairs++;
        st->kinds[a->squared + b->squared]++;
        st->worst_above = fmax(st->worst_above, above);
        st->worst_incons = fmax(st->worst_incons, inc);
        st->better += r < dm * (1 - 1e-12);
        if (!(r <= dm + 1e-9 * dm + 1e-300)) {
            if (st->above++ < 5)
                fprintf(stderr, "  pair %u,%u (closed %u sq %u%u m %u %u): min %.17g > dense %.17g (u %.6f)\n", i, j,
                        a->closed, a->squared, b->squared, a->degree, b->degree, r, dm, ua);
        }
        if (!(inc <= 1e-12 || fabs(r - ev) <= 1e-15)) {
            if (st->inconsistent++ < 5)
                fprintf(stderr, "  pair %u,%u (closed %u sq %u%u m %u %u): min %.17g, evaluated %.17g at u %.17g\n",
                        i, j, a->closed, a->squared, b->squared, a->degree, b->degree, r, ev, ua);
        }
    }
}

static void test_pairs_real(void)
{
    static const uint32_t ns[4] = {200, 120, 160, 90};
    pstats st;
    memset(&st, 0, sizeof st);
    double worst_gap = -INFINITY;
    for (int id = 0; id < 4; id++)
        for (uint32_t mm = 8; mm <= 12; mm += 4) {
            curve *c = malloc(sizeof *c);
            fset s;
            double me;
            uint32_t nsq = 0;
            make_curve(c, id, ns[id]);
            make_fset(c, 120, mm, &s, &me, &nsq);
            printf("  curve %d (%s%s, n %u, m_max %u): mean rel err %.4f%%, %u/%u d^2 fits\n", id,
                   c->closed ? "loop" : "path", c->bumpy ? ", bumpy" : "", c->n, mm, 100 * me, nsq,
                   s.nf);
            CHECK(me < (mm == 12 ? 0.0075 : 0.02)); /* incl. vertices on the curve */
            check_minval(&s, &worst_gap);
            check_pairs(&s, 1500, &st);
            free(s.r), free(s.dense), free(c);
        }
    printf("  pairs %ld (d+d %ld, d+d^2 %ld, d^2+d^2 %ld): above dense %ld, worst %.3g, "
           "inconsistent %ld (worst %.3g), strictly below dense %ld\n",
           st.pairs, st.kinds[0], st.kinds[1], st.kinds[2], st.above, st.worst_above,
           st.inconsistent, st.worst_incons, st.better);
    printf("  minval: worst (minval - dense min)/dense min %.3g\n", worst_gap);
    printf("  cached-grid minimiser: mean excess over the dense minimum %.2g, worst %.3g, "
           "%ld pairs above 1e-3, %ld inconsistent\n",
           st.grid_sum / st.pairs, st.grid_worst, st.grid_off, st.grid_incons);
    /* queries tolerate a small excess (fits are 0.5% accurate): bounded */
    CHECK_MSG(st.grid_incons == 0, "%ld cached-grid results not reached by the functions", st.grid_incons);
    CHECK_MSG(st.grid_sum / st.pairs < 2e-5 && st.grid_off * 500 <= st.pairs && st.grid_worst < 0.01,
              "cached-grid minimiser: mean excess %.3g, %ld above 1e-3", st.grid_sum / st.pairs, st.grid_off);
    printf("  loop pairs with a sharp dip: %ld, grid above gs_fun_pair_min by > 1e-6: %ld, worst %.3g\n",
           st.loop_sharp, st.loop_sharp_off, st.loop_sharp_worst);
    CHECK(st.loop_sharp >= 1000);
    CHECK_MSG(st.loop_sharp_off * 200 <= st.loop_sharp && st.loop_sharp_worst < 1e-4,
              "loops with a dip: %ld grid results above gs_fun_pair_min by > 1e-6 (worst %.3g)", st.loop_sharp_off,
              st.loop_sharp_worst);
    CHECK(st.pairs >= 10000);
    /* known gap: two nearly equal minima inside one coarse cell (the sum is
     * almost flat along the curve) can differ by up to ~1e-6 relative */
    CHECK_MSG(st.above * 2000 <= st.pairs && st.worst_above < 1e-5,
              "%ld pairs above the dense minimum (worst %.3g)", st.above, st.worst_above);
    CHECK_MSG(st.inconsistent == 0, "%ld pairs inconsistent with gs_fun_value", st.inconsistent);
    CHECK_MSG(st.below_bad == 0, "%ld pair_min_below results off", st.below_bad);
    CHECK(st.kinds[1] > 500 && st.kinds[2] > 50);
}

/* ---- unreachable curves, SEPsam -------------------------------------- */

static void test_infinity(void)
{
    double c[3] = {1, 0.1, 0.2};
    gs_fun inf = {GS_FUN_CHEBYSHEV, 0, 0, 0, 0.0, INFINITY, NULL};
    gs_fun f = {GS_FUN_CHEBYSHEV, 2, 0, 0, 0.0, 0.0, c};
    f.minval = gs_fun_min(&f, NULL);
    double u = 5.0;
    CHECK(isinf(gs_fun_value(&inf, 0.3)));
    CHECK(isinf(gs_fun_pair_min(&inf, &f, &u)) && u == 0.0);
    CHECK(isinf(gs_fun_pair_min(&f, &inf, NULL)));
    CHECK(isinf(gs_fun_pair_min(&inf, &inf, NULL)));
    CHECK(gs_fun_cost(&inf) == 0 && gs_fun_cost(&f) == 3);
    CHECK(isfinite(gs_fun_pair_min(&f, &f, NULL)));
}

static void test_sampled(void)
{
    double d1[MAXN], d2[MAXN], c1[MAXN], c2[MAXN];
    gs_fun a, b;
    gs_error err;
    for (int closed = 0; closed <= 1; closed++)
        for (int trial = 0; trial < 50; trial++) {
            uint32_t n = 20 + (uint32_t)(rnd() * 100);
            for (uint32_t k = 0; k < n; k++)
                d1[k] = urand(0.5, 2), d2[k] = urand(0.5, 2);
            CHECK(gs_fun_make_sampled(d1, n, closed, c1, &a, &err) == GS_OK);
            CHECK(gs_fun_make_sampled(d2, n, closed, c2, &b, &err) == GS_OK);
            CHECK(gs_fun_cost(&a) == n);
            double du = closed ? 2.0 / n : 2.0 / (n - 1);
            for (uint32_t k = 0; k + 1 < n; k++) {
                CHECK_NEAR(gs_fun_value(&a, -1 + k * du), d1[k], 1e-12);
                CHECK_NEAR(gs_fun_value(&a, -1 + (k + 0.5) * du), 0.5 * (d1[k] + d1[k + 1]), 1e-12);
            }
            if (closed)
                CHECK_NEAR(gs_fun_value(&a, 1 - 0.5 * du), 0.5 * (d1[n - 1] + d1[0]), 1e-12);
            double ua, r = gs_fun_pair_min(&a, &b, &ua), dm = INFINITY;
            for (int k = 0; k < DENSE; k++)
                dm = fmin(dm, gs_fun_value(&a, dense_u(k)) + gs_fun_value(&b, dense_u(k)));
            CHECK(r <= dm + 1e-12 && r >= dm - 0.1);
            CHECK_NEAR(gs_fun_value(&a, ua) + gs_fun_value(&b, ua), r, 1e-12);
        }
    CHECK(gs_fun_make_sampled(d1, 0, 0, c1, &a, &err) == GS_EARG);
    d1[3] = NAN;
    CHECK(gs_fun_make_sampled(d1, 10, 0, c1, &a, &err) == GS_EARG);
}

/* The cached-grid minimiser on loops: the fit is not periodic, so its seam
 * may jump; a minimum at the seam (one-sided limit) must be found exactly
 * as gs_fun_pair_min finds it, and a loop without a seam near the minimum
 * agrees with it closely. A sharp dip clamped to 0 (a vertex on the curve):
 * the minimum sits at its zero set's edge. */
static void test_grid_loops(void)
{
    double ca[3] = {1.0, 0.3, 0.0}, cb[3] = {1.0, 0.0, 0.0}, cc[3] = {1.0, 0.0, 0.5};
    for (int i = 0; i < 8; i++) {
        double shift = -0.9 + 0.237 * i; /* seam of a at u = shift - 1 (wrapped) */
        gs_fun a = {GS_FUN_CHEBYSHEV, 1, 0, 1, shift, 0.0, ca};
        gs_fun b = {GS_FUN_CHEBYSHEV, 0, 0, 1, 0.3, 0.0, cb};
        a.minval = gs_fun_min(&a, NULL), b.minval = gs_fun_min(&b, NULL);
        double u, r = gs_fun_pair_min(&a, &b, NULL), rg = grid_pair_min(&a, &b, &u);
        /* a = 1 + 0.3 t jumps from 1.3 to 0.7 at its seam: the minimum, 1.7 */
        CHECK_NEAR(r, 1.7, 1e-9);
        CHECK_MSG(fabs(rg - r) <= 1e-12 && rg == gs_fun_value(&a, u) + gs_fun_value(&b, u),
                  "seam minimum: grid %.17g, robust %.17g", rg, r);
        /* a smooth periodic partner: 1 + 0.5 T2(t) has its minimum inside */
        gs_fun c = {GS_FUN_CHEBYSHEV, 2, 0, 1, -shift, 0.0, cc};
        c.minval = gs_fun_min(&c, NULL);
        double r2 = gs_fun_pair_min(&c, &b, NULL), rg2 = grid_pair_min(&c, &b, &u);
        CHECK_MSG(fabs(rg2 - r2) <= 1e-7 * r2 && /* 16-bit grid values: the parabola's vertex ~1e-4 off */ rg2 == gs_fun_value(&c, u) + gs_fun_value(&b, u),
                  "smooth loop: grid %.17g, robust %.17g", rg2, r2);
    }
    /* sharp: d^2 = (t - 0.2)^2 - 1e-4 dips below 0 on [0.19, 0.21]; with
     * the slope of b the minimum is b at the zero set's right edge */
    double cs[3] = {0.5 * 1.0 + 0.04 - 1e-4, -0.4, 0.5}, cl[2] = {2.0, -0.5};
    for (int closed = 0; closed <= 1; closed++) {
        gs_fun a = {GS_FUN_CHEBYSHEV, 2, 1, (uint32_t)closed, 0.0, 0.0, cs};
        gs_fun b = {GS_FUN_CHEBYSHEV, 1, 0, (uint32_t)closed, 0.0, 0.0, cl};
        a.minval = gs_fun_min(&a, NULL), b.minval = gs_fun_min(&b, NULL);
        gs_fun_dip d;
        gs_fun_dip_find(&a, &d);
        CHECK_NEAR(d.lo, 0.19, 1e-9);
        CHECK_NEAR(d.hi, 0.21, 1e-9);
        double u, r = gs_fun_pair_min(&a, &b, NULL), rg = grid_pair_min(&a, &b, &u);
        CHECK_NEAR(r, 2.0 - 0.5 * 0.21, 1e-9);
        CHECK_MSG(rg >= r && rg - r <= 1e-8, "zero-set edge: grid %.17g, robust %.17g", rg, r);
    }
}

/* The tolerance schedule over tree depth: tol at the root, 1.5x per level,
 * capped at max(tol, 2%). */
/* The query's grid values (src/query/pair_grid.c): a path's within float
 * rounding of the function's values; a loop's, interpolated (cubic) from its
 * own variable's uniform points, within the interpolation bound 3/128 h^4
 * max|p''''| (exact when the shift falls on the grid); values beyond float
 * range give a minimiser answer all the same (the robust one). */
static void test_grid_values(void)
{
    double c[7] = {2.0, -0.7, 0.4, 0.05, 0.03, -0.01, 0.004}, big[2] = {1e60, 1e59};
    static const double shifts[3] = {0.0, 0.37, -1.5};
    for (int t = 0; t < 4; ++t) {
        int closed = t > 0;
        gs_fun f = {GS_FUN_CHEBYSHEV, 6, (uint32_t)(t & 1), (uint32_t)closed, closed ? shifts[t - 1] : 0.0, 0.0, c};
        uint32_t g = gs_fun_grid_points(f.degree);
        float v[GS_FUN_GRID_MAX];
        gs__grid_values(&f, g, v);
        double h = 2.0 / g, p4 = 0.0, worst = 0.0;
        for (uint32_t k = 4; k <= f.degree; ++k) {
            double k2 = (double)k * k;
            p4 += fabs(c[k]) * k2 * (k2 - 1) * (k2 - 4) * (k2 - 9) / 105.0;
        }
        double bound = closed && f.shift != 0.0 ? 3.0 / 128.0 * h * h * h * h * p4 + 1e-6 : 1e-6;
        for (uint32_t j = 0; j < g; ++j) {
            double u = closed ? -1.0 + 2.0 * j / g : -1.0 + 2.0 * j / (g - 1);
            gs_fun sq = f;
            sq.squared = 0; /* the bound is on the series: compare p, then its root */
            double pv = gs_fun_value(&sq, u), e = fabs((double)v[j] - gs_fun_value(&f, u));
            if (f.squared) e = fabs((double)v[j] * v[j] - pv);
            worst = fmax(worst, e);
        }
        CHECK_MSG(worst <= bound * (1 + 1e-3) + 1e-6, "grid (%s, shift %g): off by %.3g, bound %.3g",
                  closed ? "loop" : "path", f.shift, worst, bound);
        printf("  grid values (%s, shift %g, %u points): worst error %.3g (bound %.3g)\n", closed ? "loop" : "path",
               f.shift, g, worst, bound);
    }
    gs_fun a = {GS_FUN_CHEBYSHEV, 1, 0, 0, 0.0, 0.0, big}, b = a;
    double r = gs_fun_pair_min(&a, &b, NULL), rg = grid_pair_min(&a, &b, NULL);
    CHECK(r == rg); /* no float grid: the robust minimiser */
}

static void test_depth_tol(void)
{
    const double expect[8] = {0.002, 0.003, 0.0045, 0.00675, 0.010125, 0.0151875, 0.02, 0.02};
    for (uint32_t d = 0; d < 8; d++)
        CHECK_NEAR(gs_fit_tol_at_depth(0.002, d), expect[d], 1e-15);
    CHECK_NEAR(gs_fit_tol_at_depth(0.002, 1000000), 0.02, 0);
    for (uint32_t d = 0; d < 5; d++) /* looser than the cap at the root: kept */
        CHECK_NEAR(gs_fit_tol_at_depth(0.05, d), 0.05, 0);
    CHECK_NEAR(gs_fit_tol_at_depth(0.015, 1), 0.02, 0);
}

/* The certificate between samples (fit.h): a vertex at height h over a
 * straight path of length L (flat: d(s) = sqrt(h^2 + (s - s0)^2) exactly)
 * with few samples, for dips at many places. Without the certificate
 * (ulen 0) high-degree fits of samples that pass at the samples swing
 * between them; with it, the kept fit stays within the samples' Lipschitz
 * band wherever it reports so (cert_err), and its true error between the
 * samples is far smaller. */
/* The certificate between samples (fit.h): few samples (21) of a distance
 * with a kink, d(s) = 0.05 + |s - s0| (1-Lipschitz in arc length, like
 * every separator distance function; the kind a vertex beyond a curve's
 * bend sees), kinks at many places. Without the certificate (ulen 0) the
 * degree climbs until the samples are met and the series swings between
 * them; with it, the kept fit stays within the samples' Lipschitz band
 * wherever it reports so (cert_err), and its true error is smaller. */
static void test_certificate(void)
{
    gs_fit_work *w = make_work(2, 20, 0.002);
    enum { N = 21, FINE = 4000 };
    double u[N], d[N], L = 2.0, worst_cert = 0, worst_plain = 0, band_plain = 0;
    uniform_u(u, N, 0);
    for (int q = 0; q < 40; ++q) {
        double s0 = L * (0.013 + 0.024 * q);
        for (int k = 0; k < N; ++k) d[k] = 0.05 + fabs((u[k] + 1) * L / 2 - s0);
        gs_fit_result rc, rp;
        CHECK(gs_fit_distance(w, u, d, N, 0, L / 2, &rc, NULL) == GS_OK);
        CHECK(gs_fit_distance(w, u, d, N, 0, 0, &rp, NULL) == GS_OK);
        CHECK(rp.cert_err == 0 && rc.cert_err >= 0);
        double ec = 0, ep = 0, band = 0, bandp = 0;
        for (int i = 0; i <= FINE; ++i) {
            double t = -1 + 2.0 * i / FINE, s = (t + 1) * L / 2, dt = 0.05 + fabs(s - s0);
            double vc = gs_fun_value(&rc.fun, t), vp = gs_fun_value(&rp.fun, t);
            int k = (int)((t + 1) / 2 * (N - 1)); /* the samples k, k+1 around t */
            if (k > N - 2) k = N - 2;
            double da = (t - u[k]) * L / 2, db = (u[k + 1] - t) * L / 2;
            double lo = fmax(d[k] - da, d[k + 1] - db), hi = fmin(d[k] + da, d[k + 1] + db);
            band = fmax(band, vc < lo ? (lo - vc) / lo : vc > hi ? (vc - hi) / hi : 0);
            bandp = fmax(bandp, vp < lo ? (lo - vp) / lo : vp > hi ? (vp - hi) / hi : 0);
            ec = fmax(ec, fabs(vc - dt) / dt);
            ep = fmax(ep, fabs(vp - dt) / dt);
        }
        /* checked at 3 points per interval: allow a little more at others */
        CHECK_MSG(band <= fmax(rc.cert_err, GS_FIT_MAX_ERR) * 1.5 + 1e-9, "kink at %g: band %g, reported %g", s0,
                  band, rc.cert_err);
        worst_cert = fmax(worst_cert, ec);
        worst_plain = fmax(worst_plain, ep);
        band_plain = fmax(band_plain, bandp);
    }
    printf("  certificate: worst true error %.2f%% certified, %.2f%% without (outside the band by %.2f%%)\n",
           100 * worst_cert, 100 * worst_plain, 100 * band_plain);
    CHECK_MSG(band_plain > 2 * GS_FIT_MAX_ERR, "the uncertified fits stay in the band (%g): no test", band_plain);
    CHECK_MSG(worst_cert < 0.5 * worst_plain, "certified %g vs plain %g", worst_cert, worst_plain);
    gs_fit_work_free(w);
}

int main(void)
{
    printf("chebyshev kernels\n");
    test_wrap();
    test_cheb();
    printf("fitting\n");
    test_poly_reproduction();
    test_segment();
    test_loops();
    test_escalation();
    test_near_zero();
    test_tiny_and_bad();
    test_depth_tol();
    test_certificate();
    printf("pair minimum vs dense scan\n");
    test_pairs_real();
    test_grid_loops();
    printf("  loops with the seam cells given: %ld of %ld pairs differ\n", cell_diff, cell_loops);
    CHECK_MSG(cell_diff == 0 && cell_loops > 1000, "seam cells given: %ld of %ld loop pairs differ", cell_diff,
              cell_loops);
    test_seam_cell();
    test_grid_values();
    test_infinity();
    test_sampled();
    return gs_test_finish("test_fit");
}
