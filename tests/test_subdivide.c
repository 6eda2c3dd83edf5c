/* test_subdivide.c - 1-to-4 midpoint subdivision: counts, topology kept
 * (components, boundary loops, genus), original vertices kept in place, and
 * the surface unchanged (exact geodesic distances between original vertices
 * equal those on the coarse mesh). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void check_spec(const char *spec)
{
    gs_mesh *m = NULL, *s = NULL;
    gs_error err;
    CHECK(gs_mesh_generate(spec, &m, &err) == GS_OK);
    CHECK_MSG(gs_mesh_subdivide(m, &s, &err) == GS_OK, "%s: %s", spec, err.message);
    if (!s) return;
    gs_mesh_report a, b;
    gs_mesh_get_report(m, &a, NULL);
    gs_mesh_get_report(s, &b, NULL);
    CHECK(b.n_vertices == a.n_vertices + a.n_edges);
    CHECK(b.n_faces == 4 * a.n_faces);
    CHECK(b.n_edges == 2 * a.n_edges + 3 * a.n_faces);
    CHECK(b.n_components == a.n_components && b.n_boundary_loops == a.n_boundary_loops);
    CHECK(b.genus == a.genus && b.euler == a.euler);
    CHECK(memcmp(gs_mesh_positions(m), gs_mesh_positions(s), 3 * sizeof(double) * a.n_vertices) == 0);
    /* the same polyhedral surface: exact distances between original vertices agree */
    uint32_t n = a.n_vertices, src[3];
    CHECK(gs_mesh_random_vertices(m, 3, 7, src, &err) == GS_OK);
    gs_patch *pm, *ps;
    gs_patch_create(m, NULL, 0, &pm, NULL);
    gs_patch_create(s, NULL, 0, &ps, NULL);
    double *dm = malloc(n * sizeof *dm), *ds = malloc(b.n_vertices * sizeof *ds), worst = 0;
    for (int k = 0; k < 3; ++k) {
        gs_source so = gs_source_vertex(src[k]);
        CHECK(gs_distance_field(pm, GS_METHOD_EXACT, &so, 1, 0, dm, &err) == GS_OK);
        CHECK(gs_distance_field(ps, GS_METHOD_EXACT, &so, 1, 0, ds, &err) == GS_OK);
        for (uint32_t v = 0; v < n; ++v)
            if (isfinite(dm[v]) && dm[v] > 0) worst = fmax(worst, fabs(ds[v] - dm[v]) / dm[v]);
    }
    printf("%-16s %6u -> %7u vertices, %6u -> %7u faces, distances agree to %.2g\n", spec, a.n_vertices,
           b.n_vertices, a.n_faces, b.n_faces, worst);
    CHECK_MSG(worst < 1e-9, "%s: distances differ by %g after subdivision", spec, worst);
    free(dm);
    free(ds);
    gs_patch_free(pm);
    gs_patch_free(ps);
    gs_mesh_free(m);
    gs_mesh_free(s);
}

int main(void)
{
    check_spec("peaks:20");
    check_spec("plate:300");
    check_spec("torus:16,8");
    check_spec("two:6");
    check_spec("cube:3");
    CHECK(gs_mesh_subdivide(NULL, NULL, NULL) == GS_EARG);
    return gs__test_finish("test_subdivide");
}
