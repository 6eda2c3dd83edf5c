/* bench/fields.c - accuracy and speed of an approximate distance method
 * (fmm, heat or dgg) against the exact ground truth of the shared meshes:
 * section 5's ME, RMSE and max relative error averaged over every source
 * of each mesh's GEOGT1 file, the solver's creation time and the time per
 * field.
 * Usage: bench_fields [--method fmm|heat|dgg] [--heat-time M] [--fmm-start R] [--dgg-eps E]
 *                     [--heat-refine N|auto] [MESH ...]   (default: heat, every shared mesh)
 * MESH is a name of ../shared/meshes (without .obj). */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

static const char *MESHES[] = {"spot",      "bunny-5k",  "homer",          "fandisk",  "rocker-arm",
                               "bunny-10k", "bunny-20k", "stanford-bunny", "homer-60k"};

static int run(const char *name, gs_method method, const gs_solver_options *opt)
{
    char mp[512], gp[512];
    snprintf(mp, sizeof mp, "%s/meshes/%s.obj", GEOSEP_SHARED_DIR, name);
    snprintf(gp, sizeof gp, "%s/groundtruth/%s.gt", GEOSEP_SHARED_DIR, name);
    gs_error err;
    gs_mesh *m = NULL;
    gs_gt *gt = NULL;
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    double *d = NULL;
    int rc = 1;
    if (gs_mesh_load(mp, GS_FORMAT_AUTO, &m, &err) || gs_gt_read(gp, &gt, &err) ||
        gs_patch_create(m, NULL, 0, &p, &err)) {
        fprintf(stderr, "%s: %s\n", name, err.message);
        goto done;
    }
    uint32_t n = gs_mesh_num_vertices(m);
    if (gt->n_vertices != n) {
        fprintf(stderr, "%s: ground truth has %u vertices, the mesh %u\n", name, gt->n_vertices, n);
        goto done;
    }
    double t0 = now();
    if (gs_solver_create_ex(p, method, opt, &s, &err)) {
        fprintf(stderr, "%s: %s\n", name, err.message);
        goto done;
    }
    double t_create = now() - t0, t_solve = 0, me = 0, rmse = 0, mx = 0;
    d = malloc(sizeof(double) * n);
    if (!d) goto done;
    for (uint32_t j = 0; j < gt->n_sources; ++j) {
        gs_source src = gs_source_vertex(gt->sources[j]);
        t0 = now();
        if (gs_solver_solve(s, &src, 1, 0, d, &err)) {
            fprintf(stderr, "%s: %s\n", name, err.message);
            goto done;
        }
        t_solve += now() - t0;
        gs_field_errors fe;
        if (gs_field_errors_compute(gt->dist + (size_t)j * n, d, n, gt->sources[j], &fe, &err)) {
            fprintf(stderr, "%s: %s\n", name, err.message);
            goto done;
        }
        me += fe.me / gt->n_sources;
        rmse += fe.rmse / gt->n_sources;
        mx = fmax(mx, fe.max);
    }
    printf("%-16s %7u %4u  %7.4f%% %7.4f%% %7.3f%%  %8.1f %9.2f\n", name, n, gt->n_sources, 100 * me,
           100 * rmse, 100 * mx, 1e3 * t_create, 1e3 * t_solve / gt->n_sources);
    rc = 0;
done:
    free(d);
    gs_solver_free(s);
    gs_patch_free(p);
    gs_gt_free(gt);
    gs_mesh_free(m);
    return rc;
}

int main(int argc, char **argv)
{
    gs_method method = GS_METHOD_HEAT;
    gs_solver_options opt;
    gs_solver_options_default(&opt);
    gs_error err;
    int first = argc;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--method") && i + 1 < argc) {
            if (gs_method_from_name(argv[++i], &method, &err)) {
                fprintf(stderr, "%s\n", err.message);
                return 2;
            }
        } else if (!strcmp(argv[i], "--heat-time") && i + 1 < argc) {
            opt.heat_time = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--heat-refine") && i + 1 < argc) {
            const char *v = argv[++i];
            opt.heat_refine = !strcmp(v, "auto") ? GS_HEAT_REFINE_AUTO : (uint32_t)atoi(v);
        } else if (!strcmp(argv[i], "--dgg-eps") && i + 1 < argc) {
            opt.dgg_eps = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--fmm-start") && i + 1 < argc) {
            opt.fmm_exact_start = atof(argv[++i]);
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: bench_fields [--method fmm|heat|dgg] [--heat-time M] [--fmm-start R] [--dgg-eps E] [--heat-refine N|auto] [MESH ...]\n");
            return 2;
        } else {
            first = i;
            break;
        }
    }
    printf("%s fields against the exact ground truth (every source of each file)\n",
           gs_method_name(method));
    printf("%-16s %7s %4s  %8s %8s %8s  %8s %9s\n", "mesh", "n", "src", "ME", "RMSE", "max",
           "create ms", "field ms");
    int bad = 0;
    if (first < argc)
        for (int i = first; i < argc; ++i) bad |= run(argv[i], method, &opt);
    else
        for (size_t i = 0; i < sizeof MESHES / sizeof *MESHES; ++i) bad |= run(MESHES[i], method, &opt);
    return bad;
}
