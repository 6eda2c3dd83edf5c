/* bench/paths.c - exact geodesic paths on the shared meshes: the time of one
 * exact field (gs_solver_solve), of tracing one path from it
 * (gs_solver_trace, to 1000 random vertices) and of gs_solver_path between
 * two surface points (a field plus the trace), with the paths' mean number of
 * points. Usage: bench_paths [N_SOURCES=5] [SHARED_DIR]. Medians over the
 * sources (random vertices, seed 12345). Times are the calling thread's CPU
 * time (everything here runs on it), which a loaded machine disturbs far
 * less than wall-clock time. */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

#define N_TARGETS 1000

static const char *const MESHES[] = {"bunny-5k", "stanford-bunny", "homer-60k"};

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 5;
    const char *dir = argc > 2 ? argv[2] : GEOSEP_SHARED_DIR;
    if (n < 1) {
        fprintf(stderr, "usage: %s [n_sources >= 1] [shared_dir]\n", argv[0]);
        return 2;
    }
    printf("exact paths, one thread (CPU time), medians over %d random sources (%d traces each)\n", n, N_TARGETS);
    printf("%-15s %7s | %10s %10s %8s | %12s\n", "mesh", "verts", "field ms", "trace us", "points",
           "point-point ms");
    for (size_t m = 0; m < sizeof MESHES / sizeof MESHES[0]; ++m) {
        char path[4096];
        snprintf(path, sizeof path, "%s/meshes/%s.obj", dir, MESHES[m]);
        gs_mesh *mesh = NULL;
        gs_patch *patch = NULL;
        gs_solver *s = NULL;
        gs_error err;
        if (gs_mesh_load(path, GS_FORMAT_AUTO, &mesh, &err) || gs_patch_create(mesh, NULL, 0, &patch, &err) ||
            gs_solver_create(patch, GS_METHOD_EXACT, &s, &err)) {
            printf("%-15s skipped: %s\n", MESHES[m], err.message);
            gs_patch_free(patch);
            gs_mesh_free(mesh);
            continue;
        }
        uint32_t nv = gs_mesh_num_vertices(mesh), nf = gs_mesh_num_faces(mesh);
        uint32_t *src = malloc((size_t)n * sizeof *src), *tgt = malloc(N_TARGETS * sizeof *tgt);
        double *dist = malloc((size_t)nv * sizeof *dist);
        double *tf = malloc((size_t)n * sizeof *tf), *tt = malloc((size_t)n * sizeof *tt),
               *tp = malloc((size_t)n * sizeof *tp), *np = malloc((size_t)n * sizeof *np);
        int ok = gs_mesh_random_vertices(mesh, (uint32_t)n, 12345, src, &err) == GS_OK &&
                 gs_mesh_random_vertices(mesh, N_TARGETS, 777, tgt, &err) == GS_OK;
        for (int i = 0; ok && i < n; ++i) {
            gs_source so = gs_source_vertex(src[i]);
            double t0 = now();
            ok = gs_solver_solve(s, &so, 1, 0, dist, &err) == GS_OK;
            tf[i] = now() - t0;
            double points = 0;
            t0 = now();
            for (int k = 0; ok && k < N_TARGETS; ++k) {
                gs_source tv = gs_source_vertex(tgt[k]);
                gs_path *p = NULL;
                ok = gs_solver_trace(s, &tv, &p, &err) == GS_OK;
                points += gs_path_num_points(p);
                gs_path_free(p);
            }
            tt[i] = (now() - t0) / N_TARGETS;
            np[i] = points / N_TARGETS;
            gs_source a = gs_source_point((uint32_t)((src[i] * 7u) % nf), 0.2, 0.3, 0.5);
            gs_source b = gs_source_point((uint32_t)((src[i] * 13u + 1) % nf), 0.6, 0.1, 0.3);
            gs_path *p = NULL;
            t0 = now();
            ok = ok && gs_solver_path(s, &a, &b, &p, &err) == GS_OK;
            tp[i] = now() - t0;
            gs_path_free(p);
        }
        if (ok)
            printf("%-15s %7u | %10.2f %10.2f %8.1f | %12.2f\n", MESHES[m], nv, 1e3 * median(tf, n),
                   1e6 * median(tt, n), median(np, n), 1e3 * median(tp, n));
        else
            printf("%-15s failed: %s\n", MESHES[m], err.message);
        free(src);
        free(tgt);
        free(dist);
        free(tf);
        free(tt);
        free(tp);
        free(np);
        gs_solver_free(s);
        gs_patch_free(patch);
        gs_mesh_free(mesh);
    }
    return 0;
}
