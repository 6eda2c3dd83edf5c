/* bench/db.c - what a database costs where users see it: file size, bytes
 * and numbers per vertex, gs_db_open time, resident memory after opening
 * and after a million queries (VmRSS, RssFile + RssAnon of
 * /proc/self/status, Linux), and query times (median of single queries,
 * batches). Public API only (gs_db_open, gs_db_get_info, gs_db_distance,
 * gs_db_distances), so that the same program compiles against an older
 * library for a comparison (tools/bench_db_compare.sh). */
#include "bench_util.h"
#include "geosep.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N_PAIRS 1000000u
#define BATCH 1000u
#define N_OPENS 21

/* VmRSS, RssAnon and RssFile in kB (-1: unknown). */
static void rss(long *vm, long *anon, long *file)
{
    *vm = *anon = *file = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        if (!strncmp(line, "VmRSS:", 6)) *vm = atol(line + 6);
        else if (!strncmp(line, "RssAnon:", 8)) *anon = atol(line + 8);
        else if (!strncmp(line, "RssFile:", 8)) *file = atol(line + 8);
    }
    fclose(f);
}

static uint64_t rng_state = 0x853C49E6748FEA9Bull;
static uint32_t rng(uint32_t n)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint32_t)((rng_state >> 11) % n);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        printf("usage: %s DB.gsdb\n"
               "  file size, bytes/vertex, open time (median of %d opens of the cached file), resident\n"
               "  memory after opening and after %u random queries, query median and batch times.\n",
               argv[0], N_OPENS, N_PAIRS);
        return 0;
    }
    gs_error err = {0};
    double topen[N_OPENS];
    for (int i = 0; i < N_OPENS; ++i) { /* the file in the page cache: the open itself */
        gs_db *d = NULL;
        double t = now();
        if (gs_db_open(argv[1], &d, &err) != GS_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        topen[i] = now() - t;
        gs_db_free(d);
    }
    qsort(topen, N_OPENS, sizeof *topen, cmp_double);
    /* the benchmark's own arrays first, touched, so that they count in
     * every reading below */
    uint32_t *pairs = malloc(sizeof *pairs * 2 * N_PAIRS);
    double *t = malloc(sizeof *t * N_PAIRS), *out = malloc(sizeof *out * BATCH), sum = 0.0;
    double *tl = malloc(sizeof *tl * (N_PAIRS / BATCH)), *tb = malloc(sizeof *tb * (N_PAIRS / BATCH));
    if (!pairs || !t || !out || !tl || !tb) return 1;
    for (uint32_t i = 0; i < N_PAIRS; ++i) t[i] = 1.0; /* not memset: malloc + memset 0 may become calloc */
    for (uint32_t i = 0; i < N_PAIRS / BATCH; ++i) tl[i] = tb[i] = 1.0;
    for (uint32_t i = 0; i < BATCH; ++i) out[i] = 1.0;
    long vm0, anon0, file0, vm1, anon1, file1, vm2, anon2, file2;
    gs_db *db = NULL;
    if (gs_db_open(argv[1], &db, &err) != GS_OK) { /* the ids need n_vertices */
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    gs_db_free(db);
    uint32_t nv = info.n_vertices;
    for (uint32_t i = 0; i < 2 * N_PAIRS; ++i) pairs[i] = rng(nv);
    rss(&vm0, &anon0, &file0);
    if (gs_db_open(argv[1], &db, &err) != GS_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    rss(&vm1, &anon1, &file1);
    double t0 = 1e300;
    for (int i = 0; i < 1000; ++i) {
        double a = now(), b = now();
        t0 = b - a < t0 ? b - a : t0;
    }
    for (uint32_t i = 0; i < N_PAIRS; ++i) {
        double a = now();
        sum += gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        t[i] = now() - a - t0;
    }
    rss(&vm2, &anon2, &file2);
    /* batches of BATCH, each timed: their median per query (robust to the
     * other processes of a shared machine), in a loop and through the batch
     * call */
    for (uint32_t b = 0; b < N_PAIRS / BATCH; ++b) {
        double a = now();
        for (uint32_t i = b * BATCH; i < (b + 1) * BATCH; ++i) sum += gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        tl[b] = (now() - a) / BATCH;
        a = now();
        gs_db_distances(db, pairs + 2 * (size_t)b * BATCH, BATCH, out, NULL);
        tb[b] = (now() - a) / BATCH;
        for (uint32_t i = 0; i < BATCH; ++i) sum += out[i];
    }
    qsort(tl, N_PAIRS / BATCH, sizeof *tl, cmp_double);
    qsort(tb, N_PAIRS / BATCH, sizeof *tb, cmp_double);
    qsort(t, N_PAIRS, sizeof *t, cmp_double);
    double mb = 1.0 / (1 << 20), fb = (double)info.file_bytes;
    printf("%s: format %u, %u vertices\n", argv[1], info.format_version, nv);
    printf("  file          %llu bytes, %.1f bytes/vertex, cost %.1f numbers/vertex\n",
           (unsigned long long)info.file_bytes, info.bytes_per_vertex, info.cost);
    printf("  open          %.3f ms (median of %d; min %.3f, max %.3f)\n", 1e3 * topen[N_OPENS / 2], N_OPENS,
           1e3 * topen[0], 1e3 * topen[N_OPENS - 1]);
    printf("  resident      before open %.1f MB; after open %.1f MB (+%.1f: file %+.1f, anon %+.1f); after %u "
           "queries %.1f MB (+%.1f: file %+.1f, anon %+.1f) = %.2f x the file\n",
           vm0 * 1024 * mb, vm1 * 1024 * mb, (vm1 - vm0) * 1024 * mb, (file1 - file0) * 1024 * mb,
           (anon1 - anon0) * 1024 * mb, N_PAIRS, vm2 * 1024 * mb, (vm2 - vm0) * 1024 * mb,
           (file2 - file0) * 1024 * mb, (anon2 - anon0) * 1024 * mb, (vm2 - vm0) * 1024.0 / fb);
    printf("  queries       median %.0f ns, p90 %.0f ns, p99 %.0f ns (single, timed one by one); batches of %u "
           "(median): %.0f ns/query in a loop, %.0f ns/query through gs_db_distances (checksum %.6g)\n",
           1e9 * t[N_PAIRS / 2], 1e9 * t[N_PAIRS / 10 * 9], 1e9 * t[N_PAIRS / 100 * 99], BATCH,
           1e9 * tl[N_PAIRS / BATCH / 2], 1e9 * tb[N_PAIRS / BATCH / 2], sum);
    free(pairs), free(t), free(out), free(tl), free(tb);
    gs_db_free(db);
    return 0;
}
