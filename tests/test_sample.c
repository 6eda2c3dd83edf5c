/* test_sample.c - farthest-point sampling by the database's distances
 * (gs_db_farthest_point_sampling, src/query/sample.c) against a brute-force
 * greedy over every vertex's gs_db_field, on generated meshes: a grid (many
 * ties), two components (each gets a sample first), a grid with vertices
 * used by no face (never chosen); and every bad argument. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static gs_db *build(const gs_mesh *m, const char *what)
{
    gs_build_options o;
    gs_build_options_default(&o);
    o.vmax = 20; /* a real tree on these small meshes */
    o.threads = 1;
    gs_db *db = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_build(m, &o, &db, NULL, &e) == GS_OK, "%s: build: %s", what, e.message);
    return db;
}

/* The greedy done the obvious way: all n fields, the distance to the
 * nearest chosen sample recomputed for every candidate at every step. */
static void brute_force(const gs_db *db, uint32_t n, uint32_t k, uint32_t seed, uint32_t *out)
{
    double *F = malloc((size_t)n * n * sizeof *F);
    char *chosen = calloc(n, 1);
    for (uint32_t x = 0; x < n; ++x) {
        gs_error e = {0};
        if (gs_db_vertex_leaf(db, x) == GS_NONE) {
            chosen[x] = 1; /* never a candidate */
            continue;
        }
        CHECK(gs_db_field(db, x, F + (size_t)x * n, &e) == GS_OK);
    }
    out[0] = seed;
    chosen[seed] = 1;
    for (uint32_t i = 1; i < k; ++i) {
        uint32_t best = GS_NONE;
        double best_d = -1;
        for (uint32_t v = 0; v < n; ++v) {
            if (chosen[v]) continue;
            double d = INFINITY;
            for (uint32_t j = 0; j < i; ++j) d = fmin(d, F[(size_t)out[j] * n + v]);
            if (best == GS_NONE || d > best_d) best = v, best_d = d;
        }
        out[i] = best;
        chosen[best] = 1;
    }
    free(chosen);
    free(F);
}

static uint32_t n_referenced(const gs_db *db, uint32_t n)
{
    uint32_t c = 0;
    for (uint32_t v = 0; v < n; ++v) c += gs_db_vertex_leaf(db, v) != GS_NONE;
    return c;
}

/* Sampling equals the brute force for k = 1, a few, and every referenced
 * vertex, from the given seeds. */
static void compare(const gs_db *db, const char *what, const uint32_t *seeds, int n_seeds)
{
    gs_db_info info;
    CHECK(gs_db_get_info(db, &info, NULL) == GS_OK);
    uint32_t n = info.n_vertices, m = n_referenced(db, n);
    uint32_t *got = malloc((size_t)n * sizeof *got), *want = malloc((size_t)n * sizeof *want);
    for (int s = 0; s < n_seeds; ++s) {
        brute_force(db, n, m, seeds[s], want);
        uint32_t ks[] = {1, 2, 7, m / 3, m};
        for (size_t t = 0; t < sizeof ks / sizeof *ks; ++t) {
            uint32_t k = ks[t];
            gs_error e = {0};
            memset(got, 0xff, (size_t)n * sizeof *got);
            CHECK_MSG(gs_db_farthest_point_sampling(db, k, seeds[s], got, &e) == GS_OK, "%s: %s", what, e.message);
            uint32_t first_bad = GS_NONE;
            for (uint32_t i = 0; i < k && first_bad == GS_NONE; ++i)
                if (got[i] != want[i]) first_bad = i;
            CHECK_MSG(first_bad == GS_NONE, "%s seed %u k %u: sample %u is %u, brute force %u", what, seeds[s], k,
                      first_bad, first_bad == GS_NONE ? 0 : got[first_bad], first_bad == GS_NONE ? 0 : want[first_bad]);
            CHECK_MSG(k == n || got[k] == GS_NONE, "%s: wrote past k", what);
        }
        /* all m: a permutation of the referenced vertices */
        char *seen = calloc(n, 1);
        int ok = 1;
        for (uint32_t i = 0; i < m; ++i) {
            if (got[i] >= n || seen[got[i]] || gs_db_vertex_leaf(db, got[i]) == GS_NONE) ok = 0;
            else seen[got[i]] = 1;
        }
        CHECK_MSG(ok, "%s seed %u: k = all referenced vertices is not a permutation of them", what, seeds[s]);
        free(seen);
    }
    free(got);
    free(want);
}

static void bad_arguments(const gs_db *db, uint32_t unreferenced)
{
    gs_db_info info;
    CHECK(gs_db_get_info(db, &info, NULL) == GS_OK);
    uint32_t n = info.n_vertices, m = n_referenced(db, n);
    uint32_t *out = malloc((size_t)(n + 1) * sizeof *out);
    gs_error e = {0};
    CHECK(gs_db_farthest_point_sampling(db, m + 1, 1, out, &e) == GS_EARG);
    CHECK_MSG(strstr(e.message, "exceeds"), "%s", e.message);
    CHECK(gs_db_farthest_point_sampling(db, 2, n, out, &e) == GS_EARG);
    CHECK_MSG(strstr(e.message, "seed vertex"), "%s", e.message);
    if (unreferenced != GS_NONE) {
        CHECK(gs_db_farthest_point_sampling(db, 2, unreferenced, out, &e) == GS_EARG);
        CHECK_MSG(strstr(e.message, "used by no face"), "%s", e.message);
    }
    CHECK(gs_db_farthest_point_sampling(NULL, 2, 1, out, &e) == GS_EARG);
    CHECK(gs_db_farthest_point_sampling(db, 2, 1, NULL, &e) == GS_EARG);
    CHECK(gs_db_farthest_point_sampling(db, 0, 1, NULL, &e) == GS_OK); /* nothing to write */
    free(out);
}

int main(void)
{
    /* a grid: the corners first, many ties (to the lowest id) */
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK(gs_mesh_generate("grid:12,12", &m, &e) == GS_OK);
    gs_db *db = build(m, "grid:12,12");
    if (db) {
        uint32_t seeds[] = {0, 77};
        compare(db, "grid:12,12", seeds, 2);
        uint32_t out[4];
        CHECK(gs_db_farthest_point_sampling(db, 4, 0, out, &e) == GS_OK);
        /* from corner 0, the opposite corner (143), then the other two */
        CHECK_MSG(out[1] == 143 && ((out[2] == 11 && out[3] == 132) || (out[2] == 132 && out[3] == 11)),
                  "grid: %u %u %u", out[1], out[2], out[3]);
        bad_arguments(db, GS_NONE);
    }
    gs_db_free(db);
    gs_mesh_free(m);

    /* two components: the second sample is in the other component */
    CHECK(gs_mesh_generate("two:6", &m, &e) == GS_OK);
    db = build(m, "two:6");
    if (db) {
        gs_db_info info;
        gs_db_get_info(db, &info, NULL);
        uint32_t seeds[] = {0, info.n_vertices - 1};
        compare(db, "two:6", seeds, 2);
        for (int s = 0; s < 2; ++s) {
            uint32_t out[2];
            CHECK(gs_db_farthest_point_sampling(db, 2, seeds[s], out, &e) == GS_OK);
            CHECK_MSG(isinf(gs_db_distance(db, out[0], out[1])), "two: samples %u %u in one component", out[0], out[1]);
        }
    }
    gs_db_free(db);
    gs_mesh_free(m);

    /* a grid with vertices used by no face: at id 0, in the middle, at the end */
    gs_mesh *g = NULL;
    CHECK(gs_mesh_generate("grid:9,9", &g, &e) == GS_OK);
    if (g) {
        uint32_t nv = gs_mesh_num_vertices(g), nf = gs_mesh_num_faces(g), extra[] = {0, 40, nv + 2};
        uint32_t n = nv + 3;
        double *xyz = malloc((size_t)3 * n * sizeof *xyz);
        uint32_t *tri = malloc((size_t)3 * nf * sizeof *tri), *new_id = malloc((size_t)nv * sizeof *new_id);
        for (uint32_t v = 0, id = 0; id < n; ++id) { /* ids 0, 40, nv+2 unused; the grid's in order */
            if (id == extra[0] || id == extra[1] || id == extra[2]) {
                xyz[3 * id] = 5.0 + id, xyz[3 * id + 1] = 5.0, xyz[3 * id + 2] = 0; /* far away */
                continue;
            }
            memcpy(xyz + 3 * id, gs_mesh_positions(g) + 3 * v, 3 * sizeof *xyz);
            new_id[v++] = id;
        }
        for (uint32_t i = 0; i < 3 * nf; ++i) tri[i] = new_id[gs_mesh_faces(g)[i]];
        CHECK_MSG(gs_mesh_create(xyz, n, tri, nf, &m, &e) == GS_OK, "%s", e.message);
        db = m ? build(m, "grid with unreferenced vertices") : NULL;
        if (db) {
            uint32_t seeds[] = {1, 41};
            compare(db, "grid with unreferenced vertices", seeds, 2);
            bad_arguments(db, 40);
            CHECK(gs_db_farthest_point_sampling(db, 1, 0, new_id, &e) == GS_EARG);
        }
        gs_db_free(db);
        gs_mesh_free(m);
        free(xyz);
        free(tri);
        free(new_id);
    }
    gs_mesh_free(g);
    return gs_test_finish("test_sample");
}
