/* test_threads.c - one database queried from several threads at once: every
 * kind of query (gs_db_distance, gs_db_distances batches, gs_db_field,
 * gs_db_point_distance, gs_db_point_distances, gs_db_point_field,
 * gs_db_farthest_point_sampling) answered
 * by each thread, in its own order, must equal bit for bit the answers
 * computed by one thread beforehand. Run on a database built in memory and
 * on the same database saved and opened again (memory-mapped) and opened
 * from memory. Public API only. The test command builds and runs it under
 * ThreadSanitizer (GEOSEP_SANITIZE_THREAD, tools/test.sh), where a data
 * race fails it even when the answers agree; its ctest entry sets
 * OMP_NUM_THREADS=1 (the databases are built with one thread and open's
 * OpenMP loop runs on one: the uninstrumented libgomp's barriers would be
 * reported as races; the threads under test are this test's pthreads). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define N_THREADS 4
#define N_PAIRS 1500
#define N_SOURCES 6
#define N_POINT_PAIRS 400
#define N_POINT_FIELDS 3
#define BATCH 64
#define N_SAMPLES 6

typedef struct work {
    const gs_db *db;
    uint32_t n;
    uint32_t pairs[2 * N_PAIRS];
    double want_pairs[N_PAIRS];
    uint32_t sources[N_SOURCES];
    double *want_fields; /* N_SOURCES * n */
    gs_surface_point points[2 * N_POINT_PAIRS];
    double want_points[N_POINT_PAIRS];
    double *want_point_fields; /* N_POINT_FIELDS * n */
    uint32_t want_samples[N_SAMPLES]; /* farthest-point sampling from sources[0] */
} work;

typedef struct thread_arg {
    const work *w;
    uint32_t id;
    uint64_t checked, wrong, failed;
} thread_arg;

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static uint32_t irand(uint32_t n)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (uint32_t)((rng >> 11) % n);
}

static int same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static void *run(void *p)
{
    thread_arg *a = p;
    const work *w = a->w;
    const uint32_t n = w->n, t = a->id;
    double *field = malloc((size_t)n * sizeof *field);
    if (!field) {
        a->failed++;
        return NULL;
    }
    gs_error err;
    for (int round = 0; round < 2; ++round) {
        /* single pairs, each thread starting elsewhere and some backwards */
        for (uint32_t k = 0; k < N_PAIRS; ++k) {
            uint32_t i = (t & 1) ? N_PAIRS - 1 - (k + 97 * t) % N_PAIRS : (k + 97 * t) % N_PAIRS;
            a->wrong += !same(gs_db_distance(w->db, w->pairs[2 * i], w->pairs[2 * i + 1]), w->want_pairs[i]);
            a->checked++;
        }
        /* batches */
        for (uint32_t b = 0; b + BATCH <= N_PAIRS; b += BATCH) {
            uint32_t at = (b + BATCH * t) % (N_PAIRS - BATCH + 1);
            double out[BATCH];
            if (gs_db_distances(w->db, w->pairs + 2 * at, BATCH, out, &err) != GS_OK) {
                a->failed++;
                continue;
            }
            for (uint32_t i = 0; i < BATCH; ++i) a->wrong += !same(out[i], w->want_pairs[at + i]);
            a->checked += BATCH;
        }
        /* fields */
        for (uint32_t k = 0; k < N_SOURCES; ++k) {
            uint32_t s = (k + t) % N_SOURCES;
            if (gs_db_field(w->db, w->sources[s], field, &err) != GS_OK) {
                a->failed++;
                continue;
            }
            a->wrong += memcmp(field, w->want_fields + (size_t)s * n, (size_t)n * sizeof *field) != 0;
            a->checked++;
        }
        /* farthest-point sampling (fields folded into its own work arrays) */
        uint32_t samples[N_SAMPLES];
        if (gs_db_farthest_point_sampling(w->db, N_SAMPLES, w->sources[0], samples, &err) != GS_OK)
            a->failed++;
        else
            a->wrong += memcmp(samples, w->want_samples, sizeof samples) != 0, a->checked++;
        /* surface points: single, batch, fields */
        for (uint32_t k = 0; k < N_POINT_PAIRS; ++k) {
            uint32_t i = (k + 31 * t) % N_POINT_PAIRS;
            double d = gs_db_point_distance(w->db, &w->points[2 * i], &w->points[2 * i + 1]);
            a->wrong += !same(d, w->want_points[i]);
            a->checked++;
        }
        double out[N_POINT_PAIRS];
        if (gs_db_point_distances(w->db, w->points, N_POINT_PAIRS, out, &err) != GS_OK)
            a->failed++;
        else
            for (uint32_t i = 0; i < N_POINT_PAIRS; ++i) a->wrong += !same(out[i], w->want_points[i]), a->checked++;
        for (uint32_t k = 0; k < N_POINT_FIELDS; ++k) {
            uint32_t s = (k + t) % N_POINT_FIELDS;
            if (gs_db_point_field(w->db, &w->points[2 * s], field, &err) != GS_OK) {
                a->failed++;
                continue;
            }
            a->wrong += memcmp(field, w->want_point_fields + (size_t)s * n, (size_t)n * sizeof *field) != 0;
            a->checked++;
        }
    }
    free(field);
    return NULL;
}

/* The answers of one thread, then N_THREADS threads at once. */
static void check_db(const gs_db *db, const gs_mesh *m, const char *what)
{
    work *w = calloc(1, sizeof *w);
    CHECK(w != NULL);
    if (!w) return;
    const uint32_t n = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    w->db = db;
    w->n = n;
    w->want_fields = malloc((size_t)N_SOURCES * n * sizeof(double));
    w->want_point_fields = malloc((size_t)N_POINT_FIELDS * n * sizeof(double));
    CHECK(w->want_fields && w->want_point_fields);
    gs_error err = {0};
    for (uint32_t i = 0; i < 2 * N_PAIRS; ++i) w->pairs[i] = irand(n);
    for (uint32_t i = 0; i < N_PAIRS; ++i) w->want_pairs[i] = gs_db_distance(db, w->pairs[2 * i], w->pairs[2 * i + 1]);
    for (uint32_t s = 0; s < N_SOURCES; ++s) {
        w->sources[s] = irand(n);
        CHECK(gs_db_field(db, w->sources[s], w->want_fields + (size_t)s * n, &err) == GS_OK);
    }
    CHECK(gs_db_farthest_point_sampling(db, N_SAMPLES, w->sources[0], w->want_samples, &err) == GS_OK);
    for (uint32_t i = 0; i < 2 * N_POINT_PAIRS; ++i) {
        double b0 = (irand(1000) + 0.5) / 1000.0, b1 = (1 - b0) * (irand(1000) / 1000.0);
        CHECK(gs_surface_point_from_face(m, irand(nf), b0, b1, 1 - b0 - b1, &w->points[i], &err) == GS_OK);
    }
    for (uint32_t i = 0; i < N_POINT_PAIRS; ++i)
        w->want_points[i] = gs_db_point_distance(db, &w->points[2 * i], &w->points[2 * i + 1]);
    for (uint32_t s = 0; s < N_POINT_FIELDS; ++s)
        CHECK(gs_db_point_field(db, &w->points[2 * s], w->want_point_fields + (size_t)s * n, &err) == GS_OK);
    uint32_t n_finite = 0;
    for (uint32_t i = 0; i < N_PAIRS; ++i) n_finite += isfinite(w->want_pairs[i]) != 0;
    CHECK_MSG(n_finite > N_PAIRS / 4, "%s: %u finite answers of %d", what, n_finite, N_PAIRS);

    pthread_t th[N_THREADS];
    thread_arg arg[N_THREADS];
    for (uint32_t t = 0; t < N_THREADS; ++t) {
        arg[t] = (thread_arg){w, t, 0, 0, 0};
        CHECK(pthread_create(&th[t], NULL, run, &arg[t]) == 0);
    }
    uint64_t checked = 0, wrong = 0, failed = 0;
    for (uint32_t t = 0; t < N_THREADS; ++t) {
        CHECK(pthread_join(th[t], NULL) == 0);
        checked += arg[t].checked, wrong += arg[t].wrong, failed += arg[t].failed;
    }
    CHECK_MSG(wrong == 0 && failed == 0, "%s: %llu answers differ from one thread's, %llu calls failed",
              what, (unsigned long long)wrong, (unsigned long long)failed);
    CHECK(checked > 0);
    printf("%-34s %u threads, %llu answers identical to one thread's\n", what, N_THREADS,
           (unsigned long long)checked);
    free(w->want_fields);
    free(w->want_point_fields);
    free(w);
}

static void run_mesh(const char *spec, int leaf_exact)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_generate(spec, &m, &err) == GS_OK, "%s: %s", spec, err.message);
    if (!m) return;
    gs_build_options o;
    gs_build_options_default(&o);
    o.threads = 1;
    o.vmax = 16;
    o.leaf_exact = leaf_exact;
    gs_db *db = NULL;
    CHECK_MSG(gs_db_build(m, &o, &db, NULL, &err) == GS_OK, "%s: build: %s", spec, err.message);
    if (!db) {
        gs_mesh_free(m);
        return;
    }
    char what[128];
    snprintf(what, sizeof what, "%s%s, built", spec, leaf_exact ? " leaf-exact" : "");
    check_db(db, m, what);

    /* saved, then opened from the file and from memory */
    char path[] = "/tmp/geosep-test-threads-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0) {
        close(fd);
        CHECK_MSG(gs_db_save(db, path, &err) == GS_OK, "save: %s", err.message);
        gs_db *opened = NULL;
        CHECK_MSG(gs_db_open(path, &opened, &err) == GS_OK, "open: %s", err.message);
        if (opened) {
            snprintf(what, sizeof what, "%s%s, opened", spec, leaf_exact ? " leaf-exact" : "");
            check_db(opened, m, what);
        }
        gs_db_free(opened);
        FILE *f = fopen(path, "rb");
        CHECK(f != NULL);
        if (f) {
            fseek(f, 0, SEEK_END);
            long size = ftell(f);
            rewind(f);
            char *buf = size > 0 ? malloc((size_t)size) : NULL;
            CHECK(buf && fread(buf, 1, (size_t)size, f) == (size_t)size);
            fclose(f);
            gs_db *mem = NULL;
            if (buf) CHECK_MSG(gs_db_open_memory(buf, (size_t)size, &mem, &err) == GS_OK, "open_memory: %s", err.message);
            free(buf); /* copied by gs_db_open_memory */
            if (mem) {
                snprintf(what, sizeof what, "%s%s, from memory", spec, leaf_exact ? " leaf-exact" : "");
                check_db(mem, m, what);
            }
            gs_db_free(mem);
        }
        unlink(path);
    }
    gs_db_free(db);
    gs_mesh_free(m);
}

int main(void)
{
    run_mesh("torus:30,16", 0);  /* closed, genus 1 */
    run_mesh("two:12", 1);       /* two components: +inf answers; leaf tables */
    return gs_test_finish("test_threads");
}
