/* bench/exact.c - speed of one exact distance field (GS_METHOD_EXACT) and of
 * the edge-graph baseline on the shared benchmark meshes, against the VTP
 * reference times (Qin et al. 2016, on this machine class).
 * Usage: bench_exact [N_SOURCES=9] [SHARED_DIR]. Times are the solve only
 * (the solver is created once per mesh), median over N random vertices. */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

typedef struct bench_mesh {
    const char *name;
    double vtp_lo, vtp_hi; /* VTP reference seconds per field */
} bench_mesh;

static const bench_mesh MESHES[] = {
    {"bunny-5k", 0.025, 0.025},
    {"stanford-bunny", 0.22, 0.31},
    {"homer-60k", 0.9, 0.9},
};

/* Median seconds and windows per field of `method` over the sources. */
static int run(const gs_patch *patch, gs_method method, const uint32_t *src, int n,
               double *med_s, double *med_windows, double *dist)
{
    gs_solver *s = NULL;
    gs_error err;
    if (gs_solver_create(patch, method, &s, &err)) {
        fprintf(stderr, "solver: %s\n", err.message);
        return -1;
    }
    double *t = malloc((size_t)n * sizeof *t), *w = malloc((size_t)n * sizeof *w);
    int rc = 0;
    for (int i = 0; i < n && rc == 0; ++i) {
        gs_source so = gs_source_vertex(src[i]);
        if (gs_solver_solve(s, &so, 1, 0, dist, &err)) {
            fprintf(stderr, "solve: %s\n", err.message);
            rc = -1;
            break;
        }
        uint64_t created;
        gs_solver_last_stats(s, &created, NULL, &t[i]);
        w[i] = (double)created;
    }
    if (rc == 0) {
        *med_s = median(t, n);
        *med_windows = median(w, n);
    }
    free(t);
    free(w);
    gs_solver_free(s);
    return rc;
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 9;
    const char *dir = argc > 2 ? argv[2] : GEOSEP_SHARED_DIR;
    if (n < 1) {
        fprintf(stderr, "usage: %s [n_sources >= 1] [shared_dir]\n", argv[0]);
        return 2;
    }
    printf("exact geodesic fields, one thread, median over %d random source vertices\n", n);
    printf("%-15s %7s | %9s %11s %9s | %9s %9s | %s\n", "mesh", "verts", "exact s",
           "windows", "win/vert", "graph s", "exact/gr", "exact / VTP reference");
    for (size_t m = 0; m < sizeof MESHES / sizeof MESHES[0]; ++m) {
        char path[4096];
        snprintf(path, sizeof path, "%s/meshes/%s.obj", dir, MESHES[m].name);
        gs_mesh *mesh = NULL;
        gs_error err;
        if (gs_mesh_load(path, GS_FORMAT_AUTO, &mesh, &err)) {
            printf("%-15s skipped: %s\n", MESHES[m].name, err.message);
            continue;
        }
        gs_patch *patch = NULL;
        if (gs_patch_create(mesh, NULL, 0, &patch, &err)) {
            printf("%-15s skipped: %s\n", MESHES[m].name, err.message);
            gs_mesh_free(mesh);
            continue;
        }
        uint32_t nv = gs_mesh_num_vertices(mesh);
        uint32_t *src = malloc((size_t)n * sizeof *src);
        if (gs_mesh_random_vertices(mesh, (uint32_t)n, 12345, src, &err)) { /* referenced only */
            printf("%-15s skipped: %s\n", MESHES[m].name, err.message);
            free(src);
            gs_patch_free(patch);
            gs_mesh_free(mesh);
            continue;
        }
        double *dist = malloc((size_t)nv * sizeof *dist);
        double te = 0, we = 0, tg = 0, wg = 0;
        if (run(patch, GS_METHOD_EXACT, src, n, &te, &we, dist) == 0 &&
            run(patch, GS_METHOD_GRAPH, src, n, &tg, &wg, dist) == 0) {
            char ref[64];
            if (MESHES[m].vtp_lo == MESHES[m].vtp_hi)
                snprintf(ref, sizeof ref, "%.2fx (VTP %.3g s)", te / MESHES[m].vtp_lo,
                         MESHES[m].vtp_lo);
            else
                snprintf(ref, sizeof ref, "%.2f-%.2fx (VTP %.3g-%.3g s)", te / MESHES[m].vtp_hi,
                         te / MESHES[m].vtp_lo, MESHES[m].vtp_lo, MESHES[m].vtp_hi);
            printf("%-15s %7u | %9.4f %11.0f %9.1f | %9.4f %9.1f | %s\n", MESHES[m].name, nv, te,
                   we, we / nv, tg, tg > 0 ? te / tg : 0.0, ref);
            fflush(stdout);
        }
        free(dist);
        free(src);
        gs_patch_free(patch);
        gs_mesh_free(mesh);
    }
    return 0;
}
