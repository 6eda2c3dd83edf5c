/* test_pivots.c - separator curves through sharp saddles (src/pipeline/
 * curves.c, "pivots"): a closed plate with two square holes through it
 * (genus 2, the holes' corners are saddles of angle excess pi / 2 on its
 * top and bottom faces), built with the defaults. Shortest paths round a
 * hole bend at those corners; a curve passing a corner at a distance answered
 * them through points off the corner, too long. Against the exact solver
 * from every third vertex: before pivots 65 pairs were over by more than
 * 2.1% (the largest 2.44%); now none (the largest
 * 1.99%: the near pairs' own tolerance is 2%). Underestimates come from fits
 * dipping between samples, another matter (2.1% before, 2.8% now: the
 * curves' pieces moved); checked against the 5% target only. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The plate: the cells (i, j) of an N x N grid of [0,1]^2 outside the holes,
 * each split into two triangles (diagonals alternating), on top at z = +T
 * and (reversed) at the bottom, z = -T; walls of W layers along every
 * boundary edge. The vertices no face uses are dropped. */
enum { N = 24, W = 2 };
#define T 0.1
static const int holes[2][4] = {{5, 10, 7, 17}, {14, 19, 7, 17}}; /* i0, i1, j0, j1 */

static int in_hole(int i, int j)
{
    for (int h = 0; h < 2; ++h)
        if (i >= holes[h][0] && i < holes[h][1] && j >= holes[h][2] && j < holes[h][3]) return 1;
    return 0;
}

static gs_mesh *plate(void)
{
    const uint32_t nt = (N + 1) * (N + 1), nl = W + 1;
    uint32_t *top = malloc(sizeof *top * 6 * N * N), nf_top = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            if (in_hole(i, j)) continue;
            uint32_t a = j * (N + 1) + i, b = a + 1, c = a + N + 2, d = a + N + 1;
            uint32_t t[6] = {a, b, c, a, c, d}, u[6] = {a, b, d, b, c, d};
            memcpy(top + 3 * nf_top, (i + j) % 2 == 0 ? t : u, sizeof t);
            nf_top += 2;
        }
    /* boundary edges of the top: directed edges without their twin */
    uint32_t *be = malloc(sizeof *be * 2 * 3 * nf_top), nb = 0;
    for (uint32_t f = 0; f < nf_top; ++f)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = top[3 * f + k], b = top[3 * f + (k + 1) % 3];
            int twin = 0;
            for (uint32_t g = 0; g < nf_top && !twin; ++g)
                for (int q = 0; q < 3; ++q)
                    if (top[3 * g + q] == b && top[3 * g + (q + 1) % 3] == a) twin = 1;
            if (!twin) be[2 * nb] = a, be[2 * nb + 1] = b, nb++;
        }
    uint32_t nf = 2 * nf_top + 2 * W * nb;
    uint32_t *tri = malloc(sizeof *tri * 3 * nf), f = 0;
    double *xyz = malloc(sizeof *xyz * 3 * nt * nl);
    for (uint32_t l = 0; l < nl; ++l)
        for (uint32_t v = 0; v < nt; ++v) {
            double *p = xyz + 3 * (l * nt + v);
            p[0] = (double)(v % (N + 1)) / N, p[1] = (double)(v / (N + 1)) / N, p[2] = T - 2.0 * T * l / W;
        }
    for (uint32_t g = 0; g < nf_top; ++g, ++f) memcpy(tri + 3 * f, top + 3 * g, 3 * sizeof *tri);
    for (uint32_t g = 0; g < nf_top; ++g, ++f)
        tri[3 * f] = top[3 * g] + W * nt, tri[3 * f + 1] = top[3 * g + 2] + W * nt, tri[3 * f + 2] = top[3 * g + 1] + W * nt;
    for (uint32_t e = 0; e < nb; ++e)
        for (uint32_t l = 0; l < W; ++l) {
            uint32_t a0 = be[2 * e] + l * nt, b0 = be[2 * e + 1] + l * nt, a1 = a0 + nt, b1 = b0 + nt;
            uint32_t q[6] = {b0, a0, a1, b0, a1, b1};
            memcpy(tri + 3 * f, q, sizeof q);
            f += 2;
        }
    /* drop the unused vertices */
    uint32_t *map = malloc(sizeof *map * nt * nl), nv = 0;
    for (uint32_t v = 0; v < nt * nl; ++v) map[v] = UINT32_MAX;
    for (uint32_t k = 0; k < 3 * nf; ++k) map[tri[k]] = 0;
    for (uint32_t v = 0; v < nt * nl; ++v)
        if (map[v] == 0) {
            memmove(xyz + 3 * nv, xyz + 3 * v, 3 * sizeof *xyz);
            map[v] = nv++;
        }
    for (uint32_t k = 0; k < 3 * nf; ++k) tri[k] = map[tri[k]];
    gs_mesh *m = NULL;
    gs_error e = {0};
    CHECK_MSG(gs_mesh_create(xyz, nv, tri, nf, &m, &e) == GS_OK, "plate: %s", e.message);
    free(top), free(be), free(tri), free(xyz), free(map);
    return m;
}

int main(void)
{
    gs_mesh *m = plate();
    gs_db *db = NULL;
    gs_patch *whole = NULL;
    gs_solver *s = NULL;
    gs_build_options o;
    gs_build_options_default(&o);
    gs_error e = {0};
    if (!m) return gs__test_finish("test_pivots");
    gs_mesh_report r;
    CHECK(gs_mesh_get_report(m, &r, NULL) == GS_OK);
    CHECK_MSG(r.genus == 2 && r.n_components == 1 && r.n_boundary_loops == 0, "plate: genus %d, %u components",
              r.genus, r.n_components);
    CHECK_MSG(gs_db_build(m, &o, &db, NULL, &e) == GS_OK, "plate: build: %s", e.message);
    CHECK(gs_patch_create(m, NULL, 0, &whole, NULL) == GS_OK);
    CHECK(whole && gs_solver_create(whole, GS_METHOD_EXACT, &s, NULL) == GS_OK);
    uint32_t n = gs_mesh_num_vertices(m), over = 0, pairs = 0;
    double *ex = malloc(sizeof *ex * n), *got = malloc(sizeof *got * n), worst_over = 0, worst_under = 0, sum = 0;
    for (uint32_t x = 0; db && s && x < n; x += 3) {
        gs_source src = gs_source_vertex(x);
        CHECK(gs_solver_solve(s, &src, 1, 0, ex, NULL) == GS_OK && gs_db_field(db, x, got, NULL) == GS_OK);
        for (uint32_t y = 0; y < n; ++y) {
            if (!(ex[y] > 0)) continue;
            double rel = (got[y] - ex[y]) / ex[y];
            over += rel > 0.021;
            worst_over = fmax(worst_over, rel), worst_under = fmax(worst_under, -rel);
            sum += fabs(rel), pairs++;
        }
    }
    printf("  plate with two square holes (%u vertices): %u pairs, mean error %.3f%%, largest over %.2f%%, under "
           "%.2f%%, %u over by more than 2.1%%\n",
           n, pairs, 100 * sum / (pairs ? pairs : 1), 100 * worst_over, 100 * worst_under, over);
    CHECK_MSG(pairs > 0 && over == 0, "plate: %u pairs over by more than 2.1%% (largest %.2f%%): paths round the holes' "
              "corners answered off the corners?", over, 100 * worst_over);
    CHECK_MSG(worst_under <= 0.05, "plate: an underestimate of %.2f%%", 100 * worst_under);
    free(ex), free(got);
    gs_solver_free(s);
    gs_patch_free(whole);
    gs_db_free(db);
    gs_mesh_free(m);
    return gs__test_finish("test_pivots");
}
