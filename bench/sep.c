/* sep.c - benchmark of the SEP database (paper sec. 3-5): build time per
 * stage, database size, query time per pair (median over batches of a
 * million random pairs, one thread), queries per second, and a full field
 * through queries. Usage: bench_sep [MESH|SPEC ...] (default: bunny-5k from
 * ../shared, else generated Peaks 50x50); --threads N for the build. */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static int load(const char *what, gs_mesh **m)
{
    gs_error err;
    int rc = strchr(what, ':') && access(what, R_OK) != 0 ? gs_mesh_generate(what, m, &err)
                                                          : gs_mesh_load(what, GS_FORMAT_AUTO, m, &err);
    if (rc) fprintf(stderr, "bench_sep: %s\n", err.message);
    return rc;
}

static void bench_queries(const gs_db *db, uint32_t n)
{
    enum { BATCH = 1000, NB = 1000 };
    uint32_t *pairs = malloc(2 * (size_t)BATCH * NB * sizeof *pairs);
    double *bt = malloc(NB * sizeof *bt), sink = 0;
    uint64_t s = 42;
    for (size_t i = 0; i < 2 * (size_t)BATCH * NB; ++i) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        pairs[i] = (uint32_t)((s >> 33) % n);
    }
    double t0 = now();
    for (int b = 0; b < NB; ++b) {
        double tb = now();
        const uint32_t *p = pairs + 2 * (size_t)BATCH * b;
        for (int i = 0; i < BATCH; ++i) sink += gs_db_distance(db, p[2 * i], p[2 * i + 1]);
        bt[b] = (now() - tb) / BATCH;
    }
    double total = now() - t0;
    qsort(bt, NB, sizeof *bt, cmp_double);
    printf("  query: median %.0f ns/pair (batches of %d), %.2f M queries/s over %d pairs (checksum %.3g)\n",
           1e9 * bt[NB / 2], BATCH, BATCH * NB / total / 1e6, BATCH * NB, sink);
    double *f = malloc(n * sizeof *f);
    gs_error err;
    t0 = now();
    int reps = 0;
    while (now() - t0 < 0.5 || reps < 3) {
        gs_db_field(db, (uint32_t)(reps * 7919u % n), f, &err);
        reps++;
    }
    printf("  field through queries: %.3f ms (%u vertices)\n", 1e3 * (now() - t0) / reps, n);
    free(f);
    free(pairs);
    free(bt);
}

int main(int argc, char **argv)
{
    gs_build_options o;
    gs_build_options_default(&o);
    const char *inputs[16];
    int ni = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            o.threads = (uint32_t)atoi(argv[++i]);
        else if (ni < 16)
            inputs[ni++] = argv[i];
    }
    static char def[4096];
    if (ni == 0) {
        snprintf(def, sizeof def, "%s/meshes/bunny-5k.obj", GEOSEP_SHARED_DIR);
        inputs[ni++] = access(def, R_OK) == 0 ? def : "peaks:50";
        if (inputs[0] != def) printf("(../shared not found: using generated peaks:50)\n");
    }
    for (int i = 0; i < ni; ++i) {
        gs_mesh *m = NULL;
        if (load(inputs[i], &m)) return 1;
        gs_db *db = NULL;
        gs_build_stats st;
        gs_error err;
        if (gs_db_build(m, &o, &db, &st, &err)) {
            fprintf(stderr, "bench_sep: %s\n", err.message);
            return 1;
        }
        gs_db_info info;
        gs_db_get_info(db, &info, &err);
        printf("%s: n = %u, threads %u\n", inputs[i], info.n_vertices, o.threads);
        printf("  build: tree %.3f s, fields %.3f s (%llu fields), fits %.3f s (%llu functions, mean degree "
               "%.2f), total %.3f s\n",
               st.seconds_tree, st.seconds_fields, (unsigned long long)st.n_fields, st.seconds_fits,
               (unsigned long long)st.n_functions, st.mean_degree, st.seconds_total);
        printf("  size: %llu bytes, %.1f bytes/vertex, cost %.1f numbers/vertex, depth %.2f/%u\n",
               (unsigned long long)info.file_bytes, info.bytes_per_vertex, info.cost, info.avg_depth,
               info.max_depth);
        bench_queries(db, info.n_vertices);
        gs_db_free(db);
        gs_mesh_free(m);
    }
    return 0;
}
