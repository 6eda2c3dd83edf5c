/* test_land.c - the LAND baseline (Burghard & Klein 2015, paper sec. 5):
 * farthest-point landmarks, bounds around the exact distances, estimate
 * accuracy improving with more landmarks, components, arguments. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Exact fields from `ns` sources spread over the mesh: ns x nv. */
static double *exact_fields(const gs_mesh *mesh, uint32_t ns, uint32_t *src)
{
    uint32_t nv = gs_mesh_num_vertices(mesh);
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    double *d = malloc(sizeof *d * ns * nv);
    CHECK(gs_patch_create(mesh, NULL, 0, &patch, NULL) == GS_OK);
    CHECK(gs_solver_create(patch, GS_METHOD_EXACT, &solver, NULL) == GS_OK);
    for (uint32_t s = 0; s < ns; ++s) {
        src[s] = (uint32_t)(((uint64_t)s * 7919u + 3) % nv);
        gs_source so = gs_source_vertex(src[s]);
        CHECK(gs_solver_solve(solver, &so, 1, 0, d + (size_t)s * nv, NULL) == GS_OK);
    }
    gs_solver_free(solver);
    gs_patch_free(patch);
    return d;
}

/* Mean ME over the sources, checking bounds, symmetry, d(x,x) and field. */
static double check_land(const gs_land *l, const double *ex, const uint32_t *src, uint32_t ns, uint32_t nv)
{
    double me = 0, *field = malloc(sizeof *field * nv);
    int bound_fail = 0, sym_fail = 0;
    for (uint32_t s = 0; s < ns; ++s) {
        uint32_t x = src[s];
        const double *d = ex + (size_t)s * nv;
        CHECK(gs_land_field(l, x, field, NULL) == GS_OK);
        for (uint32_t y = 0; y < nv; ++y) {
            double lo, up, e = gs_land_distance(l, x, y);
            CHECK(gs_land_bounds(l, x, y, &lo, &up, NULL) == GS_OK);
            if (!(lo <= d[y] * (1 + 1e-9) + 1e-12 && d[y] <= up * (1 + 1e-9) + 1e-12)) bound_fail++;
            if (e != gs_land_distance(l, y, x) || e != field[y] || e != lo) sym_fail++;
        }
        CHECK(field[x] == 0);
        gs_field_errors fe;
        CHECK(gs_field_errors_compute(d, field, nv, x, &fe, NULL) == GS_OK);
        CHECK(fe.n_invalid == 0);
        me += fe.me / ns;
    }
    CHECK_MSG(bound_fail == 0, "%d pairs outside [lower, upper]", bound_fail);
    CHECK_MSG(sym_fail == 0, "%d pairs asymmetric or field != single", sym_fail);
    free(field);
    return me;
}

static void test_mesh(const char *spec, uint32_t m_small, uint32_t m_big, double me_big_max)
{
    gs_mesh *mesh = NULL;
    CHECK(gs_mesh_generate(spec, &mesh, NULL) == GS_OK);
    if (!mesh) return;
    uint32_t nv = gs_mesh_num_vertices(mesh), ns = 12, src[12];
    double *ex = exact_fields(mesh, ns, src);
    gs_land *a = NULL, *b = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_land_build(mesh, m_small, GS_METHOD_EXACT, &a, &err) == GS_OK, "%s", err.message);
    CHECK_MSG(gs_land_build(mesh, m_big, GS_METHOD_EXACT, &b, &err) == GS_OK, "%s", err.message);
    if (a && b) {
        CHECK(gs_land_num_landmarks(a) == m_small && gs_land_num_landmarks(b) == m_big);
        CHECK(gs_land_num_vertices(b) == nv);
        const uint32_t *la = gs_land_landmarks(a), *lb = gs_land_landmarks(b);
        CHECK(la[0] == 0 && memcmp(la, lb, m_small * sizeof *la) == 0); /* FPS is nested */
        for (uint32_t i = 0; i < m_big; ++i)
            for (uint32_t j = 0; j < i; ++j) CHECK(lb[i] != lb[j]);
        double me_a = check_land(a, ex, src, ns, nv), me_b = check_land(b, ex, src, ns, nv);
        printf("%s: LAND ME %.2f%% (m=%u), %.2f%% (m=%u)\n", spec, 100 * me_a, m_small, 100 * me_b, m_big);
        CHECK(me_b <= me_a + 1e-12); /* more landmarks: pointwise larger lower bound */
        CHECK(me_b < me_big_max);
        /* a landmark's own field is exact */
        double *d = malloc(sizeof *d * nv);
        gs_source so = gs_source_vertex(lb[1]);
        gs_patch *p = NULL;
        CHECK(gs_patch_create(mesh, NULL, 0, &p, NULL) == GS_OK);
        CHECK(gs_distance_field(p, GS_METHOD_EXACT, &so, 1, 0, d, NULL) == GS_OK);
        for (uint32_t y = 0; y < nv; ++y) CHECK_NEAR(gs_land_distance(b, lb[1], y), d[y], 1e-12 * (1 + d[y]));
        gs_patch_free(p);
        free(d);
        CHECK(isnan(gs_land_distance(b, nv, 0)) && gs_land_bounds(b, 0, nv, NULL, NULL, &err) == GS_EARG);
        CHECK(gs_land_field(b, nv, ex, &err) == GS_EARG);
    }
    gs_land_free(a);
    gs_land_free(b);
    free(ex);
    gs_mesh_free(mesh);
}

static void test_components(void)
{
    gs_mesh *mesh = NULL;
    CHECK(gs_mesh_generate("two:5", &mesh, NULL) == GS_OK);
    if (!mesh) return;
    gs_land *l = NULL;
    CHECK(gs_land_build(mesh, 2, GS_METHOD_EXACT, &l, NULL) == GS_OK);
    if (l) {
        const uint32_t *lm = gs_land_landmarks(l);
        CHECK(lm[0] == 0 && lm[1] >= 25); /* the unreached component next */
        CHECK(gs_land_distance(l, 0, 30) == INFINITY && gs_land_distance(l, 30, 0) == INFINITY);
        CHECK(isfinite(gs_land_distance(l, 30, 31)) && isfinite(gs_land_distance(l, 1, 2)));
    }
    gs_land_free(l);
    gs_error err;
    CHECK(gs_land_build(mesh, 0, GS_METHOD_EXACT, &l, &err) == GS_EARG && l == NULL);
    CHECK(gs_land_build(mesh, 51, GS_METHOD_EXACT, &l, &err) == GS_EARG && l == NULL);
    CHECK(gs_land_build(NULL, 2, GS_METHOD_EXACT, &l, &err) == GS_EARG);
    gs_land_free(NULL);
    gs_mesh_free(mesh);
}

int main(void)
{
    test_mesh("grid:20,20", 4, 16, 0.25);
    test_mesh("sphere:2", 4, 16, 0.25);
    test_components();
    return gs__test_finish("test_land");
}
