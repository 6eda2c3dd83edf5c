/* bench/db_paths.c - geodesic paths from a database (gs_db_path) against
 * the exact distance: time per path and the length ratio (path length /
 * exact distance) over random vertex pairs and random surface-point pairs.
 * Usage: bench_db_paths MESH DB [N_SOURCES=10] [TARGETS=100] [SEED=1]
 * [POINT_PAIRS=2 N_SOURCES]; with the environment variable
 * GEOSEP_BENCH_WORST=K, the K point pairs with the largest ratios are
 * listed (face and barycentric weights of both ends), and every vertex pair
 * over 1% as it is found.
 * Sources and targets are random vertices (gs_mesh_random_vertices; the
 * surface points: random faces with random barycentric weights); the exact
 * distances come from one exact field per source (gs_solver_solve; for the
 * point pairs gs_solver_path, all solved before the point pairs are
 * timed). Times are the calling thread's CPU time per path (median, mean,
 * 99th percentile and maximum over all pairs): on a shared machine,
 * wall-clock time would count the other jobs' turns. */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* Seconds of CPU time of the calling thread. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double quantile(double *v, size_t n, double q)
{
    qsort(v, n, sizeof *v, cmp_double);
    size_t k = (size_t)ceil(q * (double)n);
    return v[k ? k - 1 : 0];
}

static uint64_t rng = 1;
static double uniform(void)
{
    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct stats {
    double *ratio, *us;
    size_t n, cap;
    double points;
} stats;

static void add(stats *s, double ratio, double us, uint32_t points)
{
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1024;
        s->ratio = realloc(s->ratio, s->cap * sizeof *s->ratio);
        s->us = realloc(s->us, s->cap * sizeof *s->us);
        if (!s->ratio || !s->us) exit(3);
    }
    s->ratio[s->n] = ratio, s->us[s->n] = us, s->n++;
    s->points += points;
}

static void report(const char *what, stats *s)
{
    if (!s->n) return;
    double mean = 0, below = 0, tmean = 0;
    size_t over1 = 0;
    for (size_t i = 0; i < s->n; ++i) {
        mean += s->ratio[i], tmean += s->us[i];
        if (s->ratio[i] > 1.01) ++over1;
        if (s->ratio[i] < 1 && 1 - s->ratio[i] > below) below = 1 - s->ratio[i];
    }
    mean /= (double)s->n;
    double pts = s->points / (double)s->n;
    double r99 = quantile(s->ratio, s->n, 0.99), rmax = quantile(s->ratio, s->n, 1.0);
    double t50 = quantile(s->us, s->n, 0.5), t99 = quantile(s->us, s->n, 0.99), tmax = quantile(s->us, s->n, 1.0);
    printf("%-13s %6zu paths | ratio mean %.5f p99 %.5f max %.5f (>1.01: %zu; most below 1: %.1e) | %.0f points | "
           "time median %.0f us mean %.0f us p99 %.0f us max %.0f us\n",
           what, s->n, mean, r99, rmax, over1, below, pts, t50, tmean / (double)s->n, t99, tmax);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s MESH DB [n_sources=10] [targets=100] [seed=1] [point_pairs=2*n_sources]\n",
                argv[0]);
        return 2;
    }
    uint32_t ns = argc > 3 ? (uint32_t)atoi(argv[3]) : 10, nt = argc > 4 ? (uint32_t)atoi(argv[4]) : 100;
    rng = argc > 5 ? (uint64_t)atoll(argv[5]) : 1;
    uint32_t npts = argc > 6 ? (uint32_t)atoi(argv[6]) : ns * 2;
    const char *worst_env = getenv("GEOSEP_BENCH_WORST");
    uint32_t nworst = worst_env ? (uint32_t)atoi(worst_env) : 0;
    gs_error err = {0};
    gs_mesh *mesh = NULL;
    gs_db *db = NULL;
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    if (gs_mesh_load(argv[1], GS_FORMAT_AUTO, &mesh, &err) || gs_db_open(argv[2], &db, &err) ||
        gs_db_check_mesh(db, mesh, &err) || gs_patch_create(mesh, NULL, 0, &patch, &err) ||
        gs_solver_create(patch, GS_METHOD_EXACT, &solver, &err)) {
        fprintf(stderr, "bench_db_paths: %s\n", err.message);
        return 1;
    }
    uint32_t nv = gs_mesh_num_vertices(mesh), nf = gs_mesh_num_faces(mesh);
    uint32_t *src = malloc(ns * sizeof *src), *tgt = malloc(nt * sizeof *tgt);
    double *field = malloc(nv * sizeof *field);
    if (!src || !tgt || !field || gs_mesh_random_vertices(mesh, ns, 12345, src, &err)) {
        fprintf(stderr, "bench_db_paths: %s\n", err.message);
        return 1;
    }
    stats sv = {0}, sp = {0};
    int failures = 0;
    for (uint32_t i = 0; i < ns; ++i) {
        gs_source x = gs_source_vertex(src[i]);
        if (gs_solver_solve(solver, &x, 1, INFINITY, field, &err) ||
            gs_mesh_random_vertices(mesh, nt, 1000 + i, tgt, &err)) {
            fprintf(stderr, "bench_db_paths: %s\n", err.message);
            return 1;
        }
        for (uint32_t j = 0; j < nt; ++j) {
            if (tgt[j] == src[i] || !isfinite(field[tgt[j]])) continue;
            gs_source y = gs_source_vertex(tgt[j]);
            gs_path *p = NULL;
            double t0 = cpu_now();
            int rc = gs_db_path(db, mesh, &x, &y, &p, &err);
            double t1 = cpu_now();
            if (rc) {
                fprintf(stderr, "path %u -> %u: %s\n", src[i], tgt[j], err.message);
                ++failures;
                continue;
            }
            double r = gs_path_length(p) / field[tgt[j]];
            add(&sv, r, 1e6 * (t1 - t0), gs_path_num_points(p));
            if (nworst && r > 1.01) printf("vertex pair over 1%%: %u -> %u ratio %.5f\n", src[i], tgt[j], r);
            gs_path_free(p);
        }
    }
    /* surface points: exact lengths from gs_solver_path (one field each),
     * all of them first: an exact solve of the whole mesh before each
     * timed path would leave it the caches of a field, not of the paths
     * before it (homer-60k: the median point pair 1.45 times slower) */
    struct worst {
        double ratio;
        gs_source e[2];
    } *worst = calloc(nworst + 1, sizeof *worst);
    gs_source *ends = malloc(2 * (size_t)(npts ? npts : 1) * sizeof *ends);
    double *exact = malloc((npts ? npts : 1) * sizeof *exact);
    if (!worst || !ends || !exact) return 3;
    for (uint32_t i = 0; i < npts; ++i) {
        gs_source *e = ends + 2 * (size_t)i;
        for (int k = 0; k < 2; ++k) {
            uint32_t f = (uint32_t)(uniform() * nf);
            double a = uniform(), b = uniform();
            if (a + b > 1) a = 1 - a, b = 1 - b;
            e[k] = gs_source_point(f < nf ? f : nf - 1, a, b, 1 - a - b);
        }
        gs_path *q = NULL;
        if (gs_solver_path(solver, &e[0], &e[1], &q, &err)) {
            fprintf(stderr, "bench_db_paths: exact: %s\n", err.message);
            return 1;
        }
        exact[i] = gs_path_length(q);
        gs_path_free(q);
    }
    for (uint32_t i = 0; i < npts; ++i) {
        const gs_source *e = ends + 2 * (size_t)i;
        gs_path *p = NULL;
        double t0 = cpu_now();
        int rc = gs_db_path(db, mesh, &e[0], &e[1], &p, &err);
        double t1 = cpu_now();
        if (rc) {
            fprintf(stderr, "point path %u: %s\n", i, err.message);
            ++failures;
        } else if (isfinite(exact[i]) && exact[i] > 0) {
            double r = gs_path_length(p) / exact[i];
            add(&sp, r, 1e6 * (t1 - t0), gs_path_num_points(p));
            uint32_t k = nworst; /* insertion into the K largest, largest first */
            while (k > 0 && worst[k - 1].ratio < r) {
                if (k < nworst) worst[k] = worst[k - 1];
                --k;
            }
            if (k < nworst) worst[k] = (struct worst){r, {e[0], e[1]}};
        }
        gs_path_free(p);
    }
    free(ends), free(exact);
    printf("%s, %u vertices; database %s\n", argv[1], nv, argv[2]);
    report("vertex pairs", &sv);
    report("point pairs", &sp);
    for (uint32_t k = 0; k < nworst && k < sp.n; ++k) {
        const gs_source *a = &worst[k].e[0], *b = &worst[k].e[1];
        printf("worst point pair %u: ratio %.5f: face %u (%.17g, %.17g, %.17g) -> face %u (%.17g, %.17g, %.17g)\n", k,
               worst[k].ratio, a->face, a->bary[0], a->bary[1], a->bary[2], b->face, b->bary[0], b->bary[1],
               b->bary[2]);
    }
    free(worst);
    if (failures) printf("%d failures\n", failures);
    free(sv.ratio), free(sv.us), free(sp.ratio), free(sp.us);
    free(src), free(tgt), free(field);
    gs_solver_free(solver);
    gs_patch_free(patch);
    gs_db_free(db);
    gs_mesh_free(mesh);
    return failures ? 1 : 0;
}
