/* test_path.c - exact geodesic paths (gs_solver_path, gs_solver_trace):
 * known geodesics on generated meshes (plane, prism cylinder, truncated
 * pyramid, cube, plate with holes, graded needles flat and bent), the invariants of every path (length
 * equals the exact distance, points inside their faces, consecutive points
 * in one face, bends only at vertices on flat meshes, reverse paths as long),
 * errors, and the lengths of 1000 random paths per source against the shared
 * ground truth (skipped with a reason when ../shared is absent).
 * GEOSEP_QUICK=1: one source per shared mesh, meshes over 40k vertices
 * skipped (sanitizer builds). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REL 1e-9
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Every invariant of a path whose exact length is want (from src to dst
 * positions, when given). */
static void check_path(const gs_mesh *m, const gs_path *p, double want, const double *src, const double *dst,
                       const char *what)
{
    uint32_t n = gs_path_num_points(p);
    CHECK_MSG(n >= 1, "%s: empty path", what);
    if (n == 0) return;
    const double *x = gs_path_xyz(p), *b = gs_path_bary(p), *P = gs_mesh_positions(m);
    const uint32_t *f = gs_path_faces(p), *T = gs_mesh_faces(m);
    double len = 0;
    for (uint32_t i = 0; i < n; ++i) {
        CHECK_MSG(f[i] < gs_mesh_num_faces(m), "%s: point %u face %u", what, i, f[i]);
        if (f[i] >= gs_mesh_num_faces(m)) return;
        double s = b[3 * i] + b[3 * i + 1] + b[3 * i + 2];
        CHECK_MSG(b[3 * i] >= -1e-12 && b[3 * i + 1] >= -1e-12 && b[3 * i + 2] >= -1e-12 && fabs(s - 1) < 1e-12,
                  "%s: point %u bary %g %g %g", what, i, b[3 * i], b[3 * i + 1], b[3 * i + 2]);
        double q[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j) q[k] += b[3 * i + j] * P[3 * T[3 * f[i] + j] + k];
        CHECK_MSG(gs__test_dist3(q, x + 3 * i) <= 1e-12 * (1 + fabs(x[3 * i]) + fabs(x[3 * i + 1]) + fabs(x[3 * i + 2])),
                  "%s: point %u xyz is not its face point", what, i);
        if (i) {
            len += gs__test_dist3(x + 3 * i - 3, x + 3 * i);
            CHECK_MSG(gs__test_in_face(m, f[i - 1], x + 3 * i, 1e-9), "%s: point %u is not in face %u of point %u", what,
                      i, f[i - 1], i - 1);
        }
    }
    CHECK_NEAR(len, gs_path_length(p), 1e-12 * (1 + len));
    CHECK_MSG(fabs(gs_path_length(p) - want) <= REL * want + 1e-14, "%s: length %.17g, distance %.17g (rel %g)", what,
              gs_path_length(p), want, fabs(gs_path_length(p) - want) / want);
    if (src) CHECK_MSG(gs__test_dist3(x, src) <= 1e-12 * (1 + fabs(src[0]) + fabs(src[1]) + fabs(src[2])), "%s: starts elsewhere", what);
    if (dst) CHECK_MSG(gs__test_dist3(x + 3 * (n - 1), dst) <= 1e-12 * (1 + fabs(dst[0]) + fabs(dst[1]) + fabs(dst[2])), "%s: ends elsewhere", what);
}

/* On a flat mesh: the path is straight except at points that are vertices. */
static int flat_bends_at_vertices(const gs_path *p, int *n_bends)
{
    uint32_t n = gs_path_num_points(p);
    const double *x = gs_path_xyz(p), *b = gs_path_bary(p);
    int ok = 1;
    *n_bends = 0;
    for (uint32_t i = 1; i + 1 < n; ++i) {
        const double *a = x + 3 * (i - 1), *c = x + 3 * i, *d = x + 3 * (i + 1);
        double u[2] = {c[0] - a[0], c[1] - a[1]}, v[2] = {d[0] - c[0], d[1] - c[1]};
        double cr = fabs(u[0] * v[1] - u[1] * v[0]) / (hypot(u[0], u[1]) * hypot(v[0], v[1]));
        int is_vertex = b[3 * i] == 1 || b[3 * i + 1] == 1 || b[3 * i + 2] == 1;
        if (cr > 1e-9) {
            ++*n_bends;
            if (!is_vertex) ok = 0;
        }
    }
    return ok;
}

static uint32_t nearest_vertex(const gs_mesh *m, double x, double y, double z)
{
    const double *P = gs_mesh_positions(m);
    uint32_t best = 0;
    double bd = INFINITY, q[3] = {x, y, z};
    for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v) {
        double d = gs__test_dist3(P + 3 * v, q);
        if (d < bd) bd = d, best = v;
    }
    return best;
}

typedef struct ctx {
    gs_mesh *m;
    gs_patch *patch;
    gs_solver *s;
    double *dist;
} ctx;

static int open_ctx(ctx *c, const char *spec, gs_mesh *given)
{
    gs_error err;
    memset(c, 0, sizeof *c);
    int rc = given ? (c->m = given, GS_OK) : gs_mesh_generate(spec, &c->m, &err);
    if (!rc) rc = gs_patch_create(c->m, NULL, 0, &c->patch, &err);
    if (!rc) rc = gs_solver_create(c->patch, GS_METHOD_EXACT, &c->s, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", spec, err.message);
    if (!rc) c->dist = malloc(gs_mesh_num_vertices(c->m) * sizeof *c->dist);
    return rc;
}

static void close_ctx(ctx *c)
{
    gs_solver_free(c->s);
    gs_patch_free(c->patch);
    gs_mesh_free(c->m);
    free(c->dist);
}

/* The path from a to b (vertices or points) through both entry points,
 * checked against the exact field and against want (if >= 0); returns its
 * length. */
static double path_checked(ctx *c, gs_source a, gs_source b, double want, const char *what)
{
    gs_error err;
    gs_path *p = NULL;
    int rc = gs_solver_path(c->s, &a, &b, &p, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", what, err.message);
    if (rc) return NAN;
    double field = INFINITY;
    const double *P = gs_mesh_positions(c->m);
    double pa[3], pb[3];
    for (int k = 0; k < 2; ++k) {
        const gs_source *s = k ? &b : &a;
        double *o = k ? pb : pa;
        if (s->face == GS_NONE) {
            memcpy(o, P + 3 * s->vertex, sizeof pa);
        } else {
            const uint32_t *T = gs_mesh_faces(c->m) + 3 * s->face;
            for (int j = 0; j < 3; ++j)
                o[j] = s->bary[0] * P[3 * T[0] + j] + s->bary[1] * P[3 * T[1] + j] + s->bary[2] * P[3 * T[2] + j];
        }
    }
    if (b.face == GS_NONE) {
        /* the field from a gives the exact distance to compare with */
        CHECK(gs_solver_solve(c->s, &a, 1, 0, c->dist, &err) == GS_OK);
        field = c->dist[b.vertex];
        gs_path *q = NULL;
        CHECK(gs_solver_trace(c->s, &b, &q, &err) == GS_OK);
        CHECK_NEAR(gs_path_length(q), gs_path_length(p), 1e-13 * (1 + field));
        gs_path_free(q);
    } else if (a.face == GS_NONE) {
        CHECK(gs_solver_solve(c->s, &b, 1, 0, c->dist, &err) == GS_OK);
        field = c->dist[a.vertex];
    } else {
        field = gs_path_length(p);
    }
    check_path(c->m, p, field, pa, pb, what);
    if (want >= 0) CHECK_MSG(fabs(gs_path_length(p) - want) <= REL * want, "%s: length %.17g, known %.17g", what,
                             gs_path_length(p), want);
    /* reverse: as long */
    gs_path *r = NULL;
    CHECK(gs_solver_path(c->s, &b, &a, &r, &err) == GS_OK);
    CHECK_MSG(fabs(gs_path_length(r) - gs_path_length(p)) <= REL * gs_path_length(p), "%s: reverse %.17g vs %.17g",
              what, gs_path_length(r), gs_path_length(p));
    if (r) check_path(c->m, r, gs_path_length(p), pb, pa, what);
    gs_path_free(r);
    double len = gs_path_length(p);
    gs_path_free(p);
    return len;
}

static void test_plane(void)
{
    ctx c;
    if (open_ctx(&c, "grid:11,7,2,1", NULL)) return;
    const double *P = gs_mesh_positions(c.m);
    uint32_t a = 0, b = gs_mesh_num_vertices(c.m) - 1;
    path_checked(&c, gs_source_vertex(a), gs_source_vertex(b), gs__test_dist3(P + 3 * a, P + 3 * b), "plane corners");
    /* a point to a vertex and point to point: straight segments */
    gs_source pa = gs_source_point(3, 0.2, 0.3, 0.5), pb = gs_source_point(100, 0.6, 0.1, 0.3);
    gs_error err;
    gs_path *p = NULL;
    CHECK(gs_solver_path(c.s, &pa, &pb, &p, &err) == GS_OK);
    if (p) {
        const double *x = gs_path_xyz(p);
        uint32_t n = gs_path_num_points(p);
        double L = gs__test_dist3(x, x + 3 * (n - 1));
        check_path(c.m, p, L, NULL, NULL, "plane points");
        int bends;
        CHECK(flat_bends_at_vertices(p, &bends) && bends == 0);
        CHECK(n > 2);
    }
    gs_path_free(p);
    for (uint32_t v = 0; v < gs_mesh_num_vertices(c.m); v += 5) {
        path_checked(&c, pa, gs_source_vertex(v), -1, "plane point to vertex");
    }
    /* the same point: one point, length 0 */
    CHECK(gs_solver_path(c.s, &pa, &pa, &p, &err) == GS_OK);
    CHECK(gs_path_num_points(p) == 1 && gs_path_length(p) == 0);
    gs_path_free(p);
    gs_source v3 = gs_source_vertex(3);
    CHECK(gs_solver_path(c.s, &v3, &v3, &p, &err) == GS_OK);
    CHECK(gs_path_num_points(p) == 1 && gs_path_length(p) == 0 && gs_path_faces(p)[0] < gs_mesh_num_faces(c.m));
    gs_path_free(p);
    /* several sources: the path leads to the nearest */
    {
        gs_source two[2] = {gs_source_vertex(0), gs_source_point(50, 0.1, 0.2, 0.7)};
        CHECK(gs_solver_solve(c.s, two, 2, 0, c.dist, &err) == GS_OK);
        for (uint32_t v = 0; v < gs_mesh_num_vertices(c.m); v += 3) {
            gs_source t = gs_source_vertex(v);
            CHECK(gs_solver_trace(c.s, &t, &p, &err) == GS_OK);
            if (p) check_path(c.m, p, c.dist[v], NULL, P + 3 * v, "plane, two sources");
            gs_path_free(p);
        }
        /* a bounded solve: vertices beyond the bound are refused */
        CHECK(gs_solver_solve(c.s, two, 1, 0.3, c.dist, &err) == GS_OK);
        gs_source far = gs_source_vertex(b);
        CHECK(gs_solver_trace(c.s, &far, &p, &err) == GS_EARG || (p && gs_path_num_points(p) == 0));
        gs_path_free(p);
        p = NULL;
    }
    /* errors */
    gs_source bad = gs_source_vertex(100000);
    CHECK(gs_solver_path(c.s, &pa, &bad, &p, &err) == GS_EARG && p == NULL && strstr(err.message, "target"));
    CHECK(gs_solver_path(c.s, &bad, &pa, &p, &err) == GS_EARG && p == NULL);
    CHECK(gs_solver_trace(c.s, &pa, &p, &err) == GS_EARG && p == NULL);
    CHECK(gs_solver_path(NULL, &pa, &pa, &p, &err) == GS_EARG);
    CHECK(gs_path_num_points(NULL) == 0 && isinf(gs_path_length(NULL)) && !gs_path_xyz(NULL));
    close_ctx(&c);
    /* a fresh exact solver has nothing to trace; other methods give GS_EARG */
    ctx d;
    if (open_ctx(&d, "grid:5,5", NULL)) return;
    CHECK(gs_solver_trace(d.s, &v3, &p, &err) == GS_EARG);
    gs_solver *g = NULL;
    CHECK(gs_solver_create(d.patch, GS_METHOD_GRAPH, &g, &err) == GS_OK);
    CHECK(gs_solver_path(g, &v3, &v3, &p, &err) == GS_EARG && strstr(err.message, "exact"));
    gs_solver_free(g);
    close_ctx(&d);
}

static void test_unreachable(void)
{
    ctx c;
    if (open_ctx(&c, "two:4", NULL)) return;
    gs_source a = gs_source_vertex(0), b = gs_source_vertex(gs_mesh_num_vertices(c.m) - 1);
    gs_path *p = NULL;
    gs_error err;
    CHECK(gs_solver_path(c.s, &a, &b, &p, &err) == GS_OK);
    CHECK(p && gs_path_num_points(p) == 0 && isinf(gs_path_length(p)) && !gs_path_xyz(p));
    gs_path_free(p);
    close_ctx(&c);
}

static void test_cylinder(void)
{
    /* a prism of 12 sides unrolls to a strip: from ring 0 to the top ring k
     * sides round, sqrt(H^2 + (k c)^2), c the side's width */
    ctx c;
    if (open_ctx(&c, "cylinder:12,9,1,2", NULL)) return;
    double chord = 2 * sin(M_PI / 12);
    for (uint32_t k = 0; k <= 5; ++k) {
        char what[64];
        snprintf(what, sizeof what, "cylinder k=%u", k);
        path_checked(&c, gs_source_vertex(0), gs_source_vertex(8 * 12 + k), sqrt(4 + k * k * chord * chord), what);
    }
    close_ctx(&c);
}

static void test_cone(void)
{
    /* a truncated pyramid of 8 sides (apex at 4H/3): base vertices k sides
     * apart are 2 l sin(k phi / 2) apart in the unfolding, l the lateral
     * edge, phi the apex angle of a side */
    ctx c;
    if (open_ctx(&c, "cone:8,6,1,1", NULL)) return;
    double l = sqrt(1 + 16.0 / 9.0), phi = 2 * asin(sin(M_PI / 8) / l);
    for (uint32_t k = 1; k <= 3; ++k) {
        char what[64];
        snprintf(what, sizeof what, "cone k=%u", k);
        path_checked(&c, gs_source_vertex(0), gs_source_vertex(k), 2 * l * sin(k * phi / 2), what);
    }
    /* along a lateral edge, base to top: 3/4 of it */
    path_checked(&c, gs_source_vertex(0), gs_source_vertex(5 * 8), 0.75 * l, "cone generator");
    close_ctx(&c);
}

static void test_cube(void)
{
    ctx c;
    if (open_ctx(&c, "cube:4", NULL)) return;
    uint32_t a = nearest_vertex(c.m, 0, 0, 0), b = nearest_vertex(c.m, 1, 1, 1);
    path_checked(&c, gs_source_vertex(a), gs_source_vertex(b), sqrt(5), "cube corners");
    uint32_t e = nearest_vertex(c.m, 1, 1, 0);
    path_checked(&c, gs_source_vertex(a), gs_source_vertex(e), sqrt(2), "cube face diagonal");
    /* the centres of two opposite faces: 2 (any way round) */
    for (uint32_t f = 0; f < gs_mesh_num_faces(c.m); f += 7)
        path_checked(&c, gs_source_point(f, 0.3, 0.3, 0.4), gs_source_vertex(b), -1, "cube point");
    close_ctx(&c);
}

static void test_plate(void)
{
    /* a flat plate with holes: paths bend only at (hole boundary) vertices,
     * and some must bend */
    ctx c;
    if (open_ctx(&c, "plate:400", NULL)) return;
    uint32_t n = gs_mesh_num_vertices(c.m);
    const double *P = gs_mesh_positions(c.m);
    int bent = 0;
    uint64_t rng = 12345;
    for (int i = 0; i < 60; ++i) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t a = (uint32_t)(rng >> 33) % n;
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t b = (uint32_t)(rng >> 33) % n;
        gs_source sa = gs_source_vertex(a), sb = gs_source_vertex(b);
        double len = path_checked(&c, sa, sb, -1, "plate");
        gs_path *p = NULL;
        gs_error err;
        CHECK(gs_solver_path(c.s, &sa, &sb, &p, &err) == GS_OK);
        int bends;
        CHECK_MSG(flat_bends_at_vertices(p, &bends), "plate %u -> %u bends off a vertex", a, b);
        if (len > gs__test_dist3(P + 3 * a, P + 3 * b) * (1 + 1e-6)) {
            CHECK(bends > 0);
            ++bent;
        } else {
            CHECK(bends == 0);
        }
        gs_path_free(p);
    }
    CHECK_MSG(bent > 0, "no path went round a hole");
    printf("plate: %d of 60 paths go round a hole\n", bent);
    close_ctx(&c);
}

/* A random point of one of nf faces (uniform face, uniform in it). */
static gs_source random_point(uint64_t *rng, uint32_t nf)
{
    double u[3];
    for (int j = 0; j < 3; ++j) {
        *rng = *rng * 6364136223846793005ull + 1442695040888963407ull;
        u[j] = (double)(*rng >> 11) * 0x1p-53;
    }
    uint32_t f = (uint32_t)(u[0] * nf);
    if (u[1] + u[2] > 1) u[1] = 1 - u[1], u[2] = 1 - u[2];
    return gs_source_point(f < nf ? f : nf - 1, u[1], u[2], 1 - u[1] - u[2]);
}

/* Graded needles: `graded:40,7` (cells 7e-12 wide, 0.2 long, flat: every
 * distance is the straight one) and the same grid bent by a wave (the walk
 * unfolds needles that are not coplanar): random surface points both ways,
 * every invariant of path_checked. */
static void test_graded(void)
{
    ctx c;
    if (open_ctx(&c, "graded:40,7", NULL)) return;
    uint32_t nv = gs_mesh_num_vertices(c.m), nf = gs_mesh_num_faces(c.m);
    const double *P = gs_mesh_positions(c.m);
    double *xyz = malloc(3 * (size_t)nv * sizeof *xyz);
    gs_mesh *wavy = NULL;
    gs_error err;
    if (xyz) {
        memcpy(xyz, P, 3 * (size_t)nv * sizeof *xyz);
        for (uint32_t v = 0; v < nv; ++v) xyz[3 * v + 2] = 0.25 * sin(5 * xyz[3 * v]) * sin(5 * xyz[3 * v + 1]);
        CHECK(gs_mesh_create(xyz, nv, gs_mesh_faces(c.m), nf, &wavy, &err) == GS_OK);
        free(xyz);
    }
    uint64_t rng = 3;
    for (int i = 0; i < 300; ++i) {
        gs_source e[2] = {random_point(&rng, nf), random_point(&rng, nf)};
        double x[2][3] = {{0}};
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 3; ++j)
                for (int d = 0; d < 3; ++d) x[k][d] += e[k].bary[j] * P[3 * gs_mesh_faces(c.m)[3 * e[k].face + j] + d];
        char what[64];
        snprintf(what, sizeof what, "graded:40,7 pair %d", i);
        path_checked(&c, e[0], e[1], gs__test_dist3(x[0], x[1]), what);
    }
    close_ctx(&c);
    if (!wavy || open_ctx(&c, "graded:40,7 bent", wavy)) return;
    rng = 3;
    for (int i = 0; i < 300; ++i) {
        gs_source e[2] = {random_point(&rng, nf), random_point(&rng, nf)};
        char what[64];
        snprintf(what, sizeof what, "graded:40,7 bent pair %d", i);
        path_checked(&c, e[0], e[1], -1, what);
    }
    close_ctx(&c);
}

/* Shared meshes: lengths of random paths against the ground truth. */
static void test_shared(int quick)
{
    char names[64][GS_TEST_NAME_MAX];
    int nm = gs__test_shared_names(names, 64);
    if (nm <= 0) {
        printf("shared ground truth: skipped (no ../shared/groundtruth)\n");
        return;
    }
    for (int i = 0; i < nm; ++i) {
        char obj[4096], gtp[4096];
        if (!gs__test_shared_pair(names[i], obj, gtp, sizeof obj)) continue;
        gs_error err;
        gs_mesh *m = NULL;
        gs_gt *gt = NULL;
        if (gs_mesh_load(obj, GS_FORMAT_AUTO, &m, &err)) {
            CHECK_MSG(0, "%s: %s", obj, err.message);
            continue;
        }
        if (quick && gs_mesh_num_vertices(m) > 40000) {
            printf("%-16s skipped (GEOSEP_QUICK)\n", names[i]);
            gs_mesh_free(m);
            continue;
        }
        CHECK_MSG(gs_gt_read(gtp, &gt, &err) == GS_OK, "%s: %s", gtp, err.message);
        ctx c;
        if (!gt || open_ctx(&c, names[i], m)) {
            gs_gt_free(gt);
            continue;
        }
        uint32_t n = gs_mesh_num_vertices(m);
        uint32_t ns = quick ? 1 : (gt->n_sources < 3 ? gt->n_sources : 3);
        double worst = 0;
        int traced = 0;
        uint64_t rng = 99;
        for (uint32_t j = 0; j < ns; ++j) {
            gs_source s = gs_source_vertex(gt->sources[j]);
            CHECK(gs_solver_solve(c.s, &s, 1, 0, c.dist, &err) == GS_OK);
            for (int k = 0; k < 1000; ++k) {
                rng = rng * 6364136223846793005ull + 1442695040888963407ull;
                uint32_t v = (uint32_t)(rng >> 33) % n;
                double want = gt->dist[(size_t)j * n + v];
                gs_source tv = gs_source_vertex(v);
                gs_path *p = NULL;
                int rc = gs_solver_trace(c.s, &tv, &p, &err);
                CHECK_MSG(rc == GS_OK, "%s %u -> %u: %s", names[i], s.vertex, v, err.message);
                if (rc) continue;
                if (isinf(want)) {
                    CHECK(gs_path_num_points(p) == 0);
                } else {
                    char what[GS_TEST_NAME_MAX + 64];
                    snprintf(what, sizeof what, "%.100s %u -> %u", names[i], s.vertex, v);
                    check_path(m, p, want, gs_mesh_positions(m) + 3 * (size_t)s.vertex,
                               gs_mesh_positions(m) + 3 * (size_t)v, what);
                    if (want > 0) worst = fmax(worst, fabs(gs_path_length(p) - want) / want);
                    ++traced;
                }
                gs_path_free(p);
            }
        }
        printf("%-16s %d paths, largest relative length error %.2g\n", names[i], traced, worst);
        close_ctx(&c);
        gs_gt_free(gt);
    }
}

int main(void)
{
    const char *q = getenv("GEOSEP_QUICK");
    int quick = q && *q && strcmp(q, "0");
    test_plane();
    test_unreachable();
    test_cylinder();
    test_cone();
    test_cube();
    test_plate();
    test_graded();
    test_shared(quick);
    return gs__test_finish("test_path");
}
