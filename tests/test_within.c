/* test_within.c - neighbourhoods and fast fields (src/query/within.c,
 * radius.c, field.c) on generated meshes and the hand-made fixture:
 *  - gs_db_field equals gs_db_distance bit for bit from every source
 *    (loops, holes, two components, vertices used by no face);
 *  - gs_db_within equals the thresholded field exactly (the same vertices,
 *    the same distances bit for bit, sorted by distance then id) for radii
 *    at quantiles of the field, at field values themselves (ties at the
 *    boundary), 0 and +inf (every vertex at a finite distance);
 *  - gs_db_nearest equals a brute-force selection (repeated and unreachable
 *    candidates, k beyond the candidates);
 *  - gs_db_radius_matrix's rows equal gs_db_within's by id, the same for 1
 *    and 2 threads;
 *  - threads racing for the first call (which computes the bounds);
 *  - every bad argument. */
#include "check.h"
#include "db_fixture.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static gs_db *build(const gs_mesh *m, const char *what, uint32_t vmax)
{
    gs_build_options o;
    gs_build_options_default(&o);
    o.vmax = vmax; /* a real tree on these small meshes */
    o.threads = 1;
    gs_db *db = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_build(m, &o, &db, NULL, &e) == GS_OK, "%s: build: %s", what, e.message);
    return db;
}

static int same(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* within(x, r) against the field f of x. Returns the number of entries. */
static size_t check_within(const gs_db *db, const char *what, uint32_t n, uint32_t x, const double *f, double r)
{
    gs_neighbors *nb = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_within(db, x, r, &nb, &e) == GS_OK, "%s: within(%u, %g): %s", what, x, r, e.message);
    if (!nb) return 0;
    size_t want = 0;
    for (uint32_t y = 0; y < n; ++y) want += f[y] <= r && f[y] < INFINITY; /* r = inf: the connected ones */
    CHECK_MSG(nb->n == want, "%s: within(%u, %.17g) has %zu vertices, the thresholded field %zu", what, x, r, nb->n,
              want);
    int bad = 0;
    for (size_t i = 0; i < nb->n && !bad; ++i) {
        uint32_t y = nb->ids[i];
        if (y >= n || !same(nb->dist[i], f[y]) || !(f[y] <= r)) bad = 1;
        if (i && (nb->dist[i] < nb->dist[i - 1] || (nb->dist[i] == nb->dist[i - 1] && y <= nb->ids[i - 1]))) bad = 2;
        if (bad)
            CHECK_MSG(0, "%s: within(%u, %g) entry %zu (vertex %u, %.17g): %s", what, x, r, i, y, nb->dist[i],
                      bad == 1 ? "not the field's" : "out of order");
    }
    size_t got = nb->n;
    gs_neighbors_free(nb);
    return got;
}

/* Brute-force k nearest of candidates (distinct, ties to lower id,
 * NaN as +inf) against gs_db_nearest. */
typedef struct pair {
    double d;
    uint32_t id;
} pair;

static int by_pair(const void *pa, const void *pb)
{
    const pair *a = pa, *b = pb;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

static void check_nearest(const gs_db *db, const char *what, uint32_t x, const double *f, const uint32_t *cand,
                          size_t nc, size_t k)
{
    pair *p = malloc((nc + 1) * sizeof *p);
    size_t m = 0;
    for (size_t i = 0; i < nc; ++i) {
        int dup = 0;
        for (size_t j = 0; j < i; ++j) dup |= cand[j] == cand[i];
        if (dup) continue;
        p[m].id = cand[i], p[m].d = f[cand[i]] == f[cand[i]] ? f[cand[i]] : INFINITY;
        m++;
    }
    qsort(p, m, sizeof *p, by_pair);
    size_t want = k < m ? k : m;
    gs_neighbors *nb = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_nearest(db, x, cand, nc, k, &nb, &e) == GS_OK, "%s: nearest: %s", what, e.message);
    if (nb) {
        CHECK_MSG(nb->n == want, "%s: nearest(%u, %zu candidates, k %zu): %zu entries, want %zu", what, x, nc, k,
                  nb->n, want);
        int bad = 0;
        for (size_t i = 0; i < nb->n && i < want; ++i) bad += nb->ids[i] != p[i].id || !same(nb->dist[i], p[i].d);
        CHECK_MSG(!bad, "%s: nearest(%u, k %zu): %d entries differ from the brute force", what, x, k, bad);
    }
    gs_neighbors_free(nb);
    free(p);
}

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint32_t rng(uint32_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)((rng_state >> 11) % n);
}

/* Everything on one database, from `n_src` sources (every vertex if 0). */
static void check_db(const gs_db *db, const char *what, uint32_t n_src)
{
    gs_db_info info;
    CHECK(gs_db_get_info(db, &info, NULL) == GS_OK);
    const uint32_t n = info.n_vertices;
    double *f = malloc((size_t)n * sizeof *f), *sorted = malloc((size_t)n * sizeof *sorted);
    uint32_t *cand = malloc((size_t)(n + 8) * sizeof *cand);
    uint32_t *srcs = malloc((size_t)n * sizeof *srcs), ns = 0;
    size_t total = 0, n_field_bad = 0;
    for (uint32_t t = 0; t < (n_src ? n_src : n); ++t) {
        uint32_t x = n_src ? rng(n) : t;
        srcs[ns++] = x;
        gs_error e = {0};
        CHECK(gs_db_field(db, x, f, &e) == GS_OK);
        for (uint32_t y = 0; y < n; ++y) n_field_bad += !same(f[y], gs_db_distance(db, x, y));
        /* radii: quantiles of the finite distances, field values (ties), 0, inf */
        uint32_t nf = 0;
        for (uint32_t y = 0; y < n; ++y)
            if (isfinite(f[y])) sorted[nf++] = f[y];
        qsort(sorted, nf, sizeof *sorted, cmp_double);
        double radii[10] = {0.0, INFINITY, sorted[nf / 100], sorted[nf / 10], sorted[nf / 3], sorted[nf - 1],
                            0.5 * (sorted[nf / 20] + sorted[nf / 20 + (nf > 1)]),
                            nextafter(sorted[nf / 5], 0.0), sorted[nf / 5], nextafter(sorted[nf / 5], INFINITY)};
        for (int i = 0; i < 10; ++i) total += check_within(db, what, n, x, f, radii[i]);
        /* nearest: random candidates with repeats, all vertices, none */
        size_t nc = 1 + rng(n < 40 ? n : 40);
        for (size_t i = 0; i < nc; ++i) cand[i] = rng(n);
        cand[nc] = cand[0], cand[nc + 1] = x; /* a repeat, x itself */
        size_t ks[] = {1, 3, nc, nc + 5};
        for (int i = 0; i < 4; ++i) check_nearest(db, what, x, f, cand, nc + 2, ks[i]);
        for (uint32_t y = 0; y < n; ++y) cand[y] = n - 1 - y;
        check_nearest(db, what, x, f, cand, n, 10);
        check_nearest(db, what, x, f, cand, 0, 10);
    }
    CHECK_MSG(n_field_bad == 0, "%s: %zu field values differ from gs_db_distance", what, n_field_bad);
    CHECK_MSG(total > 0, "%s: every within was empty", what);
    /* radius matrix: rows = within by id; 1 and 2 threads alike */
    double r = sorted[n / 10 < 1 ? 0 : n / 10 - 1];
    gs_csr *m1 = NULL, *m2 = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_radius_matrix(db, srcs, ns, r, 1, &m1, &e) == GS_OK, "%s: %s", what, e.message);
    CHECK_MSG(gs_db_radius_matrix(db, srcs, ns, r, 2, &m2, &e) == GS_OK, "%s: %s", what, e.message);
    if (m1 && m2) {
        CHECK(m1->n_rows == ns && m1->n_cols == n && m1->indptr[0] == 0 && m1->indptr[ns] == m1->nnz);
        CHECK(m2->nnz == m1->nnz && !memcmp(m1->indptr, m2->indptr, (ns + 1) * sizeof *m1->indptr) &&
              !memcmp(m1->indices, m2->indices, m1->nnz * sizeof *m1->indices) &&
              !memcmp(m1->data, m2->data, m1->nnz * sizeof *m1->data));
        int bad = 0;
        for (uint32_t i = 0; i < ns; ++i) {
            CHECK(gs_db_field(db, srcs[i], f, NULL) == GS_OK);
            uint64_t a = m1->indptr[i], b = m1->indptr[i + 1], want = 0;
            for (uint32_t y = 0; y < n; ++y) want += f[y] <= r;
            bad += b - a != want;
            for (uint64_t j = a; j < b; ++j)
                bad += !same(m1->data[j], f[m1->indices[j]]) || !(f[m1->indices[j]] <= r) ||
                       (j > a && m1->indices[j] <= m1->indices[j - 1]);
        }
        CHECK_MSG(!bad, "%s: radius matrix: %d rows or entries differ from the thresholded fields", what, bad);
    }
    gs_csr_free(m1);
    gs_csr_free(m2);
    free(f);
    free(sorted);
    free(cand);
    free(srcs);
}

static void bad_arguments(const gs_db *db, uint32_t n)
{
    gs_neighbors *nb = (gs_neighbors *)1;
    gs_csr *m = (gs_csr *)1;
    gs_error e = {0};
    uint32_t c[2] = {0, 1}, bad[2] = {0, n};
    CHECK(gs_db_within(db, n, 1.0, &nb, &e) == GS_EARG && nb == NULL && strstr(e.message, "n_vertices"));
    CHECK(gs_db_within(db, 0, -1.0, &nb, &e) == GS_EARG && strstr(e.message, "radius"));
    CHECK(gs_db_within(db, 0, NAN, &nb, &e) == GS_EARG && strstr(e.message, "radius"));
    CHECK(gs_db_within(NULL, 0, 1.0, &nb, &e) == GS_EARG);
    CHECK(gs_db_within(db, 0, 1.0, NULL, &e) == GS_EARG);
    CHECK(gs_db_nearest(db, n, c, 2, 1, &nb, &e) == GS_EARG && nb == NULL);
    CHECK(gs_db_nearest(db, 0, bad, 2, 1, &nb, &e) == GS_EARG && strstr(e.message, "candidate 1"));
    CHECK(gs_db_nearest(db, 0, NULL, 2, 1, &nb, &e) == GS_EARG);
    CHECK(gs_db_nearest(db, 0, NULL, 0, 1, &nb, &e) == GS_OK && nb && nb->n == 0);
    gs_neighbors_free(nb);
    CHECK(gs_db_nearest(db, 0, c, 2, 0, &nb, &e) == GS_OK && nb && nb->n == 0);
    gs_neighbors_free(nb);
    CHECK(gs_db_radius_matrix(db, bad, 2, 1.0, 1, &m, &e) == GS_EARG && m == NULL && strstr(e.message, "source 1"));
    CHECK(gs_db_radius_matrix(db, c, 2, -0.5, 1, &m, &e) == GS_EARG && strstr(e.message, "radius"));
    CHECK(gs_db_radius_matrix(db, NULL, 2, 1.0, 1, &m, &e) == GS_EARG);
    /* a thread count OpenMP cannot start (a negative count cast to unsigned
     * made libgomp abort the process) */
    CHECK(gs_db_radius_matrix(db, c, 2, 1.0, UINT32_MAX, &m, &e) == GS_EARG && m == NULL &&
          strstr(e.message, "threads"));
    CHECK(gs_db_radius_matrix(db, c, 2, 1.0, GS_MAX_THREADS + 1, &m, &e) == GS_EARG && strstr(e.message, "threads"));
    CHECK(gs_db_radius_matrix(db, c, 2, 1.0, GS_MAX_THREADS, &m, &e) == GS_OK && m && m->n_rows == 2);
    gs_csr_free(m);
    CHECK(gs_db_radius_matrix(db, NULL, 0, 1.0, 1, &m, &e) == GS_OK && m && m->n_rows == 0 && m->nnz == 0 &&
          m->indptr[0] == 0);
    gs_csr_free(m);
    gs_neighbors_free(NULL);
    gs_csr_free(NULL);
}

static void on_mesh(const char *spec, uint32_t vmax, uint32_t n_src)
{
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_mesh_generate(spec, &m, &e) == GS_OK, "%s: %s", spec, e.message);
    gs_db *db = m ? build(m, spec, vmax) : NULL;
    if (db) {
        check_db(db, spec, n_src);
        bad_arguments(db, gs_mesh_num_vertices(m));
    }
    gs_db_free(db);
    gs_mesh_free(m);
}

/* A grid with vertices used by no face (ids 0 and 40): never in a
 * neighbourhood but their own; x = 0 gives only itself. */
static void unreferenced(void)
{
    gs_mesh *g = NULL, *m = NULL;
    gs_error e = {0};
    CHECK(gs_mesh_generate("grid:9,9", &g, &e) == GS_OK);
    if (!g) return;
    uint32_t nv = gs_mesh_num_vertices(g), nf = gs_mesh_num_faces(g), n = nv + 2;
    double *xyz = malloc((size_t)3 * n * sizeof *xyz);
    uint32_t *tri = malloc((size_t)3 * nf * sizeof *tri), *new_id = malloc((size_t)nv * sizeof *new_id);
    for (uint32_t v = 0, id = 0; id < n; ++id) {
        if (id == 0 || id == 40) {
            xyz[3 * id] = 0.5, xyz[3 * id + 1] = 0.5, xyz[3 * id + 2] = 0; /* on top of the grid */
            continue;
        }
        memcpy(xyz + 3 * id, gs_mesh_positions(g) + 3 * v, 3 * sizeof *xyz);
        new_id[v++] = id;
    }
    for (uint32_t i = 0; i < 3 * nf; ++i) tri[i] = new_id[gs_mesh_faces(g)[i]];
    CHECK_MSG(gs_mesh_create(xyz, n, tri, nf, &m, &e) == GS_OK, "%s", e.message);
    gs_db *db = m ? build(m, "grid with unreferenced vertices", 12) : NULL;
    if (db) {
        check_db(db, "grid with unreferenced vertices", 0);
        gs_neighbors *nb = NULL;
        CHECK(gs_db_within(db, 0, INFINITY, &nb, &e) == GS_OK && nb && nb->n == 1 && nb->ids[0] == 0 &&
              nb->dist[0] == 0.0);
        gs_neighbors_free(nb);
    }
    gs_db_free(db);
    gs_mesh_free(m);
    gs_mesh_free(g);
    free(xyz);
    free(tri);
    free(new_id);
}

/* Threads racing for the first call on a fresh database (each may compute
 * the bounds; one is kept): every answer equals the serial one. */
static void first_call_race(void)
{
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK(gs_mesh_generate("sphere:3", &m, &e) == GS_OK);
    gs_db *db = m ? build(m, "sphere:3", 24) : NULL, *ref = m ? build(m, "sphere:3", 24) : NULL;
    if (db && ref) {
        enum { T = 8 };
        size_t bad = 0;
#pragma omp parallel for num_threads(4) schedule(static, 1) reduction(+ : bad)
        for (int t = 0; t < T; ++t) {
            gs_neighbors *a = NULL, *b = NULL;
            uint32_t x = (uint32_t)(37 * t);
            if (gs_db_within(db, x, 0.5, &a, NULL) != GS_OK) bad++;
#pragma omp critical(ref_db)
            if (gs_db_within(ref, x, 0.5, &b, NULL) != GS_OK) bad++;
            if (a && b)
                bad += a->n != b->n || memcmp(a->ids, b->ids, a->n * sizeof *a->ids) ||
                       memcmp(a->dist, b->dist, a->n * sizeof *a->dist);
            gs_neighbors_free(a);
            gs_neighbors_free(b);
        }
        CHECK_MSG(bad == 0, "first calls from 4 threads: %zu answers differ", bad);
    }
    gs_db_free(db);
    gs_db_free(ref);
    gs_mesh_free(m);
}

int main(void)
{
    /* the hand-made fixture: curves unreachable from some vertices, a vertex
     * used by no face, with and without leaf tables */
    for (int t = 0; t < 2; ++t) {
        fixture fx;
        gs_db *db = fixture_db(&fx, t);
        if (db) check_db(db, t ? "fixture with leaf tables" : "fixture", 0);
        gs_db_free(db);
    }
    on_mesh("grid:14,14", 12, 0);   /* every source; many ties */
    on_mesh("torus:30,12", 16, 0);  /* loops */
    on_mesh("plate:700", 20, 60);   /* holes */
    on_mesh("two:6", 10, 0);        /* two components: +inf beyond */
    on_mesh("sphere:3", 24, 40);
    unreferenced();
    first_call_race();
    return gs__test_finish("test_within");
}
