/* bench/dgg.c - discrete geodesic graph fields against exact fields on one
 * shared mesh: K fields from the same random vertices with the exact solver
 * and with dgg (graph construction included), the time ratio, the graph's
 * construction time (wall and CPU), candidate and kept edges and memory,
 * and the dgg fields' mean and max relative error against the exact ones.
 * Times are wall and process CPU; the exact fields run on one thread, the
 * graph's construction on --threads (default: OpenMP's), its fields on one.
 * Usage: bench_dgg [--fields K] [--dgg-eps E] [--threads N] [--no-prune] [MESH]
 *        (default: 64 fields, eps 1e-3, homer-60k; MESH: a name of
 *        ../shared/meshes without .obj, or a path). Run niced on a busy machine. */
#include "../src/geodesic/geodesic_internal.h"
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

static double cpu(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

int main(int argc, char **argv)
{
    uint32_t k = 64, nthreads = 0;
    int prune = 1;
    const char *name = "homer-60k";
    gs_solver_options opt;
    gs_solver_options_default(&opt);
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--fields") && i + 1 < argc) k = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--dgg-eps") && i + 1 < argc) opt.dgg_eps = atof(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) nthreads = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-prune")) prune = 0;
        else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: bench_dgg [--fields K] [--dgg-eps E] [--threads N] [--no-prune] [MESH]\n");
            return 2;
        } else name = argv[i];
    }
    char path[4096];
    if (strchr(name, '/') || strchr(name, '.')) snprintf(path, sizeof path, "%s", name);
    else snprintf(path, sizeof path, "%s/meshes/%s.obj", GEOSEP_SHARED_DIR, name);
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    if (gs_mesh_load(path, GS_FORMAT_AUTO, &m, &err) || gs_patch_create(m, NULL, 0, &p, &err)) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        return 1;
    }
    uint32_t nv = gs_mesh_num_vertices(m);
    if (k == 0 || k > nv) k = nv < 64 ? nv : 64;
    uint32_t *src = malloc(k * sizeof *src);
    double *de = malloc((size_t)k * nv * sizeof *de), *dd = malloc((size_t)nv * sizeof *dd);
    if (!src || !de || !dd || gs_mesh_random_vertices(m, k, 1, src, &err)) {
        fprintf(stderr, "out of memory or %s\n", err.message);
        return 1;
    }
    gs_solver *se = NULL, *sd = NULL;
    double t0 = now(), c0 = cpu();
    if (gs_solver_create(p, GS_METHOD_EXACT, &se, &err)) return fprintf(stderr, "%s\n", err.message), 1;
    for (uint32_t j = 0; j < k; ++j) {
        gs_source s = gs_source_vertex(src[j]);
        if (gs_solver_solve(se, &s, 1, 0, de + (size_t)j * nv, &err)) return fprintf(stderr, "%s\n", err.message), 1;
    }
    double t_exact = now() - t0, c_exact = cpu() - c0;
    t0 = now(), c0 = cpu();
    if (gs__solver_create_dgg(p, &opt, nthreads, prune, NULL, &sd, &err))
        return fprintf(stderr, "%s\n", err.message), 1;
    double t_graph = now() - t0, c_graph = cpu() - c0;
    double me = 0, mx = 0, t_fields = 0, c_fields = 0;
    for (uint32_t j = 0; j < k; ++j) {
        gs_source s = gs_source_vertex(src[j]);
        double t1 = now(), c1 = cpu();
        if (gs_solver_solve(sd, &s, 1, 0, dd, &err)) return fprintf(stderr, "%s\n", err.message), 1;
        t_fields += now() - t1;
        c_fields += cpu() - c1;
        gs_field_errors fe;
        if (gs_field_errors_compute(de + (size_t)j * nv, dd, nv, src[j], &fe, &err))
            return fprintf(stderr, "%s\n", err.message), 1;
        me += fe.me / k;
        if (fe.max > mx) mx = fe.max;
    }
    double t_dgg = t_graph + t_fields, c_dgg = c_graph + c_fields;
    gs__dgg_stats st;
    gs__solver_dgg_info(sd, &st, &err);
    printf("%s: %u vertices, %u fields, eps %g (radius %.1f mean edge lengths)%s\n", name, nv, k, opt.dgg_eps,
           gs_dgg_radius(opt.dgg_eps), prune ? "" : ", not pruned");
    printf("exact: %.2f s wall, %.2f s CPU (%.1f ms CPU/field)\n", t_exact, c_exact, 1e3 * c_exact / k);
    printf("graph: %.2f s wall, %.2f s CPU (%.3f ms CPU/vertex); %llu candidates (%.1f per vertex), "
           "%llu edges kept (%.1f per vertex), %.1f MiB\n",
           t_graph, c_graph, 1e3 * c_graph / nv, (unsigned long long)st.candidates, (double)st.candidates / nv,
           (unsigned long long)st.edges, (double)st.edges / nv, st.bytes / 1048576.0);
    printf("dgg fields: %.2f s wall, %.2f s CPU (%.2f ms CPU/field)\n", t_fields, c_fields, 1e3 * c_fields / k);
    printf("ratio dgg (graph + fields) / exact: CPU %.3f, wall %.3f   dgg vs exact: ME %.4f%%  max %.3f%%\n",
           c_dgg / c_exact, t_dgg / t_exact, 100 * me, 100 * mx);
    gs_solver_free(se);
    gs_solver_free(sd);
    gs_patch_free(p);
    gs_mesh_free(m);
    free(src);
    free(de);
    free(dd);
    return 0;
}
