/* bench/within.c - neighbourhoods and fields from a database (issue 19
 * items 3-4): for random sources, the time of
 *   - n single queries (gs_db_distance to every vertex, one by one),
 *   - a whole field (gs_db_field: x's work shared by all targets), and
 *     on 2 threads (gs_db_field_threads),
 *   - gs_db_within at the radii holding 0.1%, 1% and 10% of the vertices
 *     (each source's own quantiles of its field),
 * measured alternately source after source (medians and the median of the
 * per-source ratios); the first within call on a fresh database (which
 * computes the neighbourhood bounds); gs_db_nearest among random
 * candidates; and gs_db_radius_matrix's throughput on 1 and 2 threads.
 * usage: bench_within DB [SOURCES] */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t rng_state = 0x853C49E6748FEA9Bull;
static uint32_t rng(uint32_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)((rng_state >> 11) % n);
}

#define N_FRAC 3
static const double fracs[N_FRAC] = {0.001, 0.01, 0.1};

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_within DB [SOURCES]\n");
        return 2;
    }
    int ns = argc > 2 ? atoi(argv[2]) : 20;
    if (ns < 1) ns = 1;
    gs_db *db = NULL;
    gs_error err = {0};
    double t0 = now();
    if (gs_db_open(argv[1], &db, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    double t_open = now() - t0;
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    const uint32_t n = info.n_vertices;
    printf("%s: %u vertices, %u nodes, %u curves, depth avg %.2f; open %.3f ms\n", argv[1], n, info.n_nodes,
           info.n_curves, info.avg_depth, 1e3 * t_open);

    /* the first within on the fresh database builds the bounds */
    uint32_t x0 = rng(n);
    while (gs_db_vertex_leaf(db, x0) == GS_NONE) x0 = rng(n);
    gs_neighbors *nb = NULL;
    t0 = now();
    gs_db_within(db, x0, 0.0, &nb, NULL);
    double t_first = now() - t0;
    gs_neighbors_free(nb);
    t0 = now();
    gs_db_within(db, x0, 0.0, &nb, NULL);
    double t_second = now() - t0;
    gs_neighbors_free(nb);
    printf("first gs_db_within on the opened database (computes the bounds): %.3f ms; the next: %.4f ms\n",
           1e3 * t_first, 1e3 * t_second);

    double *f = malloc((size_t)n * sizeof *f), *g = malloc((size_t)n * sizeof *g), *s = malloc((size_t)n * sizeof *s);
    double *t_single = malloc(ns * sizeof(double)), *t_field = malloc(ns * sizeof(double)),
           *t_field2 = malloc(ns * sizeof(double));
    double *t_w[N_FRAC], *ratio_w[N_FRAC], *cnt[N_FRAC], *rad[N_FRAC], *ratio_f = malloc(ns * sizeof(double));
    for (int q = 0; q < N_FRAC; ++q) {
        t_w[q] = malloc(ns * sizeof(double)), ratio_w[q] = malloc(ns * sizeof(double));
        cnt[q] = malloc(ns * sizeof(double)), rad[q] = malloc(ns * sizeof(double));
    }
    double check = 0;
    long mismatches = 0;
    for (int i = 0; i < ns; ++i) {
        uint32_t x = rng(n);
        while (gs_db_vertex_leaf(db, x) == GS_NONE) x = rng(n);
        t0 = now();
        for (uint32_t y = 0; y < n; ++y) g[y] = gs_db_distance(db, x, y);
        t_single[i] = now() - t0;
        t0 = now();
        gs_db_field(db, x, f, NULL);
        t_field[i] = now() - t0;
        ratio_f[i] = t_single[i] / t_field[i];
        t0 = now();
        gs_db_field_threads(db, x, s, 2, NULL);
        t_field2[i] = now() - t0;
        for (uint32_t y = 0; y < n; ++y) mismatches += memcmp(&f[y], &s[y], 8) != 0;
        for (uint32_t y = 0; y < n; ++y) mismatches += memcmp(&f[y], &g[y], 8) != 0;
        uint32_t m = 0;
        for (uint32_t y = 0; y < n; ++y)
            if (isfinite(f[y])) s[m++] = f[y];
        qsort(s, m, sizeof *s, cmp_double);
        for (int q = 0; q < N_FRAC; ++q) {
            double r = s[(uint32_t)(fracs[q] * n) < m ? (uint32_t)(fracs[q] * n) : m - 1];
            t0 = now();
            gs_db_within(db, x, r, &nb, NULL);
            t_w[q][i] = now() - t0;
            ratio_w[q][i] = t_field[i] / t_w[q][i];
            cnt[q][i] = nb ? (double)nb->n : 0;
            rad[q][i] = r;
            check += nb && nb->n ? nb->dist[nb->n - 1] : 0;
            gs_neighbors_free(nb);
        }
    }
    printf("%d random sources, alternately (medians; one thread unless said):\n", ns);
    double ms = median(t_single, ns), mf = median(t_field, ns);
    printf("  %u single queries (gs_db_distance): %.3f ms; gs_db_field: %.3f ms; ratio %.2fx (median of per-source "
           "ratios %.2fx); %ld values differ\n",
           n, 1e3 * ms, 1e3 * mf, ms / mf, median(ratio_f, ns), mismatches);
    double mf2 = median(t_field2, ns);
    printf("  gs_db_field_threads, 2 threads: %.3f ms (%.2fx the n single queries, %.2fx one thread)\n", 1e3 * mf2,
           ms / mf2, mf / mf2);
    for (int q = 0; q < N_FRAC; ++q) {
        double mw = median(t_w[q], ns), mc = median(cnt[q], ns), mr = median(rad[q], ns);
        printf("  gs_db_within, radius holding %.1f%% (median r %.4g, %.0f vertices): %.4f ms; field / within %.1fx "
               "(median of per-source ratios %.1fx)\n",
               100 * fracs[q], mr, mc, 1e3 * mw, mf / mw, median(ratio_w[q], ns));
    }

    /* k nearest among random candidates */
    {
        const int nc = 1000, k = 10, reps = ns;
        uint32_t *c = malloc(nc * sizeof *c);
        double *tn = malloc(reps * sizeof(double)), *tb = malloc(reps * sizeof(double));
        for (int i = 0; i < reps; ++i) {
            uint32_t x = rng(n);
            for (int j = 0; j < nc; ++j) c[j] = rng(n);
            t0 = now();
            gs_db_nearest(db, x, c, nc, k, &nb, NULL);
            tn[i] = now() - t0;
            gs_neighbors_free(nb);
            double *pairs_d = malloc(nc * sizeof(double));
            t0 = now();
            for (int j = 0; j < nc; ++j) pairs_d[j] = gs_db_distance(db, x, c[j]);
            tb[i] = now() - t0;
            check += pairs_d[0];
            free(pairs_d);
        }
        double a = median(tn, reps), b = median(tb, reps);
        printf("  gs_db_nearest, k = %d of %d random candidates: %.4f ms (the %d single queries: %.4f ms, %.1fx)\n", k,
               nc, 1e3 * a, nc, 1e3 * b, b / a);
        free(c), free(tn), free(tb);
    }

    /* radius matrix throughput at the 1% radius */
    {
        double r = median(rad[1], ns);
        uint32_t nsrc = n < 2000 ? n : 2000;
        uint32_t *src = malloc(nsrc * sizeof *src);
        for (uint32_t i = 0; i < nsrc; ++i) src[i] = rng(n);
        for (uint32_t th = 1; th <= 2; ++th) {
            gs_csr *m = NULL;
            t0 = now();
            int rc = gs_db_radius_matrix(db, src, nsrc, r, th, &m, &err);
            double t = now() - t0;
            if (rc) {
                fprintf(stderr, "%s\n", err.message);
                return 1;
            }
            printf("  gs_db_radius_matrix, %u sources, r %.4g, %u thread%s: %.3f s, %.0f rows/s, %.3g entries/s "
                   "(%llu entries)\n",
                   nsrc, r, th, th > 1 ? "s" : "", t, nsrc / t, m->nnz / t, (unsigned long long)m->nnz);
            gs_csr_free(m);
        }
        free(src);
    }
    printf("(checksum %g)\n", check);
    for (int q = 0; q < N_FRAC; ++q) free(t_w[q]), free(ratio_w[q]), free(cnt[q]), free(rad[q]);
    free(f), free(g), free(s), free(t_single), free(t_field), free(t_field2), free(ratio_f);
    gs_db_free(db);
    return 0;
}
