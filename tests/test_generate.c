/* test_generate.c - sanity of gs_mesh_generate: vertex/face counts, the
 * health report (components, boundary loops, genus), orientation (flat
 * meshes face +z, closed ones enclose a positive volume), geometry that is
 * known in closed form, and strict rejection of malformed specs. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct expect {
    const char *spec;
    uint32_t nv, nf;      /* 0: not checked */
    uint32_t components, loops;
    int32_t genus;
    double min_angle;     /* lower bound on the smallest corner angle (deg) */
} expect;

static void face_normal(const gs_mesh *m, uint32_t f, double n[3], double c[3])
{
    const double *x = gs_mesh_positions(m);
    const uint32_t *t = gs_mesh_faces(m) + 3 * (size_t)f;
    const double *p = x + 3 * (size_t)t[0], *q = x + 3 * (size_t)t[1], *r = x + 3 * (size_t)t[2];
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = q[k] - p[k];
        v[k] = r[k] - p[k];
        c[k] = (p[k] + q[k] + r[k]) / 3;
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

/* Signed volume (closed meshes) and total area. */
static void volume_area(const gs_mesh *m, double *vol, double *area)
{
    *vol = *area = 0;
    for (uint32_t f = 0; f < gs_mesh_num_faces(m); ++f) {
        double n[3], c[3];
        face_normal(m, f, n, c);
        *vol += (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / 6;
        *area += sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
    }
}

static gs_mesh *generate(const char *spec)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    int rc = gs_mesh_generate(spec, &m, &err);
    CHECK_MSG(rc == GS_OK && m, "gs_mesh_generate(\"%s\") = %d: %s", spec, rc, err.message);
    return m;
}

static void check_expect(const expect *e)
{
    gs_mesh *m = generate(e->spec);
    if (!m) return;
    gs_mesh_report r;
    CHECK(gs_mesh_get_report(m, &r, NULL) == GS_OK);
    printf("%-22s V=%-6u F=%-6u comp=%u loops=%u genus=%d angles %.1f..%.1f deg\n", e->spec,
           r.n_vertices, r.n_faces, r.n_components, r.n_boundary_loops, r.genus, r.min_angle_deg,
           r.max_angle_deg);
    if (e->nv) CHECK_MSG(r.n_vertices == e->nv, "%s: %u vertices, expected %u", e->spec, r.n_vertices, e->nv);
    if (e->nf) CHECK_MSG(r.n_faces == e->nf, "%s: %u faces, expected %u", e->spec, r.n_faces, e->nf);
    CHECK_MSG(r.n_components == e->components, "%s: %u components", e->spec, r.n_components);
    CHECK_MSG(r.n_boundary_loops == e->loops, "%s: %u loops", e->spec, r.n_boundary_loops);
    CHECK_MSG(r.genus == e->genus, "%s: genus %d", e->spec, r.genus);
    CHECK_MSG(r.n_unreferenced == 0, "%s: %u unreferenced", e->spec, r.n_unreferenced);
    CHECK_MSG(r.min_angle_deg >= e->min_angle, "%s: min angle %g < %g", e->spec, r.min_angle_deg,
              e->min_angle);
    gs_mesh_free(m);
}

static void test_counts(void)
{
    static const expect ex[] = {
        {"grid:5,4", 20, 24, 1, 1, 0, 30},
        {"grid:3,3,2,5", 9, 8, 1, 1, 0, 20},
        {"peaks:21", 441, 800, 1, 1, 0, 1},
        {"peaks:21,20", 441, 800, 1, 1, 0, 10},
        {"plate:1000", 0, 0, 1, 4, 0, 25},
        {"plate:200", 0, 0, 1, 4, 0, 25},
        {"cylinder:16,5", 80, 128, 1, 2, 0, 30},
        {"cylinder:3,2,1,3", 6, 6, 1, 2, 0, 20},
        {"cone:16,5", 80, 128, 1, 2, 0, 15},
        {"cube:4", 98, 192, 1, 0, 0, 45},
        {"cube:1,2", 8, 12, 1, 0, 0, 45},
        {"torus:24,12", 288, 576, 1, 0, 1, 25},
        {"torus:3,3,2,1", 9, 18, 1, 0, 1, 5},
        {"knot:120,12", 1440, 2880, 1, 0, 1, 25},
        {"sphere:0", 12, 20, 1, 0, 0, 59.9},
        {"sphere:3", 642, 1280, 1, 0, 0, 45},
        {"two:5", 50, 64, 2, 2, 0, 45},
        {"graded:6", 36, 50, 1, 1, 0, 0},
    };
    for (size_t i = 0; i < sizeof ex / sizeof ex[0]; ++i) check_expect(&ex[i]);
}

/* Flat meshes: every face faces +z, z == 0, and the area is known. */
static void check_flat(const char *spec, double area_lo, double area_hi)
{
    gs_mesh *m = generate(spec);
    if (!m) return;
    uint32_t bad = 0;
    for (uint32_t f = 0; f < gs_mesh_num_faces(m); ++f) {
        double n[3], c[3];
        face_normal(m, f, n, c);
        if (!(n[2] > 0) || n[0] != 0 || n[1] != 0 || c[2] != 0) bad++;
    }
    double vol, area;
    volume_area(m, &vol, &area);
    printf("%-22s area %.15g, %u faces not facing +z\n", spec, area, bad);
    CHECK_MSG(bad == 0, "%s: %u faces do not face +z", spec, bad);
    CHECK_MSG(area >= area_lo && area <= area_hi, "%s: area %.17g not in [%g, %g]", spec, area,
              area_lo, area_hi);
    gs_mesh_free(m);
}

/* Closed meshes: outward orientation means a positive enclosed volume. */
static void check_closed(const char *spec, double vol_expected, double rel_tol)
{
    gs_mesh *m = generate(spec);
    if (!m) return;
    double vol, area;
    volume_area(m, &vol, &area);
    printf("%-22s volume %.15g (expected %.15g, rel tol %g)\n", spec, vol, vol_expected, rel_tol);
    CHECK_MSG(fabs(vol - vol_expected) <= rel_tol * vol_expected, "%s: volume %.17g vs %.17g", spec,
              vol, vol_expected);
    gs_mesh_free(m);
}

/* Tubes: every face normal points away from the z axis. */
static void check_tube(const char *spec)
{
    gs_mesh *m = generate(spec);
    if (!m) return;
    uint32_t bad = 0;
    for (uint32_t f = 0; f < gs_mesh_num_faces(m); ++f) {
        double n[3], c[3];
        face_normal(m, f, n, c);
        if (!(n[0] * c[0] + n[1] * c[1] > 0)) bad++;
    }
    CHECK_MSG(bad == 0, "%s: %u faces point inwards", spec, bad);
    gs_mesh_free(m);
}

static void test_geometry(void)
{
    const double holes = M_PI * (0.15 * 0.15 + 0.10 * 0.10 + 0.12 * 0.12);
    check_flat("grid:5,4", 1 - 1e-15, 1 + 1e-15);
    check_flat("grid:7,3,2,5", 10 - 1e-14, 10 + 1e-14);
    check_flat("two:4", 2 - 1e-15, 2 + 1e-15);
    check_flat("graded:40,7", 1 - 1e-14, 1 + 1e-14);
    gs_mesh *g = generate("graded:5,2"); /* vertex (i, j) at ((i/4)^2, (j/4)^2) */
    if (g) {
        const double *p = gs_mesh_positions(g);
        CHECK(p[3 * 1] == 1.0 / 16 && p[3 * 1 + 1] == 0 && p[3 * 7] == 1.0 / 4 && p[3 * 7 + 1] == 1.0 / 16);
        CHECK(p[3 * 24] == 1 && p[3 * 24 + 1] == 1 && p[3 * 24 + 2] == 0);
        gs_mesh_free(g);
    }
    /* polygonal holes are inscribed in their circles: a bit more area */
    check_flat("plate:1000", 1 - holes, 1 - holes + 0.01);
    check_closed("cube:4", 1, 1e-14);
    check_closed("cube:3,2", 8, 1e-14);
    check_closed("sphere:4", 4 * M_PI / 3, 0.01);
    check_closed("torus:64,32,1,0.4", 2 * M_PI * M_PI * 1 * 0.4 * 0.4, 0.01);
    /* a tube of radius r around a curve of length L (31.8986 for the trefoil,
     * numerically) encloses pi r^2 L while it does not cross itself */
    check_closed("knot:600,48,0.3", M_PI * 0.3 * 0.3 * 31.8986, 0.01);
    check_tube("cylinder:16,5,2,3");
    check_tube("cone:16,5,2,3");

    gs_mesh *m = generate("peaks:21"); /* (0,0) is vertex 10*21+10 */
    if (m) {
        const double *p = gs_mesh_positions(m) + 3 * (10 * 21 + 10);
        CHECK_NEAR(p[0], 0, 1e-15);
        CHECK_NEAR(p[1], 0, 1e-15);
        CHECK_NEAR(p[2], 8.0 / 3.0 * exp(-1.0), 1e-15);
        gs_mesh_free(m);
    }
    /* peaks:21,20: the same heights on a 20 x 20 grid (x, y scaled by 20/6) */
    gs_mesh *a = generate("peaks:21"), *b = generate("peaks:21,20");
    if (a && b) {
        const double *p = gs_mesh_positions(a), *q = gs_mesh_positions(b);
        CHECK_NEAR(q[0], -10, 1e-14);
        CHECK_NEAR(q[1], -10, 1e-14);
        CHECK_NEAR(q[3 * 20], 10, 1e-14);
        CHECK_NEAR(q[3 * (20 * 21 + 20) + 1], 10, 1e-14);
        double worst = 0;
        for (uint32_t v = 0; v < 441; ++v)
            worst = fmax(worst, fabs(q[3 * v] - p[3 * v] * 20 / 6) + fabs(q[3 * v + 1] - p[3 * v + 1] * 20 / 6) +
                                    fabs(q[3 * v + 2] - p[3 * v + 2]));
        CHECK_MSG(worst <= 1e-13, "peaks:21,20 is not peaks:21 scaled in x and y (off by %g)", worst);
        CHECK(gs_mesh_num_faces(a) == gs_mesh_num_faces(b));
        CHECK(memcmp(gs_mesh_faces(a), gs_mesh_faces(b), 3 * gs_mesh_num_faces(a) * sizeof(uint32_t)) == 0);
    }
    gs_mesh_free(a);
    gs_mesh_free(b);
    m = generate("cone:8,3,2,6"); /* top ring radius R/4 at z = H */
    if (m) {
        const double *p = gs_mesh_positions(m) + 3 * 16;
        CHECK_NEAR(hypot(p[0], p[1]), 0.5, 1e-15);
        CHECK_NEAR(p[2], 6, 1e-15);
        gs_mesh_free(m);
    }
    m = generate("sphere:2");
    if (m) {
        double worst = 0;
        for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v) {
            const double *p = gs_mesh_positions(m) + 3 * (size_t)v;
            worst = fmax(worst, fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1));
        }
        CHECK_MSG(worst < 1e-15, "sphere vertices off the unit sphere by %g", worst);
        gs_mesh_free(m);
    }
}

static void test_deterministic(void)
{
    gs_mesh *a = generate("plate:500"), *b = generate("plate:500");
    if (a && b) {
        CHECK(gs_mesh_num_vertices(a) == gs_mesh_num_vertices(b));
        CHECK(gs_mesh_num_faces(a) == gs_mesh_num_faces(b));
        CHECK(!memcmp(gs_mesh_positions(a), gs_mesh_positions(b),
                      3 * sizeof(double) * gs_mesh_num_vertices(a)));
        CHECK(!memcmp(gs_mesh_faces(a), gs_mesh_faces(b), 3 * sizeof(uint32_t) * gs_mesh_num_faces(a)));
    }
    gs_mesh_free(a);
    gs_mesh_free(b);
    /* "about N vertices" */
    static const uint32_t ns[] = {100, 1000, 10000};
    for (int i = 0; i < 3; ++i) {
        char spec[32];
        snprintf(spec, sizeof spec, "plate:%u", ns[i]);
        gs_mesh *m = generate(spec);
        if (!m) continue;
        uint32_t nv = gs_mesh_num_vertices(m);
        printf("%-22s %u vertices\n", spec, nv);
        CHECK_MSG(nv > ns[i] * 0.7 && nv < ns[i] * 1.3, "%s gives %u vertices", spec, nv);
        gs_mesh_free(m);
    }
}

static void test_bad_specs(void)
{
    static const char *bad[] = {
        "", "grid", "grid:", "grid:1,5", "grid:5", "grid:5,5,1", "grid:5,5,0,1", "grid:5,5,-1,1",
        "grid:5,5,1,x", "grid:5,,5", "grid:5,5,", "grid:5.5,5", "grid:a,b", "grid:+5,5",
        "grid:5,5,nan,1", "grid:5,5,inf,1", "grid:5,5,1,1,1", " grid:5,5", "GRID:5,5", "blob:3",
        "grid:99999999999,5", "torus:10,10,1,2", "torus:10,10,1,1", "sphere:10", "cube:0",
        "cube:2,0", "plate:10", "peaks:1", "peaks:5,0", "peaks:5,-6", "peaks:5,6,6", "two:1", "cylinder:2,5", "cone:5,1", "torus:5,2", "sphere:-1", "knot:7,5",
        "knot:10,10,0.6", "knot:10,10,0.4,1", "graded:1", "graded:5,0.5", "graded:5,9", "graded:5000",
        "grid:5 ,5", "grid:5,5,1e400,1",
        /* strict sizes: blanks, signs, hex, inf/nan words, out of [1e-30, 1e30] */
        "grid:3,3, 1,1", "grid:3,3,1 ,1", "grid:3,3,1,\t1", "grid:3,3,+1,1", "grid:3,3,0x1p1,1",
        "grid:3,3,infinity,1", "grid:3,3,1e,1", "grid:3,3,.,1", "grid:3,3,1e31,1", "grid:3,3,1e-31,1",
        "grid:3,3,1.5e+300,1", "torus:8,8, 1,0.4", "cube:3,\n2", "grid:3,3,1,1e",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        gs_mesh *m = (gs_mesh *)&m; /* must be reset to NULL */
        gs_error err = {0};
        int rc = gs_mesh_generate(bad[i], &m, &err);
        printf("reject %-22s -> %d: %s\n", bad[i], rc, err.message);
        CHECK_MSG(rc == GS_EARG, "\"%s\" gave %d", bad[i], rc);
        CHECK_MSG(m == NULL, "\"%s\" left *out set", bad[i]);
        CHECK_MSG(strstr(err.message, bad[i]) && (strstr(err.message, "expected") ||
                                                   strstr(err.message, "accepted")),
                  "\"%s\": message does not quote the spec or say what is accepted: %s", bad[i],
                  err.message);
    }
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK(gs_mesh_generate(NULL, &m, &err) == GS_EARG && m == NULL);
    CHECK(gs_mesh_generate("grid:3,3", NULL, NULL) == GS_EARG);
    CHECK(gs_mesh_generate("grid:20000,20000", &m, &err) == GS_ELIMIT && m == NULL);
    printf("reject grid:20000,20000 -> %s\n", err.message);
    CHECK(gs_mesh_generate("grid:3,3, 1,1", &m, &err) == GS_EARG && m == NULL);
    CHECK_MSG(strstr(err.message, "bad mesh spec \"grid:3,3, 1,1\": argument 3 (\" 1\") must be a plain decimal "
                                  "number from 1e-30 to 1e+30"), "%s", err.message);
    /* the plain decimal forms are all accepted, with their exact values */
    static const char *good[] = {"grid:3,3,.5,2.", "grid:3,3,5e-1,2E0", "grid:3,3,0.5,2e+0", "grid:3,3,1e-30,1e-30", "grid:3,3,1e30,1e30"};
    for (size_t i = 0; i < sizeof good / sizeof *good; ++i) {
        int rc = gs_mesh_generate(good[i], &m, &err);
        CHECK_MSG(rc == GS_OK, "%s: %s", good[i], err.message);
        gs_mesh_report r;
        if (rc == GS_OK && gs_mesh_get_report(m, &r, &err) == GS_OK) {
            if (i < 3) CHECK(r.bbox_max[0] == 0.5 && r.bbox_max[1] == 2.0);
            else CHECK(r.bbox_max[0] == (i == 3 ? 1e-30 : 1e30) && r.bbox_max[1] == r.bbox_max[0]);
        }
        gs_mesh_free(m);
        m = NULL;
    }
}

int main(void)
{
    test_counts();
    test_geometry();
    test_deterministic();
    test_bad_specs();
    return gs__test_finish("test_generate");
}
