/* bench/fit.c - speed of the separator distance functions (paper sec. 4.2,
 * 4.3): ns per gs__fun_value and per gs__fun_pair_min for degrees 4..20, paths
 * and loops, split by the kinds of the pair (d+d, d+d^2, d^2+d^2), and per
 * fit (n = 50, 200, 1000 samples, m_max 12). Single thread, median of 7 runs.
 * Data: distances from random points (a quarter of them close to the curve,
 * giving d^2 fits) to a wavy planar path or an ellipse-like loop.
 * With GS_BENCH_BELOW defined at compile time (the default) it also times
 * gs__fun_pair_min_below in a query-like sequence. */
#include "bench_util.h"
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../src/fit/fit.h"
#include "../src/fit/fun.h"

#ifndef GS_BENCH_BELOW
#define GS_BENCH_BELOW 1
#endif

#define NF 256
#define NP 4096
#define RUNS 7

static uint64_t g_rng = 99;

static double rnd(void)
{
    uint64_t z = (g_rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static void curve_at(int closed, double u, double *x, double *y)
{
    double th = M_PI * (u + 1.0);
    *x = closed ? cos(th) : u;
    *y = closed ? 0.8 * sin(th) : 0.3 * sin(2.5 * u);
}

/* Distances from (px, py) to n uniform samples of a wavy path or a loop. */
static void samples(int closed, uint32_t n, double px, double py, double *u, double *d)
{
    for (uint32_t k = 0; k < n; k++) {
        u[k] = closed ? -1.0 + 2.0 * k / n : -1.0 + 2.0 * k / (n - 1);
        double x, y;
        curve_at(closed, u[k], &x, &y);
        d[k] = hypot(px - x, py - y);
    }
}

/* NF functions of exactly degree m (m_min = m_max = m); every fourth point
 * lies within 0.05 of the curve (d^2 fits, sharp dips). */
static void make_funs(int closed, uint32_t m, gs__fit_result *r, uint32_t *nsq)
{
    gs__fit_options o = {m, m, 0.005};
    gs__fit_work *w = NULL;
    double u[200], d[200];
    if (gs__fit_work_create(200, &o, &w, NULL))
        exit(1);
    *nsq = 0;
    for (int i = 0; i < NF; i++) {
        double px = 4 * rnd() - 2, py = 4 * rnd() - 2;
        if (i % 4 == 0) {
            curve_at(closed, 2 * rnd() - 1, &px, &py);
            px += 0.1 * rnd() - 0.05, py += 0.1 * rnd() - 0.05;
        }
        samples(closed, 200, px, py, u, d);
        if (gs__fit_distance(w, u, d, 200, closed, 0, &r[i], NULL))
            exit(1);
        r[i].fun.coef = r[i].coef;
        *nsq += r[i].fun.squared;
    }
    gs__fit_work_free(w);
}

static double g_sink;

/* ns per pair_min over the n pairs (ia, ib), median of RUNS. */
static double time_pairs(const gs__fit_result *r, const uint32_t *ia, const uint32_t *ib, int n)
{
    double t[RUNS];
    int reps = 1 + 20000 / (n > 0 ? n : 1);
    if (n == 0)
        return NAN;
    for (int run = 0; run < RUNS; run++) {
        double t0 = now();
        for (int rep = 0; rep < reps; rep++)
            for (int k = 0; k < n; k++)
                g_sink += gs__fun_pair_min(&r[ia[k]].fun, &r[ib[k]].fun, NULL);
        t[run] = (now() - t0) / ((double)reps * n) * 1e9;
    }
    return median(t, RUNS);
}

#if GS_BENCH_BELOW
/* A query-like sequence: three candidate pairs, the first with no bound, the
 * next two against the running minimum; ns per call with pair_min and with
 * pair_min_below, and the fraction of calls cut short. */
static void time_below(const gs__fit_result *r, const uint32_t *ia, const uint32_t *ib, int n,
                       double *t_full, double *t_below, double *frac_cut)
{
    double tf[RUNS], tb[RUNS];
    long cut = 0, calls = 0;
    for (int run = 0; run < RUNS; run++) {
        double t0 = now();
        for (int rep = 0; rep < 5; rep++)
            for (int k = 0; k + 2 < n; k += 3) {
                double best = INFINITY;
                for (int i = 0; i < 3; i++) {
                    double d = gs__fun_pair_min(&r[ia[k + i]].fun, &r[ib[k + i]].fun, NULL);
                    best = d < best ? d : best;
                }
                g_sink += best;
            }
        tf[run] = (now() - t0) / (5.0 * (n / 3) * 3) * 1e9;
        t0 = now();
        for (int rep = 0; rep < 5; rep++)
            for (int k = 0; k + 2 < n; k += 3) {
                double best = INFINITY;
                for (int i = 0; i < 3; i++) {
                    double d = gs__fun_pair_min_below(&r[ia[k + i]].fun, &r[ib[k + i]].fun, best, NULL);
                    if (run == 0 && rep == 0)
                        cut += i > 0 && d >= best, calls++;
                    best = d < best ? d : best;
                }
                g_sink += best;
            }
        tb[run] = (now() - t0) / (5.0 * (n / 3) * 3) * 1e9;
    }
    *t_full = median(tf, RUNS), *t_below = median(tb, RUNS);
    *frac_cut = calls ? (double)cut / calls : 0.0;
}
#endif

static void bench_funs(int closed, uint32_t m)
{
    static gs__fit_result r[NF];
    static uint32_t ia[NP], ib[NP], ka[3][NP], kb[3][NP];
    static double us[NP];
    int nk[3] = {0, 0, 0};
    uint32_t nsq;
    make_funs(closed, m, r, &nsq);
    for (int k = 0; k < NP; k++)
        ia[k] = (uint32_t)(rnd() * NF), ib[k] = (uint32_t)(rnd() * NF), us[k] = 2 * rnd() - 1;
    for (uint32_t i = 0; i < NF; i++) /* every kind of pair, in a fixed order */
        for (uint32_t j = 0; j < NF; j++) {
            uint32_t a = (i * 97 + j * 31) % NF, b = (j * 61 + i * 13 + 7) % NF;
            int kind = (int)(r[a].fun.squared + r[b].fun.squared);
            if (nk[kind] < NP)
                ka[kind][nk[kind]] = a, kb[kind][nk[kind]++] = b;
        }
    double tv[RUNS];
    for (int run = 0; run < RUNS; run++) {
        double t0 = now();
        for (int rep = 0; rep < 50; rep++)
            for (int k = 0; k < NP; k++)
                g_sink += gs__fun_value(&r[ia[k]].fun, us[k]);
        tv[run] = (now() - t0) / (50 * NP) * 1e9;
    }
    double tall = time_pairs(r, ia, ib, NP), tk[3];
    for (int kind = 0; kind < 3; kind++)
        tk[kind] = time_pairs(r, ka[kind], kb[kind], nk[kind]);
    printf("%-4s m=%-2u %3u/%u d^2 | value %5.1f | pair_min all %6.1f  d+d %6.1f  d+d2 %6.1f  "
           "d2+d2 %6.1f ns",
           closed ? "loop" : "path", m, nsq, NF, median(tv, RUNS), tall, tk[0], tk[1], tk[2]);
#if GS_BENCH_BELOW
    double tf, tb, fc;
    time_below(r, ia, ib, NP, &tf, &tb, &fc);
    printf(" | seq of 3: full %6.1f  below %6.1f ns/call (%2.0f%% cut)", tf, tb, 100 * fc);
#endif
    printf("\n");
}

static void bench_fit(uint32_t n, int closed)
{
    gs__fit_work *w = NULL;
    double *u = malloc(n * sizeof *u), *d = malloc(n * sizeof *d), t[RUNS], deg = 0;
    gs__fit_result r;
    if (gs__fit_work_create(n, NULL, &w, NULL))
        exit(1);
    int reps = n >= 1000 ? 40 : 200;
    for (int run = 0; run < RUNS; run++) {
        double t0 = now();
        for (int i = 0; i < reps; i++) {
            samples(closed, n, 4 * rnd() - 2, 4 * rnd() - 2, u, d);
            gs__fit_distance(w, u, d, n, closed, 0, &r, NULL);
            deg += r.fun.degree;
        }
        t[run] = (now() - t0) / reps * 1e6;
    }
    printf("fit n=%-4u %s m_max 12: %8.1f us per fit (mean degree %.1f, incl. sampling)\n", n,
           closed ? "loop" : "path", median(t, RUNS), deg / (RUNS * reps));
    gs__fit_work_free(w);
    free(u), free(d);
}

int main(int argc, char **argv)
{
    int fits = !(argc > 1 && strcmp(argv[1], "--pairs") == 0);
    for (int closed = 0; closed <= 1; closed++)
        for (uint32_t m = 4; m <= 20; m += 4)
            bench_funs(closed, m);
    for (int closed = 0; closed <= 1 && fits; closed++)
        for (uint32_t n = 50; n <= 1000; n = n == 50 ? 200 : (n == 200 ? 1000 : 2000))
            bench_fit(n, closed);
    printf("(sink %.3g)\n", g_sink);
    return 0;
}
