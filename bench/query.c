/* bench/query.c - query speed of a database (paper sec. 3.2, appendix A.2):
 * median time of single point-to-point queries over a million random pairs
 * (one thread), queries per second, full distance fields, open time, size;
 * with the mesh, surface-point queries (gs_db_point_distance: random points
 * of random faces) beside the vertex queries. */
#include "bench_util.h"
#include "geosep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N_PAIRS 1000000u
#define BATCH 1000u
#define N_FIELDS 20u
#define N_POINT_PAIRS 200000u

static uint64_t rng_state = 0x853C49E6748FEA9Bull;
static uint32_t rng(uint32_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)((rng_state >> 11) % n);
}

/* Single queries, timed individually (timer overhead subtracted) and in
 * batches of BATCH. Returns the median of the single timings. */
static double bench_pairs(const gs_db *db, uint32_t nv)
{
    uint32_t *pairs = malloc(sizeof *pairs * 2 * N_PAIRS);
    double *t = malloc(sizeof *t * N_PAIRS), *tb = malloc(sizeof *tb * (N_PAIRS / BATCH)), sum = 0;
    for (uint32_t i = 0; i < 2 * N_PAIRS; ++i) pairs[i] = rng(nv);
    double t0 = timer_overhead();
    for (uint32_t i = 0; i < N_PAIRS; ++i) {
        double a = now();
        sum += gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        t[i] = now() - a - t0;
    }
    double total = now();
    for (uint32_t b = 0; b < N_PAIRS / BATCH; ++b) {
        double a = now();
        for (uint32_t i = b * BATCH; i < (b + 1) * BATCH; ++i) sum += gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        tb[b] = (now() - a) / BATCH;
    }
    total = now() - total;
    double *outb = malloc(sizeof *outb * BATCH), tapi = now();
    for (uint32_t b = 0; b < N_PAIRS / BATCH; ++b) { /* the batch API: gs_db_distances */
        gs_db_distances(db, pairs + 2 * (size_t)b * BATCH, BATCH, outb, NULL);
        for (uint32_t i = 0; i < BATCH; ++i) sum += outb[i];
    }
    tapi = now() - tapi;
    free(outb);
    qsort(t, N_PAIRS, sizeof *t, cmp_double);
    qsort(tb, N_PAIRS / BATCH, sizeof *tb, cmp_double);
    printf("single queries (%u random pairs, one thread):\n", N_PAIRS);
    printf("  median %.0f ns, p90 %.0f ns, p99 %.0f ns (individually timed, timer %.0f ns subtracted)\n",
           1e9 * t[N_PAIRS / 2], 1e9 * t[N_PAIRS / 10 * 9], 1e9 * t[N_PAIRS / 100 * 99], 1e9 * t0);
    printf("  median of %u-query batches: %.0f ns/query; %.3g queries/s overall (checksum %g)\n", BATCH,
           1e9 * tb[N_PAIRS / BATCH / 2], N_PAIRS / total, sum);
    printf("  batch API (gs_db_distances, %u pairs a call): %.0f ns/query; %.3g queries/s\n", BATCH, 1e9 * tapi / N_PAIRS,
           N_PAIRS / tapi);
    double median = t[N_PAIRS / 2];
    free(pairs);
    free(t);
    free(tb);
    return median;
}

/* A uniformly random point of a uniformly chosen face. */
static gs_surface_point random_point(const gs_mesh *m)
{
    const uint32_t *c = gs_mesh_faces(m) + 3 * (size_t)rng(gs_mesh_num_faces(m));
    double r1 = rng(1u << 30) / (double)(1u << 30), r2 = rng(1u << 30) / (double)(1u << 30);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    return gs_surface_point_make(c[0], c[1], c[2], 1 - r1 - r2, r1, r2);
}

/* Surface-point queries (gs_db_point_distance), timed like the vertex
 * queries, and point fields (gs_db_point_field). */
static void bench_points(const gs_db *db, const gs_mesh *m, uint32_t nv, double vertex_median)
{
    gs_surface_point *p = malloc(sizeof *p * 2 * N_POINT_PAIRS);
    double *t = malloc(sizeof *t * N_POINT_PAIRS), *out = malloc(sizeof *out * nv), sum = 0, tf = 0;
    for (uint32_t i = 0; i < 2 * N_POINT_PAIRS; ++i) p[i] = random_point(m);
    double t0 = timer_overhead();
    for (uint32_t i = 0; i < N_POINT_PAIRS; ++i) {
        double a = now();
        sum += gs_db_point_distance(db, &p[2 * i], &p[2 * i + 1]);
        t[i] = now() - a - t0;
    }
    qsort(t, N_POINT_PAIRS, sizeof *t, cmp_double);
    for (uint32_t k = 0; k < N_FIELDS; ++k) {
        double a = now();
        gs_db_point_field(db, &p[k], out, NULL);
        tf += now() - a;
        sum += out[k];
    }
    printf("surface points (%u random pairs of points of random faces, one thread):\n", N_POINT_PAIRS);
    printf("  median %.0f ns, p90 %.0f ns, p99 %.0f ns per point pair; vertex pairs above: median %.0f ns (x%.1f)\n",
           1e9 * t[N_POINT_PAIRS / 2], 1e9 * t[N_POINT_PAIRS / 10 * 9], 1e9 * t[N_POINT_PAIRS / 100 * 99],
           1e9 * vertex_median, t[N_POINT_PAIRS / 2] / vertex_median);
    printf("  field from a point (gs_db_point_field): %.3f ms (checksum %g)\n", 1e3 * tf / N_FIELDS, sum);
    free(p);
    free(t);
    free(out);
}

static void bench_fields(const gs_db *db, uint32_t nv)
{
    double *out = malloc(sizeof *out * nv), tf = 0, tq = 0, sum = 0;
    for (uint32_t k = 0; k < N_FIELDS; ++k) {
        uint32_t x = rng(nv);
        double a = now();
        gs_db_field(db, x, out, NULL);
        tf += now() - a;
        a = now();
        for (uint32_t y = 0; y < nv; ++y) sum += gs_db_distance(db, x, y);
        tq += now() - a;
    }
    printf("full field (%u vertices): %.3f ms with gs_db_field, %.3f ms through %u single queries (checksum %g)\n", nv,
           1e3 * tf / N_FIELDS, 1e3 * tq / N_FIELDS, nv, sum);
    free(out);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        printf("usage: %s DB.gsdb [MESH]\n"
               "make a database first, e.g.:\n"
               "  geosep build ../shared/meshes/bunny-5k.obj -o bunny-5k.gsdb\n"
               "  (or a generated mesh: geosep generate sphere:5 -o sphere.obj)\n"
               "MESH (the database's mesh) adds surface-point queries on its faces\n",
               argv[0]);
        return 0;
    }
    gs_db *db = NULL;
    gs_error err = {0};
    double t = now();
    if (gs_db_open(argv[1], &db, &err) != GS_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    t = now() - t;
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    printf("%s: %u vertices, %u nodes, %u leaves, %u curves, depth avg %.2f max %u\n", argv[1], info.n_vertices,
           info.n_nodes, info.n_leaves, info.n_curves, info.avg_depth, info.max_depth);
    printf("size %llu bytes, %.1f bytes/vertex, cost %.1f reals/vertex; open+validate %.3f ms\n",
           (unsigned long long)info.file_bytes, info.bytes_per_vertex, info.cost, 1e3 * t);
    double vertex_median = bench_pairs(db, info.n_vertices);
    bench_fields(db, info.n_vertices);
    if (argc > 2) {
        gs_mesh *m = NULL;
        if (gs_mesh_load(argv[2], GS_FORMAT_AUTO, &m, &err) != GS_OK) {
            fprintf(stderr, "%s\n", err.message);
            gs_db_free(db);
            return 1;
        }
        if (gs_mesh_num_vertices(m) != info.n_vertices)
            fprintf(stderr, "%s: %u vertices, the database has %u\n", argv[2], gs_mesh_num_vertices(m), info.n_vertices);
        else
            bench_points(db, m, info.n_vertices, vertex_median);
        gs_mesh_free(m);
    } else {
        printf("(pass the database's mesh to time surface-point queries too)\n");
    }
    gs_db_free(db);
    return 0;
}
