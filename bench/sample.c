/* bench/sample.c - farthest-point sampling by a database's distances
 * (gs_db_farthest_point_sampling): the time for K samples (default 100) and
 * the time per sample next to one gs_db_field, on a generated mesh and on
 * the shared bunny-5k when present (databases built here, default options).
 * Usage: bench_sample [K] [MESH ...]   (MESH: a generator spec such as
 * sphere:5, or a name of ../shared/meshes without .obj; default: sphere:5
 * and bunny-5k) */
#include "bench_util.h"
#include "geosep.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

static int run(const char *name, uint32_t k)
{
    gs_error err = {0};
    gs_mesh *m = NULL;
    gs_db *db = NULL;
    uint32_t *out = NULL;
    double *field = NULL;
    int rc = 1;
    if (strchr(name, ':')) {
        if (gs_mesh_generate(name, &m, &err)) goto fail;
    } else {
        char path[512];
        snprintf(path, sizeof path, "%s/meshes/%s.obj", GEOSEP_SHARED_DIR, name);
        if (access(path, R_OK)) {
            printf("%-12s skipped: %s not found\n", name, path);
            return 0;
        }
        if (gs_mesh_load(path, GS_FORMAT_AUTO, &m, &err)) goto fail;
    }
    gs_build_options o;
    gs_build_options_default(&o);
    double t0 = now();
    if (gs_db_build(m, &o, &db, NULL, &err)) goto fail;
    double t_build = now() - t0;
    uint32_t n = gs_mesh_num_vertices(m);
    out = malloc((size_t)k * sizeof *out);
    field = malloc((size_t)n * sizeof *field);
    if (!out || !field) goto fail;
    /* one field per sample: the field's time, alternated with sampling's */
    double t_sample = 1e300, t_field = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
        t0 = now();
        if (gs_db_farthest_point_sampling(db, k, 0, out, &err)) goto fail;
        double t = now() - t0;
        if (t < t_sample) t_sample = t;
        t0 = now();
        for (uint32_t i = 0; i < k; ++i)
            if (gs_db_field(db, out[i], field, &err)) goto fail;
        t = (now() - t0) / k;
        if (t < t_field) t_field = t;
    }
    printf("%-12s %7u %5u  %9.1f %10.3f %10.3f %6.2f  (build %.1f s)\n", name, n, k, 1e3 * t_sample,
           1e3 * t_sample / k, 1e3 * t_field, t_sample / k / t_field, t_build);
    rc = 0;
    goto done;
fail:
    fprintf(stderr, "%s: %s\n", name, err.message[0] ? err.message : "out of memory");
done:
    free(out);
    free(field);
    gs_db_free(db);
    gs_mesh_free(m);
    return rc;
}

int main(int argc, char **argv)
{
    uint32_t k = 100;
    int first = 1;
    if (argc > 1 && argv[1][0] >= '0' && argv[1][0] <= '9') k = (uint32_t)strtoul(argv[1], NULL, 10), first = 2;
    printf("farthest-point sampling, best of 3 (one thread)\n");
    printf("%-12s %7s %5s  %9s %10s %10s %6s\n", "mesh", "n", "k", "total ms", "ms/sample", "ms/field", "ratio");
    int rc = 0;
    if (first < argc)
        for (int i = first; i < argc; ++i) rc |= run(argv[i], k);
    else
        rc = run("sphere:5", k) | run("bunny-5k", k);
    return rc;
}
