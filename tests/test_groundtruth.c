/* test_groundtruth.c - the exact solver against the CGAL ground truth of the
 * shared folder: for every mesh M with meshes/M.obj and groundtruth/M.gt,
 * every source's field must match to 1e-9 maximum relative error (+inf
 * exactly where the ground truth is +inf). GEOSEP_QUICK=1: two sources per
 * mesh, meshes over 40k vertices skipped (for sanitizer builds). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_REL_ERR 1e-9


static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Relative error of one value; inf must match inf exactly. */
static double rel_err(double got, double want)
{
    if (isinf(want) || isinf(got) || isnan(got)) return (got == want) ? 0.0 : INFINITY;
    if (want == 0) return got == 0 ? 0.0 : INFINITY;
    return fabs(got - want) / want;
}

static int test_mesh(const char *name, int quick, int *n_tested)
{
    char obj[4096], gtp[4096];
    if (!gs__test_shared_pair(name, obj, gtp, sizeof obj)) return 0;

    gs_error err;
    gs_mesh *mesh = NULL;
    gs_gt *gt = NULL;
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    double *dist = NULL;
    int rc = gs_mesh_load(obj, GS_FORMAT_AUTO, &mesh, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", obj, err.message);
    if (rc) return 0;
    if (quick && gs_mesh_num_vertices(mesh) > 40000) {
        printf("%-16s skipped (GEOSEP_QUICK, %u vertices)\n", name, gs_mesh_num_vertices(mesh));
        gs_mesh_free(mesh);
        return 0;
    }
    rc = gs_gt_read(gtp, &gt, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", gtp, err.message);
    if (rc) goto done;
    CHECK_MSG(gt->n_vertices == gs_mesh_num_vertices(mesh), "%s: %u vertices, ground truth %u",
              name, gs_mesh_num_vertices(mesh), gt->n_vertices);
    if (gt->n_vertices != gs_mesh_num_vertices(mesh)) goto done;
    rc = gs_patch_create(mesh, NULL, 0, &patch, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", name, err.message);
    if (rc) goto done;
    rc = gs_solver_create(patch, GS_METHOD_EXACT, &solver, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", name, err.message);
    if (rc) goto done;
    dist = malloc(gt->n_vertices * sizeof *dist);
    CHECK(dist != NULL);
    if (!dist) goto done;

    uint32_t n_src = gt->n_sources;
    if (quick && n_src > 2) n_src = 2;
    double worst = 0, total_time = 0;
    uint32_t worst_src = 0, worst_v = 0;
    for (uint32_t j = 0; j < n_src; ++j) {
        gs_source s = gs_source_vertex(gt->sources[j]);
        double t0 = now();
        rc = gs_solver_solve(solver, &s, 1, 0, dist, &err);
        total_time += now() - t0;
        CHECK_MSG(rc == GS_OK, "%s source %u: %s", name, gt->sources[j], err.message);
        if (rc) continue;
        const double *want = gt->dist + (size_t)j * gt->n_vertices;
        double src_worst = 0;
        uint32_t src_v = 0;
        for (uint32_t v = 0; v < gt->n_vertices; ++v) {
            double e = rel_err(dist[v], want[v]);
            if (e > src_worst || isnan(e)) {
                src_worst = e;
                src_v = v;
            }
        }
        CHECK_MSG(src_worst <= MAX_REL_ERR,
                  "%s source %u: vertex %u has %.17g, ground truth %.17g (rel err %.3g)", name,
                  gt->sources[j], src_v, dist[src_v], want[src_v], src_worst);
        if (src_worst > worst) {
            worst = src_worst;
            worst_src = gt->sources[j];
            worst_v = src_v;
        }
    }
    printf("%-16s %6u vertices %3u sources  max rel err %.3g (source %u, vertex %u)  mean %.4f s\n",
           name, gt->n_vertices, n_src, worst, worst_src, worst_v,
           n_src ? total_time / n_src : 0.0);
    fflush(stdout);
    (*n_tested)++;
done:
    free(dist);
    gs_solver_free(solver);
    gs_patch_free(patch);
    gs_gt_free(gt);
    gs_mesh_free(mesh);
    return 0;
}

int main(void)
{
    if (!gs__test_shared_path("meshes"))
        gs__test_skip("shared folder with meshes/ and groundtruth/ not found "
                     "(set GEOSEP_SHARED or the GEOSEP_SHARED_DIR CMake cache variable)");
    const char *q = getenv("GEOSEP_QUICK");
    int quick = q && strcmp(q, "1") == 0;
    /* every groundtruth/M.gt, in name order; test_mesh skips those without
     * meshes/M.obj */
    static char names[256][GS_TEST_NAME_MAX];
    int n_names = gs__test_shared_names(names, 256);
    if (n_names < 0) gs__test_skip("shared folder has no groundtruth/");
    int n_tested = 0;
    for (int i = 0; i < n_names; ++i) test_mesh(names[i], quick, &n_tested);
    CHECK_MSG(n_tested > 0, "no mesh with both meshes/M.obj and groundtruth/M.gt was found");
    return gs__test_finish("test_groundtruth");
}
