/* test_fields.c - a database's fields (gs_db_field: one query source for
 * every target, src/query/field.c) equal its single queries
 * (gs_db_distance) bit for bit, as do gs_db_field_threads's on 2 and 3
 * threads (every third source), and gs_db_within equals the thresholded
 * field, whatever method built the database (exact, graph, fast marching,
 * heat, DGG: their functions differ in degree, sharp dips and zero sets):
 * on generated meshes (loops, holes, two components) from every source,
 * and on ../shared's spot (every method, 150 sources; skipped under
 * GEOSEP_QUICK=1 and without ../shared). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const gs_method methods[] = {GS_METHOD_EXACT, GS_METHOD_GRAPH, GS_METHOD_FMM, GS_METHOD_HEAT, GS_METHOD_DGG};
#define N_METHODS (sizeof methods / sizeof methods[0])

static gs_db *build(const gs_mesh *m, gs_method method, uint32_t vmax, const char *what)
{
    gs_build_options o;
    gs_build_options_default(&o);
    o.method = method;
    if (vmax) o.vmax = vmax; /* a real tree on the small meshes */
    o.threads = 2;
    gs_db *db = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_db_build(m, &o, &db, NULL, &e) == GS_OK, "%s (%s): build: %s", what, gs_method_name(method),
              e.message);
    return db;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Fields from every step-th vertex against the single queries; within at
 * the radius holding a twentieth of the finite distances against the
 * thresholded field, for every fifth of those sources. */
static void check(const gs_db *db, const char *what, gs_method method, uint32_t step)
{
    gs_db_info info;
    CHECK(gs_db_get_info(db, &info, NULL) == GS_OK);
    const uint32_t n = info.n_vertices;
    double *f = malloc((size_t)n * sizeof *f), *s = malloc((size_t)n * sizeof *s);
    uint64_t pairs = 0, differ = 0, finite = 0, within_bad = 0, within_n = 0, threads_differ = 0;
    for (uint32_t x = 0; x < n && f && s; x += step) {
        gs_error e = {0};
        CHECK_MSG(gs_db_field(db, x, f, &e) == GS_OK, "%s: field %u: %s", what, x, e.message);
        for (uint32_t y = 0; y < n; ++y) {
            double d = gs_db_distance(db, x, y);
            if (memcmp(&d, &f[y], sizeof d) && differ++ < 5)
                fprintf(stderr, "%s (%s): d(%u,%u) = %.17g, field %.17g\n", what, gs_method_name(method), x, y, d,
                        f[y]);
            finite += isfinite(d) && d > 0;
            pairs++;
        }
        if ((x / step) % 3 == 0) { /* the threaded field: the same values for 2 and 3 threads */
            for (uint32_t th = 2; th <= 3; ++th) {
                CHECK_MSG(gs_db_field_threads(db, x, s, th, &e) == GS_OK, "%s: field %u, %u threads: %s", what, x,
                          th, e.message);
                for (uint32_t y = 0; y < n; ++y) threads_differ += memcmp(&s[y], &f[y], sizeof *s) != 0;
            }
        }
        if ((x / step) % 5) continue;
        uint32_t m = 0;
        for (uint32_t y = 0; y < n; ++y)
            if (isfinite(f[y])) s[m++] = f[y];
        qsort(s, m, sizeof *s, cmp_double);
        double r = s[m / 20];
        gs_neighbors *nb = NULL;
        CHECK(gs_db_within(db, x, r, &nb, &e) == GS_OK);
        size_t want = 0;
        for (uint32_t y = 0; y < n; ++y) want += f[y] <= r;
        within_bad += !nb || nb->n != want;
        for (size_t i = 0; nb && i < nb->n; ++i)
            within_bad += nb->ids[i] >= n || memcmp(&nb->dist[i], &f[nb->ids[i]], sizeof(double)) != 0;
        within_n += want;
        gs_neighbors_free(nb);
    }
    CHECK_MSG(differ == 0, "%s (%s): %llu of %llu field values differ from gs_db_distance", what,
              gs_method_name(method), (unsigned long long)differ, (unsigned long long)pairs);
    {
        gs_error e = {0};
        CHECK(gs_db_field_threads(db, n, f, 2, &e) == GS_EARG && strstr(e.message, "n_vertices"));
        CHECK(gs_db_field_threads(db, 0, NULL, 2, &e) == GS_EARG && strstr(e.message, "NULL"));
        CHECK(gs_db_field_threads(NULL, 0, f, 2, &e) == GS_EARG);
        CHECK(gs_db_field_threads(db, 0, f, UINT32_MAX, &e) == GS_EARG && strstr(e.message, "threads"));
        CHECK(gs_db_field_threads(db, 0, f, GS_MAX_THREADS + 1, &e) == GS_EARG && strstr(e.message, "threads"));
    }
    CHECK_MSG(threads_differ == 0, "%s (%s): %llu values of gs_db_field_threads differ from gs_db_field", what,
              gs_method_name(method), (unsigned long long)threads_differ);
    CHECK_MSG(finite * 3 > pairs, "%s (%s): too few finite distances (%llu of %llu)", what, gs_method_name(method),
              (unsigned long long)finite, (unsigned long long)pairs);
    CHECK_MSG(within_bad == 0 && within_n > 0, "%s (%s): gs_db_within differs from the thresholded field (%llu)",
              what, gs_method_name(method), (unsigned long long)within_bad);
    printf("%s (%s): %llu field values equal to single queries, %llu within answers\n", what, gs_method_name(method),
           (unsigned long long)pairs, (unsigned long long)within_n);
    free(f);
    free(s);
}

static void generated(const char *spec, uint32_t vmax)
{
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_mesh_generate(spec, &m, &e) == GS_OK, "%s: %s", spec, e.message);
    for (size_t i = 0; m && i < N_METHODS; ++i) {
        gs_db *db = build(m, methods[i], vmax, spec);
        if (db) check(db, spec, methods[i], 1);
        gs_db_free(db);
    }
    gs_mesh_free(m);
}

static void shared(const char *name)
{
    char rel[256];
    snprintf(rel, sizeof rel, "meshes/%s.obj", name);
    const char *p = gs__test_shared_path(rel);
    if (!p) {
        printf("%s: skipped (not in the shared data)\n", name);
        return;
    }
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_mesh_load(p, GS_FORMAT_AUTO, &m, &e) == GS_OK, "%s: %s", name, e.message);
    for (size_t i = 0; m && i < N_METHODS; ++i) {
        gs_db *db = build(m, methods[i], 0, name);
        if (db) check(db, name, methods[i], gs_mesh_num_vertices(m) / 150 + 1);
        gs_db_free(db);
    }
    gs_mesh_free(m);
}

int main(void)
{
    generated("torus:24,10", 16); /* loops */
    generated("plate:500", 20);   /* paths, holes */
    generated("two:6", 10);       /* two components: +inf between them */
    generated("sphere:3", 24);
    const char *q = getenv("GEOSEP_QUICK");
    if (q && !strcmp(q, "1")) {
        printf("shared meshes skipped (GEOSEP_QUICK)\n");
        return gs__test_finish("test_fields");
    }
    shared("spot");
    return gs__test_finish("test_fields");
}
