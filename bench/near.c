/* bench/near.c - what the near pairs (section 'near_pairs', issue 17) cost:
 * the section's bytes per vertex, and the query time with and without it,
 * measured alternately in one run (blocks of 50,000 single queries, one
 * thread, median of the individually timed queries; timer overhead
 * subtracted) on random pairs (nearly all far apart: one comparison) and
 * on near pairs (a vertex and one 1 to 3 edges away: the lookup). The two
 * databases must be built from the same mesh with the same options but
 * the near radius (geosep build MESH -o A; geosep build MESH -o B
 * --near-radius 0): their records are the same, so the difference is the
 * section's. Usage: bench_near WITH.gsdb WITHOUT.gsdb MESH */
#include "bench_util.h"
#include "geosep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BLOCK 50000u
#define ROUNDS 10u

static uint64_t rng_state = 0x853C49E6748FEA9Bull;
static uint32_t rng(uint32_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)((rng_state >> 11) % n);
}

/* Vertex adjacency (CSR) of the mesh's faces. */
static void adjacency(const gs_mesh *m, uint32_t **start, uint32_t **adj)
{
    uint32_t nv = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    const uint32_t *t = gs_mesh_faces(m);
    uint32_t *s = calloc((size_t)nv + 1, sizeof *s), *a = malloc(6 * (size_t)nf * sizeof *a);
    for (uint32_t f = 0; f < 3 * nf; ++f) s[t[f] + 1] += 2;
    for (uint32_t v = 0; v < nv; ++v) s[v + 1] += s[v];
    uint32_t *fill = malloc((size_t)nv * sizeof *fill);
    memcpy(fill, s, nv * sizeof *fill);
    for (uint32_t f = 0; f < nf; ++f)
        for (int i = 0; i < 3; ++i) {
            uint32_t v = t[3 * f + i];
            a[fill[v]++] = t[3 * f + (i + 1) % 3];
            a[fill[v]++] = t[3 * f + (i + 2) % 3];
        }
    free(fill);
    *start = s;
    *adj = a;
}

/* A vertex 1 to 3 edges from x (a random walk of 3 steps, not back to x). */
static uint32_t near_of(uint32_t x, const uint32_t *s, const uint32_t *a)
{
    uint32_t v = x;
    for (int k = 0; k < 3; ++k) {
        if (s[v + 1] == s[v]) break;
        uint32_t w = a[s[v] + rng(s[v + 1] - s[v])];
        if (w != x) v = w;
    }
    return v;
}

/* Median ns of single queries of pairs[0..n), each timed. */
static double median_ns(const gs_db *db, const uint32_t *pairs, uint32_t n, double *t, double t0, double *sum)
{
    for (uint32_t i = 0; i < n; ++i) {
        double a = now();
        *sum += gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        t[i] = now() - a - t0;
    }
    qsort(t, n, sizeof *t, cmp_double);
    return 1e9 * t[n / 2];
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s WITH.gsdb WITHOUT.gsdb MESH\n", argv[0]);
        return 2;
    }
    gs_error err = {0};
    gs_db *db[2] = {NULL, NULL};
    gs_mesh *m = NULL;
    if (gs_db_open(argv[1], &db[0], &err) || gs_db_open(argv[2], &db[1], &err) ||
        gs_mesh_load(argv[3], GS_FORMAT_AUTO, &m, &err)) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    gs_db_info in[2];
    gs_db_get_info(db[0], &in[0], NULL);
    gs_db_get_info(db[1], &in[1], NULL);
    uint32_t nv = in[0].n_vertices;
    if (in[1].n_vertices != nv || gs_mesh_num_vertices(m) != nv || in[1].n_near_pairs) {
        fprintf(stderr, "%s: the databases and the mesh must match, the second without near pairs\n", argv[0]);
        return 1;
    }
    printf("%s: %u vertices, %llu near pairs within %g, section %llu bytes = %.2f bytes/vertex of %.1f\n", argv[1],
           nv, (unsigned long long)in[0].n_near_pairs, in[0].near_radius, (unsigned long long)in[0].near_bytes,
           (double)in[0].near_bytes / nv, in[0].bytes_per_vertex);
    uint32_t *s, *a;
    adjacency(m, &s, &a);
    uint32_t *far = malloc(2 * sizeof *far * BLOCK), *near = malloc(2 * sizeof *near * BLOCK);
    double *t = malloc(sizeof *t * BLOCK), t0 = timer_overhead(), sum = 0;
    double med[2][2][ROUNDS]; /* [class][db][round] */
    uint64_t differ = 0;
    for (uint32_t r = 0; r < ROUNDS; ++r) {
        for (uint32_t i = 0; i < BLOCK; ++i) {
            far[2 * i] = rng(nv), far[2 * i + 1] = rng(nv);
            near[2 * i] = rng(nv), near[2 * i + 1] = near_of(near[2 * i], s, a);
            if (r == 0) differ += gs_db_distance(db[0], near[2 * i], near[2 * i + 1]) !=
                                  gs_db_distance(db[1], near[2 * i], near[2 * i + 1]);
        }
        for (int k = 0; k < 2; ++k) { /* alternately: with, without, in turn first */
            int d = (int)((r + k) & 1);
            med[0][d][r] = median_ns(db[d], far, BLOCK, t, t0, &sum);
            med[1][d][r] = median_ns(db[d], near, BLOCK, t, t0, &sum);
        }
    }
    const char *cls[2] = {"random pairs", "near pairs (1-3 edges)"};
    for (int c = 0; c < 2; ++c) {
        double x[ROUNDS], y[ROUNDS], q[ROUNDS];
        for (uint32_t r = 0; r < ROUNDS; ++r) x[r] = med[c][0][r], y[r] = med[c][1][r], q[r] = x[r] / y[r];
        qsort(x, ROUNDS, sizeof *x, cmp_double);
        qsort(y, ROUNDS, sizeof *y, cmp_double);
        qsort(q, ROUNDS, sizeof *q, cmp_double);
        printf("%-24s median ns with %.0f, without %.0f; ratio per round: median %.3f (range %.3f-%.3f)\n", cls[c],
               x[ROUNDS / 2], y[ROUNDS / 2], q[ROUNDS / 2], q[0], q[ROUNDS - 1]);
    }
    printf("near pairs answered from the section: %.2f%% of %u (checksum %g)\n", 100.0 * differ / BLOCK, BLOCK, sum);
    free(far), free(near), free(t), free(s), free(a);
    gs_db_free(db[0]);
    gs_db_free(db[1]);
    gs_mesh_free(m);
    return 0;
}
