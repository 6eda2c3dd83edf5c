/* accuracy.c - the accuracy benchmark (issue 17): for each mesh, the default
 * database (or one built with the options given) against exact distances:
 * ME and RMSE (the paper's, per source, averaged), p99, p99.9 and max over
 * all pairs, near-pair ME (pairs whose exact d is below 10% of the median
 * exact d), the largest under- and overestimates, pairs off by > 5%, and
 * storage (bytes and numbers per vertex). Ground truth: GTDIR/NAME.gt when
 * --gt-dir is given and the file exists (e.g. every vertex a source: geosep
 * solve MESH --format gt --all -o GTDIR/NAME.gt), else ../shared's
 * groundtruth/NAME.gt; for generated specs (NAME with ':'), exact fields
 * from every vertex, solved here. Usage:
 *   bench_accuracy [--gt-dir DIR] [--leaf-exact] [--spacing F] [--mmax N]
 *                  [--tol F] [--threads N] [MESH|SPEC ...]
 * Default meshes: knot:120,12, cylinder:48,30, and spot, bunny-5k, homer,
 * fandisk from ../shared when present. */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static int exists(const char *p) { return access(p, R_OK) == 0; }

/* Exact fields from every vertex used by a face (generated meshes). */
static int all_pairs_gt(const gs_mesh *m, gs_gt **out, gs_error *err)
{
    gs_mesh_report r;
    int rc = gs_mesh_get_report(m, &r, err);
    if (rc) return rc;
    uint32_t n = gs_mesh_num_vertices(m), k = n - r.n_unreferenced;
    gs_gt *gt = calloc(1, sizeof *gt);
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    if (!gt || !(gt->sources = malloc(k * sizeof *gt->sources)) ||
        !(gt->dist = malloc((size_t)k * n * sizeof *gt->dist))) {
        gs_gt_free(gt);
        return GS_ENOMEM;
    }
    gt->n_vertices = n;
    gt->n_sources = k;
    if ((rc = gs_mesh_random_vertices(m, k, 0, gt->sources, err)) || (rc = gs_patch_create(m, NULL, 0, &p, err)) ||
        (rc = gs_solver_create(p, GS_METHOD_EXACT, &s, err)))
        goto done;
    for (uint32_t j = 0; j < k && !rc; ++j) {
        gs_source src = gs_source_vertex(gt->sources[j]);
        rc = gs_solver_solve(s, &src, 1, 0, gt->dist + (size_t)j * n, err);
    }
done:
    gs_solver_free(s);
    gs_patch_free(p);
    if (rc) gs_gt_free(gt);
    else *out = gt;
    return rc;
}

static int run(const char *what, const char *gt_dir, const gs_build_options *opt)
{
    char path[4096];
    gs_mesh *m = NULL;
    gs_gt *gt = NULL;
    gs_db *db = NULL;
    gs_error_acc *acc = NULL;
    gs_error err = {0};
    double *d = NULL;
    int rc, generated = strchr(what, ':') != NULL;
    const char *gt_src = "all pairs, solved here";
    if (generated) rc = gs_mesh_generate(what, &m, &err);
    else {
        snprintf(path, sizeof path, "%s/meshes/%s.obj", GEOSEP_SHARED_DIR, what);
        if (!exists(path)) {
            printf("%-14s skipped: %s not found\n", what, path);
            return 0;
        }
        rc = gs_mesh_load(path, GS_FORMAT_AUTO, &m, &err);
    }
    if (rc) goto done;
    if (generated) rc = all_pairs_gt(m, &gt, &err);
    else {
        snprintf(path, sizeof path, "%s/%s.gt", gt_dir ? gt_dir : "", what);
        if (gt_dir && exists(path)) gt_src = "all pairs (--gt-dir)";
        else {
            snprintf(path, sizeof path, "%s/groundtruth/%s.gt", GEOSEP_SHARED_DIR, what);
            gt_src = "shared ground truth";
        }
        rc = gs_gt_read(path, &gt, &err);
    }
    if (rc) goto done;
    double t0 = now();
    if ((rc = gs_db_build(m, opt, &db, NULL, &err))) goto done;
    double t_build = now() - t0;
    uint32_t n = gs_mesh_num_vertices(m);
    if (gt->n_vertices != n) {
        rc = GS_EARG;
        snprintf(err.message, sizeof err.message, "ground truth for %u vertices, mesh has %u", gt->n_vertices, n);
        goto done;
    }
    if (!(d = malloc(n * sizeof *d))) {
        rc = GS_ENOMEM;
        goto done;
    }
    if ((rc = gs_error_acc_create(&acc, &err))) goto done;
    for (uint32_t j = 0; j < gt->n_sources && !rc; ++j)
        if (!(rc = gs_db_field(db, gt->sources[j], d, &err)))
            rc = gs_error_acc_add(acc, gt->dist + (size_t)j * n, d, n, gt->sources[j], &err);
    gs_error_stats st;
    gs_db_info info;
    if (rc || (rc = gs_error_acc_result(acc, 0.1, &st, &err)) || (rc = gs_db_get_info(db, &info, &err))) goto done;
    printf("%-14s %6u %6.3f%% %6.3f%% %6.3f%% %6.3f%% %7.2f%% %6.3f%% %7.2f%% %7.2f%% %7llu %7llu %6.1f %6.1f %6.1f  %s\n",
           what, n, 100 * st.me, 100 * st.rmse, 100 * st.p99, 100 * st.p999, 100 * st.max, 100 * st.near_me,
           100 * st.max_under, 100 * st.max_over, (unsigned long long)st.n_under_5pct,
           (unsigned long long)st.n_over_5pct, info.bytes_per_vertex, info.cost, t_build, gt_src);
    fflush(stdout);
done:
    if (rc) fprintf(stderr, "bench_accuracy: %s: %s\n", what, err.message);
    free(d);
    gs_error_acc_free(acc);
    gs_db_free(db);
    gs_gt_free(gt);
    gs_mesh_free(m);
    return rc;
}

int main(int argc, char **argv)
{
    gs_build_options opt;
    gs_build_options_default(&opt);
    const char *gt_dir = NULL;
    const char *meshes[64];
    int nm = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--gt-dir") && i + 1 < argc) gt_dir = argv[++i];
        else if (!strcmp(a, "--leaf-exact")) opt.leaf_exact = 1;
        else if (!strcmp(a, "--spacing") && i + 1 < argc) opt.sample_spacing = atof(argv[++i]);
        else if (!strcmp(a, "--mmax") && i + 1 < argc) opt.mmax = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(a, "--tol") && i + 1 < argc) opt.tol = atof(argv[++i]);
        else if (!strcmp(a, "--threads") && i + 1 < argc) opt.threads = (uint32_t)atoi(argv[++i]);
        else if (a[0] == '-') {
            fprintf(stderr, "usage: bench_accuracy [--gt-dir DIR] [--leaf-exact] [--spacing F] [--mmax N] [--tol F] "
                            "[--threads N] [MESH|SPEC ...]\n");
            return 2;
        } else if (nm < 64) meshes[nm++] = a;
    }
    if (!nm) {
        static const char *def[] = {"knot:120,12", "cylinder:48,30", "spot", "bunny-5k", "homer", "fandisk"};
        for (size_t k = 0; k < sizeof def / sizeof *def; ++k) meshes[nm++] = def[k];
    }
    printf("near pairs: exact d < 10%% of the median exact d; ME, RMSE: per source, averaged; the rest over all pairs\n");
    printf("%-14s %6s %7s %7s %7s %7s %8s %7s %8s %8s %7s %7s %6s %6s %6s\n", "mesh", "n", "ME", "RMSE", "p99",
           "p99.9", "max", "nearME", "maxunder", "maxover", ">5%und", ">5%ovr", "B/vtx", "num/v", "build");
    int bad = 0;
    for (int k = 0; k < nm; ++k) bad |= run(meshes[k], gt_dir, &opt) != 0;
    return bad;
}
