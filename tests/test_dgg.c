/* test_dgg.c - discrete geodesic graphs (GS_METHOD_DGG): known answers on
 * flat grids (Euclidean distances: exact within the local radius, upper
 * bounds everywhere, within the error targets), agreement with the exact
 * solver on curved generated meshes and on patches (d_P), surface-point
 * sources, several sources, max_distance, options, thread independence,
 * the pruning's guarantee (within 1 + eps of the unpruned graph), views
 * of a whole mesh's graph on a patch (the builder's), and the shared
 * ground truth: every source of every file within the targets ME 0.1% and
 * max 1% (skipped with a reason when absent).
 * GEOSEP_QUICK=1: shared meshes over 20k vertices are skipped, the others
 * checked from their first 4 sources. */
#include "check.h"
#include "geodesic/geodesic_internal.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

static double dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double mean_edge(const gs_mesh *m)
{
    const double *x = gs_mesh_positions(m);
    const uint32_t *f = gs_mesh_faces(m);
    double s = 0;
    uint32_t nf = gs_mesh_num_faces(m);
    for (uint32_t i = 0; i < nf; ++i)
        for (int k = 0; k < 3; ++k) s += dist3(x + 3 * (size_t)f[3 * i + k], x + 3 * (size_t)f[3 * i + (k + 1) % 3]);
    return s / (3.0 * nf);
}

/* Flat grid: the exact distances are Euclidean. */
static void test_plane(void)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    CHECK(gs_mesh_generate("grid:60,60", &m, &err) == GS_OK);
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    gs_solver_options o;
    gs_solver_options_default(&o);
    CHECK(o.dgg_eps == 1e-3);
    CHECK(gs_solver_create_ex(p, GS_METHOD_DGG, &o, &s, &err) == GS_OK);
    uint32_t nv = gs_mesh_num_vertices(m);
    const double *x = gs_mesh_positions(m);
    double R = gs_dgg_radius(o.dgg_eps) * mean_edge(m);
    double *d = malloc(nv * sizeof *d);
    const uint32_t srcs[3] = {0, 1830, 3599 - 17};
    double worst = 0, me_max = 0;
    for (int j = 0; j < 3; ++j) {
        gs_source src = gs_source_vertex(srcs[j]);
        CHECK(gs_solver_solve(s, &src, 1, 0, d, &err) == GS_OK);
        CHECK(d[srcs[j]] == 0);
        double me = 0;
        uint32_t bad_lb = 0, bad_near = 0;
        for (uint32_t v = 0; v < nv; ++v) {
            double e = dist3(x + 3 * (size_t)v, x + 3 * (size_t)srcs[j]);
            if (d[v] < e * (1 - 1e-12)) bad_lb++;
            if (e <= R * 0.999 && fabs(d[v] - e) > 1e-12 * (1 + e)) bad_near++;
            if (e > 0) {
                double r = d[v] / e - 1;
                me += r / (nv - 1);
                if (r > worst) worst = r;
            }
        }
        CHECK_MSG(bad_lb == 0, "plane source %u: %u values below the Euclidean distance", srcs[j], bad_lb);
        CHECK_MSG(bad_near == 0, "plane source %u: %u vertices within R not exact", srcs[j], bad_near);
        if (me > me_max) me_max = me;
    }
    printf("plane grid:60,60  ME %.5f%%  max %.4f%%\n", 100 * me_max, 100 * worst);
    CHECK_MSG(me_max < 1e-3, "plane ME %g", me_max);
    CHECK_MSG(worst < 1e-2, "plane max %g", worst);

    /* a surface point: Euclidean again, exact nearby */
    gs_source sp = gs_source_point(2000, 0.2, 0.3, 0.5);
    CHECK(gs_solver_solve(s, &sp, 1, 0, d, &err) == GS_OK);
    const uint32_t *f = gs_mesh_faces(m);
    double q[3];
    for (int k = 0; k < 3; ++k)
        q[k] = 0.2 * x[3 * f[6000] + k] + 0.3 * x[3 * f[6001] + k] + 0.5 * x[3 * f[6002] + k];
    uint32_t bad = 0, bad_near = 0;
    double worst_p = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        double e = dist3(x + 3 * (size_t)v, q);
        if (d[v] < e * (1 - 1e-12)) bad++;
        if (e <= R * 0.999 && fabs(d[v] - e) > 1e-12 * (1 + e)) bad_near++;
        if (e > 0 && d[v] / e - 1 > worst_p) worst_p = d[v] / e - 1;
    }
    CHECK_MSG(bad == 0 && bad_near == 0, "surface point: %u below, %u not exact within R", bad, bad_near);
    CHECK_MSG(worst_p < 1e-2, "surface point max %g", worst_p);

    /* two sources: the minimum of the two fields */
    double *a = malloc(nv * sizeof *a), *b = malloc(nv * sizeof *b);
    gs_source two[2] = {gs_source_vertex(0), gs_source_vertex(3599)};
    CHECK(gs_solver_solve(s, &two[0], 1, 0, a, &err) == GS_OK);
    CHECK(gs_solver_solve(s, &two[1], 1, 0, b, &err) == GS_OK);
    CHECK(gs_solver_solve(s, two, 2, 0, d, &err) == GS_OK);
    uint32_t bad_min = 0;
    for (uint32_t v = 0; v < nv; ++v) bad_min += d[v] != fmin(a[v], b[v]);
    CHECK_MSG(bad_min == 0, "two sources: %u vertices differ from the minimum", bad_min);

    /* max_distance: every vertex within it as unbounded, the others beyond */
    CHECK(gs_solver_solve(s, &two[0], 1, 0.3, d, &err) == GS_OK);
    uint32_t bad_max = 0;
    for (uint32_t v = 0; v < nv; ++v)
        if (a[v] <= 0.3 ? d[v] != a[v] : !(d[v] > 0.3)) bad_max++;
    CHECK_MSG(bad_max == 0, "max_distance: %u vertices wrong", bad_max);
    free(a);
    free(b);
    free(d);
    gs_solver_free(s);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* Curved meshes: against the exact solver (upper bound, error targets). */
static void test_vs_exact(const char *spec, double eps)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_solver *se = NULL, *sd = NULL;
    CHECK(gs_mesh_generate(spec, &m, &err) == GS_OK);
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    gs_solver_options o;
    gs_solver_options_default(&o);
    o.dgg_eps = eps;
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &se, &err) == GS_OK);
    CHECK(gs_solver_create_ex(p, GS_METHOD_DGG, &o, &sd, &err) == GS_OK);
    uint32_t nv = gs_mesh_num_vertices(m);
    double *de = malloc(nv * sizeof *de), *dd = malloc(nv * sizeof *dd);
    uint32_t srcs[4];
    CHECK(gs_mesh_random_vertices(m, 4, 7, srcs, &err) == GS_OK);
    double me = 0, mx = 0;
    uint32_t below = 0;
    for (int j = 0; j < 4; ++j) {
        gs_source src = gs_source_vertex(srcs[j]);
        CHECK(gs_solver_solve(se, &src, 1, 0, de, &err) == GS_OK);
        CHECK(gs_solver_solve(sd, &src, 1, 0, dd, &err) == GS_OK);
        gs_field_errors fe;
        CHECK(gs_field_errors_compute(de, dd, nv, srcs[j], &fe, &err) == GS_OK);
        me += fe.me / 4;
        if (fe.max > mx) mx = fe.max;
        for (uint32_t v = 0; v < nv; ++v) below += dd[v] < de[v] * (1 - 1e-10);
    }
    printf("%-16s eps %g  ME %.5f%%  max %.4f%%\n", spec, eps, 100 * me, 100 * mx);
    CHECK_MSG(below == 0, "%s: %u values below the exact distance", spec, below);
    CHECK_MSG(me < 1e-3, "%s: ME %g", spec, me);
    CHECK_MSG(mx < 1e-2, "%s: max %g", spec, mx);
    free(de);
    free(dd);
    gs_solver_free(se);
    gs_solver_free(sd);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* A patch: a grid with a wall cut out; dgg honours d_P (distances inside the
 * patch), never shorter than the exact patch distances, never crossing the gap. */
static void test_patch(void)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_solver *se = NULL, *sd = NULL;
    CHECK(gs_mesh_generate("grid:40,40", &m, &err) == GS_OK);
    const double *x = gs_mesh_positions(m);
    const uint32_t *f = gs_mesh_faces(m);
    uint32_t nf = gs_mesh_num_faces(m), k = 0;
    uint32_t *keep = malloc(nf * sizeof *keep);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v)
        for (int c = 0; c < 3; ++c) lo[c] = fmin(lo[c], x[3 * v + c]), hi[c] = fmax(hi[c], x[3 * v + c]);
    for (uint32_t i = 0; i < nf; ++i) {
        double cx = 0, cy = 0;
        for (int c = 0; c < 3; ++c) cx += x[3 * f[3 * i + c]] / 3, cy += x[3 * f[3 * i + c] + 1] / 3;
        double u = (cx - lo[0]) / (hi[0] - lo[0]), w = (cy - lo[1]) / (hi[1] - lo[1]);
        /* a thin wall at u ~ 0.5 from w = 0 to 0.8 */
        if (!(u > 0.47 && u < 0.53 && w < 0.8)) keep[k++] = i;
    }
    CHECK(gs_patch_create(m, keep, k, &p, &err) == GS_OK);
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &se, &err) == GS_OK);
    CHECK(gs_solver_create(p, GS_METHOD_DGG, &sd, &err) == GS_OK);
    uint32_t nv = gs_patch_num_vertices(p);
    double *de = malloc(nv * sizeof *de), *dd = malloc(nv * sizeof *dd);
    gs_source src = gs_source_vertex(gs_patch_vertex_from_mesh(p, 0));
    CHECK(gs_solver_solve(se, &src, 1, 0, de, &err) == GS_OK);
    CHECK(gs_solver_solve(sd, &src, 1, 0, dd, &err) == GS_OK);
    uint32_t below = 0, inf_mismatch = 0;
    double mx = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        if (isinf(de[v]) != isinf(dd[v])) inf_mismatch++;
        if (!isfinite(de[v]) || de[v] == 0) continue;
        if (dd[v] < de[v] * (1 - 1e-10)) below++;
        mx = fmax(mx, dd[v] / de[v] - 1);
    }
    printf("patch (grid with a wall)  max %.4f%%\n", 100 * mx);
    CHECK_MSG(below == 0, "patch: %u values below d_P", below);
    CHECK(inf_mismatch == 0);
    CHECK_MSG(mx < 1e-2, "patch: max %g", mx);
    free(keep);
    free(de);
    free(dd);
    gs_solver_free(se);
    gs_solver_free(sd);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* Options are checked; the graph and so the fields do not depend on threads. */
static void test_options_threads(void)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    CHECK(gs_mesh_generate("torus:40,16", &m, &err) == GS_OK);
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    gs_solver_options o;
    gs_solver_options_default(&o);
    o.dgg_eps = 0;
    CHECK(gs_solver_create_ex(p, GS_METHOD_DGG, &o, &s, &err) == GS_EARG && strstr(err.message, "dgg_eps"));
    o.dgg_eps = NAN;
    CHECK(gs_solver_create_ex(p, GS_METHOD_DGG, &o, &s, &err) == GS_EARG && s == NULL);
    o.dgg_eps = 0.6;
    CHECK(gs_solver_create_ex(p, GS_METHOD_DGG, &o, &s, &err) == GS_EARG);
    CHECK(gs_dgg_radius(1e-2) < gs_dgg_radius(1e-3) && gs_dgg_radius(1e-3) < gs_dgg_radius(1e-4));
    uint32_t nv = gs_mesh_num_vertices(m);
    double *a = malloc(nv * sizeof *a), *b = malloc(nv * sizeof *b);
    gs_source src = gs_source_point(17, 0.1, 0.1, 0.8);
#ifdef _OPENMP
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
#endif
    CHECK(gs_solver_create(p, GS_METHOD_DGG, &s, &err) == GS_OK);
    CHECK(gs_solver_solve(s, &src, 1, 0, a, &err) == GS_OK);
    gs_solver_free(s);
#ifdef _OPENMP
    omp_set_num_threads(3);
#endif
    CHECK(gs_solver_create(p, GS_METHOD_DGG, &s, &err) == GS_OK);
    CHECK(gs_solver_solve(s, &src, 1, 0, b, &err) == GS_OK);
    CHECK(gs_solver_solve(s, &src, 1, 0, b, &err) == GS_OK); /* reuse */
#ifdef _OPENMP
    omp_set_num_threads(saved);
#endif
    CHECK(memcmp(a, b, nv * sizeof *a) == 0);
    free(a);
    free(b);
    gs_solver_free(s);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* Pruning: the pruned graph's fields lie within 1 + eps of the unpruned
 * graph's (and never below them: it is a subgraph, the same start), with
 * fewer edges; both are exact within the start radius (6 R) and upper
 * bounds of the exact distances. Threads: the same graph and fields for 1
 * and 3 construction threads. */
static void test_prune(const char *spec, double eps)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_solver *se = NULL, *sp = NULL, *sf = NULL, *s3 = NULL;
    CHECK(gs_mesh_generate(spec, &m, &err) == GS_OK);
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    gs_solver_options o;
    gs_solver_options_default(&o);
    o.dgg_eps = eps;
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &se, &err) == GS_OK);
    CHECK(gs__solver_create_dgg(p, &o, 1, 1, NULL, &sp, &err) == GS_OK);
    CHECK(gs__solver_create_dgg(p, &o, 1, 0, NULL, &sf, &err) == GS_OK);
    CHECK(gs__solver_create_dgg(p, &o, 3, 1, NULL, &s3, &err) == GS_OK);
    gs__dgg_stats a, b, c;
    CHECK(gs__solver_dgg_info(sp, &a, &err) == GS_OK && gs__solver_dgg_info(sf, &b, &err) == GS_OK &&
          gs__solver_dgg_info(s3, &c, &err) == GS_OK);
    CHECK(gs__solver_dgg_info(se, &c, &err) == GS_EARG);
    CHECK(gs__solver_dgg_info(s3, &c, &err) == GS_OK);
    CHECK_MSG(a.candidates == b.candidates && b.edges == b.candidates && a.edges < b.edges,
              "%s: %llu candidates, %llu / %llu edges", spec, (unsigned long long)a.candidates,
              (unsigned long long)a.edges, (unsigned long long)b.edges);
    CHECK(c.edges == a.edges && c.candidates == a.candidates);
    uint32_t nv = gs_mesh_num_vertices(m);
    double *de = malloc(nv * sizeof *de), *dp = malloc(nv * sizeof *dp), *df = malloc(nv * sizeof *df),
           *d3 = malloc(nv * sizeof *d3);
    uint32_t srcs[4];
    CHECK(gs_mesh_random_vertices(m, 4, 3, srcs, &err) == GS_OK);
    uint32_t bad_eps = 0, bad_sub = 0, bad_start = 0, below = 0, differ = 0;
    double worst = 0;
    for (int j = 0; j < 4; ++j) {
        gs_source src = gs_source_vertex(srcs[j]);
        CHECK(gs_solver_solve(se, &src, 1, 0, de, &err) == GS_OK);
        CHECK(gs_solver_solve(sp, &src, 1, 0, dp, &err) == GS_OK);
        CHECK(gs_solver_solve(sf, &src, 1, 0, df, &err) == GS_OK);
        CHECK(gs_solver_solve(s3, &src, 1, 0, d3, &err) == GS_OK);
        differ += memcmp(dp, d3, nv * sizeof *dp) != 0;
        for (uint32_t v = 0; v < nv; ++v) {
            if (dp[v] > (1 + eps) * df[v] * (1 + 1e-12)) bad_eps++;
            if (dp[v] < df[v] * (1 - 1e-12)) bad_sub++;
            if (df[v] < de[v] * (1 - 1e-10)) below++;
            if (de[v] <= 6 * a.radius * 0.999 && fabs(dp[v] - de[v]) > 1e-9 * (1 + de[v])) bad_start++;
            if (df[v] > 0) worst = fmax(worst, dp[v] / df[v] - 1);
        }
    }
    printf("%-16s eps %g: %.1f candidates, %.1f edges per vertex; pruned / unpruned - 1 <= %.5f%%\n", spec, eps,
           (double)a.candidates / nv, (double)a.edges / nv, 100 * worst);
    CHECK_MSG(bad_eps == 0, "%s: %u values above (1 + eps) x unpruned", spec, bad_eps);
    CHECK_MSG(bad_sub == 0, "%s: %u values below the unpruned graph's", spec, bad_sub);
    CHECK_MSG(below == 0, "%s: %u values below the exact distance", spec, below);
    CHECK_MSG(bad_start == 0, "%s: %u vertices within 6 R not exact", spec, bad_start);
    CHECK_MSG(differ == 0, "%s: 1 and 3 construction threads give different fields", spec);
    free(de), free(dp), free(df), free(d3);
    gs_solver_free(se), gs_solver_free(sp), gs_solver_free(sf), gs_solver_free(s3);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* Views (what gs_db_build does): the whole grid's graph, restricted to a
 * patch with a wall cut out. A view's edges may cross the wall's gap (their
 * geodesics leave the patch), so its fields lie between d_M (Euclidean here)
 * and d_P, never below d_M; every patch vertex is reached; sizes checked. */
static void test_view(void)
{
    gs_error err;
    gs_mesh *m = NULL;
    gs_patch *whole = NULL, *p = NULL, *tiny = NULL;
    gs_solver *sw = NULL, *sv = NULL, *sc = NULL, *se = NULL, *st = NULL;
    CHECK(gs_mesh_generate("grid:40,40", &m, &err) == GS_OK);
    const double *x = gs_mesh_positions(m);
    const uint32_t *f = gs_mesh_faces(m);
    uint32_t nf = gs_mesh_num_faces(m), k = 0;
    uint32_t *keep = malloc(nf * sizeof *keep);
    for (uint32_t i = 0; i < nf; ++i) {
        double cx = 0, cy = 0;
        for (int c = 0; c < 3; ++c) cx += x[3 * f[3 * i + c]] / 3, cy += x[3 * f[3 * i + c] + 1] / 3;
        if (!(cx > 0.47 && cx < 0.53 && cy < 0.8)) keep[k++] = i; /* grid:40,40 spans [0,1]^2 */
    }
    CHECK(k < nf);
    CHECK(gs_patch_create(m, NULL, 0, &whole, &err) == GS_OK);
    CHECK(gs_patch_create(m, keep, k, &p, &err) == GS_OK);
    CHECK(gs_patch_create(m, keep, 6, &tiny, &err) == GS_OK); /* binary-search map */
    CHECK(gs__solver_create_dgg(whole, NULL, 2, 1, NULL, &sw, &err) == GS_OK);
    CHECK(gs__solver_dgg_view(sw, p, &sv, &err) == GS_OK);
    CHECK(gs__solver_clone(sv, &sc, &err) == GS_OK);
    CHECK(gs__solver_dgg_view(sw, tiny, &st, &err) == GS_OK);
    CHECK(gs__solver_dgg_view(sv, p, &se, &err) == GS_EARG && se == NULL); /* a view of a view */
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &se, &err) == GS_OK);
    uint32_t nv = gs_patch_num_vertices(p);
    double *dv = malloc(nv * sizeof *dv), *dc = malloc(nv * sizeof *dc), *dp = malloc(nv * sizeof *dp);
    uint32_t s0 = gs_patch_vertex_from_mesh(p, 0);
    gs_source src = gs_source_vertex(s0);
    CHECK(gs_solver_solve(sv, &src, 1, 0, dv, &err) == GS_OK);
    CHECK(gs_solver_solve(sc, &src, 1, 0, dc, &err) == GS_OK);
    CHECK(gs_solver_solve(se, &src, 1, 0, dp, &err) == GS_OK);
    CHECK(memcmp(dv, dc, nv * sizeof *dv) == 0);
    uint32_t below_m = 0, above_p = 0, unreached = 0, shorter = 0;
    const double *x0 = x + 3 * (size_t)0;
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t mv = gs_patch_vertex_to_mesh(p, v);
        double e = dist3(x + 3 * (size_t)mv, x0);
        if (!isfinite(dv[v])) unreached++;
        if (dv[v] < e * (1 - 1e-12)) below_m++;
        if (dv[v] > dp[v] * 1.01) above_p++;
        if (dv[v] < dp[v] * (1 - 1e-6)) shorter++;
    }
    printf("view of a grid's graph on a patch with a wall: %u of %u vertices shorter than d_P (edges across the gap)\n",
           shorter, nv);
    CHECK_MSG(unreached == 0 && below_m == 0 && above_p == 0, "view: %u unreached, %u below d_M, %u above 1.01 d_P",
              unreached, below_m, above_p);
    /* the tiny patch: its own vertices only */
    uint32_t nt = gs_patch_num_vertices(tiny);
    double *dt = malloc(nt * sizeof *dt);
    gs_source s1 = gs_source_vertex(0);
    CHECK(gs_solver_solve(st, &s1, 1, 0, dt, &err) == GS_OK);
    uint32_t bad_t = 0;
    for (uint32_t v = 0; v < nt; ++v) {
        double e = dist3(x + 3 * (size_t)gs_patch_vertex_to_mesh(tiny, v), x + 3 * (size_t)gs_patch_vertex_to_mesh(tiny, 0));
        if (!(fabs(dt[v] - e) <= 1e-12 * (1 + e))) bad_t++; /* within R: exact */
    }
    CHECK_MSG(bad_t == 0, "tiny view: %u of %u vertices not exact", bad_t, nt);
    free(dt);
    /* the whole mesh as a view: the graph shared (identity patch) or copied
     * (every face listed: a sub-graph of all vertices) gives the same fields,
     * exact within R, never below d_M */
    {
        gs_patch *all = NULL;
        gs_solver *s_id = NULL, *s_all = NULL;
        uint32_t *allf = malloc(nf * sizeof *allf);
        for (uint32_t i = 0; i < nf; ++i) allf[i] = i;
        CHECK(gs_patch_create(m, allf, nf, &all, &err) == GS_OK);
        CHECK(gs__solver_dgg_view(sw, whole, &s_id, &err) == GS_OK);
        CHECK(gs__solver_dgg_view(sw, all, &s_all, &err) == GS_OK);
        uint32_t nw = gs_mesh_num_vertices(m);
        CHECK(gs_patch_num_vertices(all) == nw);
        double *d1 = malloc(nw * sizeof *d1), *d2 = malloc(nw * sizeof *d2);
        gs__dgg_stats st;
        CHECK(gs__solver_dgg_info(sw, &st, &err) == GS_OK);
        uint32_t sid = 817, bad_w = 0;
        gs_source sv0 = gs_source_vertex(sid);
        CHECK(gs_solver_solve(s_id, &sv0, 1, 0, d1, &err) == GS_OK);
        sv0 = gs_source_vertex(gs_patch_vertex_from_mesh(all, sid));
        CHECK(gs_solver_solve(s_all, &sv0, 1, 0, d2, &err) == GS_OK);
        for (uint32_t v = 0; v < nw; ++v) {
            double e = dist3(x + 3 * (size_t)v, x + 3 * (size_t)sid);
            double a2 = d2[gs_patch_vertex_from_mesh(all, v)];
            if (d1[v] != a2 || d1[v] < e * (1 - 1e-12) || (e <= st.radius * 0.999 && fabs(d1[v] - e) > 1e-12 * (1 + e)))
                bad_w++;
        }
        CHECK_MSG(bad_w == 0, "whole-mesh views: %u of %u vertices differ, below d_M or not exact within R", bad_w, nw);
        free(d1), free(d2), free(allf);
        gs_solver_free(s_id), gs_solver_free(s_all);
        gs_patch_free(all);
    }
    free(keep), free(dv), free(dc), free(dp);
    gs_solver_free(sc), gs_solver_free(sv), gs_solver_free(st), gs_solver_free(se), gs_solver_free(sw);
    gs_patch_free(tiny), gs_patch_free(p), gs_patch_free(whole);
    gs_mesh_free(m);
}

static int test_shared_mesh(const char *name, int quick)
{
    char obj[4096], gtp[4096];
    if (!gs__test_shared_pair(name, obj, gtp, sizeof obj)) return 0;
    gs_error err;
    gs_mesh *m = NULL;
    gs_gt *gt = NULL;
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    double *d = NULL;
    int tested = 0;
    if (gs_mesh_load(obj, GS_FORMAT_AUTO, &m, &err)) {
        CHECK_MSG(0, "%s: %s", obj, err.message);
        return 0;
    }
    if (quick && gs_mesh_num_vertices(m) > 20000) { /* the graph: ~0.05 ms of CPU per vertex */
        printf("%-16s skipped (GEOSEP_QUICK, %u vertices)\n", name, gs_mesh_num_vertices(m));
        goto done;
    }
    if (gs_gt_read(gtp, &gt, &err) || gs_patch_create(m, NULL, 0, &p, &err) ||
        gs_solver_create(p, GS_METHOD_DGG, &s, &err)) {
        CHECK_MSG(0, "%s: %s", name, err.message);
        goto done;
    }
    uint32_t nv = gt->n_vertices;
    CHECK(nv == gs_mesh_num_vertices(m));
    if (nv != gs_mesh_num_vertices(m)) goto done;
    d = malloc(nv * sizeof *d);
    uint32_t n_src = quick && gt->n_sources > 4 ? 4 : gt->n_sources;
    double me = 0, mx = 0;
    uint32_t below = 0;
    for (uint32_t j = 0; j < n_src; ++j) {
        gs_source src = gs_source_vertex(gt->sources[j]);
        CHECK(gs_solver_solve(s, &src, 1, 0, d, &err) == GS_OK);
        const double *want = gt->dist + (size_t)j * nv;
        gs_field_errors fe;
        CHECK(gs_field_errors_compute(want, d, nv, gt->sources[j], &fe, &err) == GS_OK);
        CHECK(fe.n_invalid == 0);
        for (uint32_t v = 0; v < nv; ++v) {
            CHECK(isinf(d[v]) == isinf(want[v]));
            if (isfinite(want[v]) && d[v] < want[v] * (1 - 1e-9)) below++;
        }
        me += fe.me / n_src;
        if (fe.max > mx) mx = fe.max;
    }
    printf("%-16s %6u vertices %2u sources  dgg ME %.5f%%  max %.4f%%\n", name, nv, n_src, 100 * me, 100 * mx);
    CHECK_MSG(below == 0, "%s: %u values below the ground truth", name, below);
    /* the targets of issue 20 at the default eps */
    CHECK_MSG(me < 1e-3, "%s: dgg ME %g", name, me);
    CHECK_MSG(mx < 1e-2, "%s: dgg max %g", name, mx);
    tested = 1;
done:
    free(d);
    gs_solver_free(s);
    gs_patch_free(p);
    gs_gt_free(gt);
    gs_mesh_free(m);
    return tested;
}

static void test_shared(void)
{
    if (!gs__test_shared_path("meshes/bunny-5k.obj")) {
        printf("shared data absent (no meshes/bunny-5k.obj): ground-truth part skipped\n");
        return;
    }
    static char names[256][GS_TEST_NAME_MAX];
    int n_names = gs__test_shared_names(names, 256);
    if (n_names < 0) {
        printf("shared folder has no groundtruth/: ground-truth part skipped\n");
        return;
    }
    const char *q = getenv("GEOSEP_QUICK");
    int quick = q && strcmp(q, "1") == 0;
    int n = 0;
    for (int i = 0; i < n_names; ++i) n += test_shared_mesh(names[i], quick);
    CHECK(n > 0);
}

int main(void)
{
    test_plane();
    test_vs_exact("sphere:4", 1e-3);
    test_vs_exact("torus:60,24", 1e-3);
    test_vs_exact("peaks:40", 1e-3);
    test_patch();
    test_options_threads();
    test_prune("torus:60,24", 1e-3);
    test_prune("sphere:4", 1e-2);
    test_view();
    test_shared();
    return gs__test_finish("test_dgg");
}
