/* test_exact_basic.c - the exact solver on meshes built here from arrays,
 * with answers known in closed form: Euclidean distances on flat (also
 * folded) sheets, taut strings around reflex corners and holes, paths
 * through a bow-tie vertex, the cube, needle triangles; plus the solver
 * contract: point sources, several sources = pointwise min, max_distance,
 * +inf where unreachable, and no state leaking between solves. And a
 * patch's connectivity (gs_patch_create reuses the mesh's) equals the one
 * built from its faces alone, bit for bit; a path solve bounded by a length
 * (and pruned towards its target) gives the unbounded path's length, or no
 * path when the bound is shorter. */
#include "check.h"
#include "geosep.h"
#include "geodesic/geodesic_internal.h"
#include "mesh/mesh_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REL 1e-12

static double g_worst; /* worst relative error seen by expect_close */

static void expect_close(double got, double want, const char *what, uint32_t v)
{
    double e = (want == 0) ? fabs(got) : fabs(got - want) / want;
    if (!(e <= g_worst)) g_worst = e;
    CHECK_MSG(e <= REL, "%s: vertex %u: got %.17g, want %.17g (rel err %.3g)", what, v, got,
              want, e);
}

/* ---- a rectangular grid of cells, each split in two triangles ----------- */

typedef struct grid {
    uint32_t nx, ny; /* cells */
    uint32_t nv, nf;
    double *uv;   /* 2 per vertex: the flat (intrinsic) coordinates */
    double *xyz;  /* 3 per vertex */
    uint32_t *tri;
} grid;

static uint32_t gv(const grid *g, uint32_t i, uint32_t j) { return j * (g->nx + 1) + i; }

static uint64_t g_rng = 88172645463325252ull;
static double rnd(void) /* uniform in [0,1) */
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (double)(g_rng >> 11) / 9007199254740992.0;
}

/* Grid on [0,W]x[0,H]; interior vertices jittered by up to `jitter` cells;
 * diagonals alternate. Cell (i,j) holds faces 2*(j*nx+i) and +1. */
static grid make_grid(uint32_t nx, uint32_t ny, double W, double H, double jitter)
{
    grid g = {nx, ny, (nx + 1) * (ny + 1), 2 * nx * ny, NULL, NULL, NULL};
    g.uv = malloc(2 * sizeof(double) * g.nv);
    g.xyz = malloc(3 * sizeof(double) * g.nv);
    g.tri = malloc(3 * sizeof(uint32_t) * g.nf);
    for (uint32_t j = 0; j <= ny; ++j)
        for (uint32_t i = 0; i <= nx; ++i) {
            double u = W * i / nx, v = H * j / ny;
            if (i > 0 && i < nx && j > 0 && j < ny) {
                if ((3 * i) % nx != 0) u += jitter * (2 * rnd() - 1) * W / nx;
                v += jitter * (2 * rnd() - 1) * H / ny;
            }
            uint32_t k = gv(&g, i, j);
            g.uv[2 * k] = u;
            g.uv[2 * k + 1] = v;
            g.xyz[3 * k] = u;
            g.xyz[3 * k + 1] = v;
            g.xyz[3 * k + 2] = 0;
        }
    for (uint32_t j = 0; j < ny; ++j)
        for (uint32_t i = 0; i < nx; ++i) {
            uint32_t a = gv(&g, i, j), b = gv(&g, i + 1, j), c = gv(&g, i + 1, j + 1),
                     d = gv(&g, i, j + 1);
            uint32_t *t = g.tri + 6 * (j * nx + i);
            if ((i + j) % 2) {
                uint32_t f[6] = {a, b, c, a, c, d};
                memcpy(t, f, sizeof f);
            } else {
                uint32_t f[6] = {a, b, d, b, c, d};
                memcpy(t, f, sizeof f);
            }
        }
    return g;
}

static void free_grid(grid *g)
{
    free(g->uv);
    free(g->xyz);
    free(g->tri);
}

static gs_mesh *mesh_of(const double *xyz, uint32_t nv, const uint32_t *tri, uint32_t nf)
{
    gs_mesh *m = NULL;
    gs_error err;
    int rc = gs_mesh_create(xyz, nv, tri, nf, &m, &err);
    CHECK_MSG(rc == GS_OK, "gs_mesh_create: %s", err.message);
    return m;
}

static gs_patch *whole(const gs_mesh *m)
{
    gs_patch *p = NULL;
    gs_error err;
    int rc = gs_patch_create(m, NULL, 0, &p, &err);
    CHECK_MSG(rc == GS_OK, "gs_patch_create: %s", err.message);
    return p;
}

static int solve(gs_solver *s, const gs_source *src, uint32_t n, double maxd, double *dist)
{
    gs_error err;
    int rc = gs_solver_solve(s, src, n, maxd, dist, &err);
    CHECK_MSG(rc == GS_OK, "gs_solver_solve: %s", err.message);
    return rc;
}

static double dist2(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
}

/* ---- shortest paths in a rectangle minus an open box, by visibility ---- */

/* Does the segment p-q cross the open box (x0,x1)x(y0,y1)? */
static int blocked(const double *p, const double *q, const double *box)
{
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 2; ++k) {
        double lo = box[2 * k], hi = box[2 * k + 1], a = p[k], d = q[k] - p[k];
        if (fabs(d) < 1e-300) {
            if (!(a > lo && a < hi)) return 0;
            continue;
        }
        double s0 = (lo - a) / d, s1 = (hi - a) / d;
        if (s0 > s1) {
            double x = s0;
            s0 = s1;
            s1 = x;
        }
        if (s0 > t0) t0 = s0;
        if (s1 < t1) t1 = s1;
    }
    return t1 - t0 > 1e-12;
}

/* Length of the taut string from s to p avoiding the open box, bending only
 * at the given corner points (Dijkstra on the visibility graph). */
static double taut(const double *s, const double *p, const double *box, const double *corners,
                   int nc)
{
    double pts[8][2], best[8];
    int done[8] = {0};
    int n = nc + 2;
    memcpy(pts[0], s, sizeof pts[0]);
    for (int i = 0; i < nc; ++i) memcpy(pts[1 + i], corners + 2 * i, sizeof pts[0]);
    memcpy(pts[n - 1], p, sizeof pts[0]);
    for (int i = 0; i < n; ++i) best[i] = INFINITY;
    best[0] = 0;
    for (;;) {
        int u = -1;
        for (int i = 0; i < n; ++i)
            if (!done[i] && best[i] < INFINITY && (u < 0 || best[i] < best[u])) u = i;
        if (u < 0) break;
        done[u] = 1;
        for (int i = 0; i < n; ++i)
            if (!done[i] && !blocked(pts[u], pts[i], box)) {
                double c = best[u] + dist2(pts[u], pts[i]);
                if (c < best[i]) best[i] = c;
            }
    }
    return best[n - 1];
}

/* ---- tests --------------------------------------------------------------- */

static void test_single_triangle(void)
{
    const double xyz[] = {0, 0, 0, 3, 0, 0, 0.4, 2, 1};
    const uint32_t tri[] = {0, 1, 2};
    gs_mesh *m = mesh_of(xyz, 3, tri, 1);
    if (!m) return;
    gs_patch *p = whole(m);
    gs_solver *s = NULL;
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
    double d[3];
    for (uint32_t v = 0; v < 3; ++v) {
        gs_source src = gs_source_vertex(v);
        if (solve(s, &src, 1, 0, d)) continue;
        for (uint32_t w = 0; w < 3; ++w) {
            double e[3] = {xyz[3 * w] - xyz[3 * v], xyz[3 * w + 1] - xyz[3 * v + 1],
                           xyz[3 * w + 2] - xyz[3 * v + 2]};
            expect_close(d[w], sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), "triangle", w);
        }
    }
    /* points inside, on an edge, next to a vertex */
    const double bary[][3] = {{0.2, 0.3, 0.5}, {0.5, 0.5, 0}, {0, 0.25, 0.75},
                              {1 - 1e-12, 5e-13, 5e-13}, {1e-9, 0.5, 0.5 - 1e-9}};
    for (size_t k = 0; k < sizeof bary / sizeof bary[0]; ++k) {
        gs_source src = gs_source_point(0, bary[k][0], bary[k][1], bary[k][2]);
        if (solve(s, &src, 1, 0, d)) continue;
        double q[3];
        for (int c = 0; c < 3; ++c)
            q[c] = bary[k][0] * xyz[c] + bary[k][1] * xyz[3 + c] + bary[k][2] * xyz[6 + c];
        for (uint32_t w = 0; w < 3; ++w) {
            double e[3] = {xyz[3 * w] - q[0], xyz[3 * w + 1] - q[1], xyz[3 * w + 2] - q[2]};
            expect_close(d[w], sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), "triangle point", w);
        }
    }
    gs_solver_free(s);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* Fold a flat grid along the lines u = W/3 and u = 2W/3 (mesh lines; the
 * jitter never moves those columns off them): each third is placed rigidly,
 * so the intrinsic geometry stays flat and distances stay Euclidean in uv. */
static void fold(grid *g, double W)
{
    const double a1 = 1.0, a2 = -1.9; /* directions of the 2nd and 3rd panels */
    for (uint32_t k = 0; k < g->nv; ++k) {
        double u = g->uv[2 * k];
        double *x = g->xyz + 3 * k;
        if (u <= W / 3) continue;
        double l1 = (u < 2 * W / 3 ? u : 2 * W / 3) - W / 3, l2 = u - 2 * W / 3;
        x[0] = W / 3 + l1 * cos(a1);
        x[2] = l1 * sin(a1);
        if (l2 > 0) {
            x[0] += l2 * cos(a2);
            x[2] += l2 * sin(a2);
        }
    }
}

/* Flat (and folded) convex sheets: every distance is Euclidean in uv. */
static void test_flat_sheets(void)
{
    for (int variant = 0; variant < 4; ++variant) {
        /* 0: regular grid, 1: jittered, 2: jittered + folded, 3: thin strip of slivers */
        uint32_t nx = variant == 3 ? 40 : 12, ny = variant == 3 ? 1 : 9;
        double W = 3, H = variant == 3 ? 0.02 : 2;
        grid g = make_grid(nx, ny, W, H, (variant == 1 || variant == 2) ? 0.3 : 0);
        if (variant == 2) fold(&g, W);
        gs_mesh *m = mesh_of(g.xyz, g.nv, g.tri, g.nf);
        if (!m) {
            free_grid(&g);
            continue;
        }
        gs_patch *p = whole(m);
        gs_solver *s = NULL;
        CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
        double *d = malloc(g.nv * sizeof *d);
        char what[64];
        snprintf(what, sizeof what, "flat sheet %d", variant);
        /* vertex sources: corners, boundary middles, interior */
        uint32_t vs[] = {0, gv(&g, nx, ny), gv(&g, nx / 2, 0), gv(&g, nx / 3, ny / 2),
                         gv(&g, nx, ny / 2)};
        for (size_t k = 0; k < sizeof vs / sizeof vs[0]; ++k) {
            gs_source src = gs_source_vertex(vs[k]);
            if (solve(s, &src, 1, 0, d)) continue;
            for (uint32_t v = 0; v < g.nv; ++v)
                expect_close(d[v], dist2(g.uv + 2 * v, g.uv + 2 * vs[k]), what, v);
        }
        /* point sources in a few faces, one on an edge */
        for (int k = 0; k < 4; ++k) {
            uint32_t f = (uint32_t)(rnd() * g.nf);
            double b0 = rnd(), b1 = rnd() * (1 - b0), b2 = 1 - b0 - b1;
            if (k == 3) {
                b2 = 0;
                b1 = 1 - b0;
            }
            gs_source src = gs_source_point(f, b0, b1, b2);
            if (solve(s, &src, 1, 0, d)) continue;
            double q[2];
            const uint32_t *c = g.tri + 3 * f;
            for (int j = 0; j < 2; ++j)
                q[j] = b0 * g.uv[2 * c[0] + j] + b1 * g.uv[2 * c[1] + j] + b2 * g.uv[2 * c[2] + j];
            for (uint32_t v = 0; v < g.nv; ++v) expect_close(d[v], dist2(g.uv + 2 * v, q), what, v);
        }
        free(d);
        gs_solver_free(s);
        gs_patch_free(p);
        gs_mesh_free(m);
        free_grid(&g);
    }
}

/* A strip of needle triangles (angles down to ~0.2 degrees, apex ~179.6):
 * bottom vertices at x = 0..n, top ones at x = k + 0.5, height h. The strip
 * is a convex flat trapezoid: distances are Euclidean. */
static void test_needles(void)
{
    const uint32_t n = 30;
    const double h = 0.0035;
    uint32_t nv = 2 * n, nf = 2 * n - 1;
    double *xyz = calloc(3 * nv, sizeof *xyz);
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    for (uint32_t k = 0; k < n; ++k) {
        xyz[3 * k] = k;                 /* bottom k */
        xyz[3 * (n + k)] = k + 0.5;     /* top k    */
        xyz[3 * (n + k) + 1] = h;
    }
    uint32_t f = 0;
    for (uint32_t k = 0; k + 1 < n; ++k) {
        uint32_t t1[3] = {k, k + 1, n + k};
        memcpy(tri + 3 * f++, t1, sizeof t1);
        uint32_t t2[3] = {k + 1, n + k + 1, n + k};
        memcpy(tri + 3 * f++, t2, sizeof t2);
    }
    nf = f;
    gs_mesh *m = mesh_of(xyz, nv, tri, nf);
    if (m) {
        gs_mesh_report r;
        gs_mesh_get_report(m, &r, NULL);
        CHECK(r.min_angle_deg < 0.5);
        gs_patch *p = whole(m);
        gs_solver *s = NULL;
        CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
        double *d = malloc(nv * sizeof *d);
        uint32_t vs[] = {0, n / 2, n + 3, 2 * n - 1};
        for (size_t k = 0; k < sizeof vs / sizeof vs[0]; ++k) {
            gs_source src = gs_source_vertex(vs[k]);
            if (solve(s, &src, 1, 0, d)) continue;
            for (uint32_t v = 0; v < nv; ++v) {
                double e[2] = {xyz[3 * v] - xyz[3 * vs[k]], xyz[3 * v + 1] - xyz[3 * vs[k] + 1]};
                expect_close(d[v], sqrt(e[0] * e[0] + e[1] * e[1]), "needles", v);
            }
        }
        gs_source src = gs_source_point(7, 0.3, 0.3, 0.4);
        if (!solve(s, &src, 1, 0, d)) {
            double q[2] = {0, 0};
            for (int c = 0; c < 3; ++c) {
                double b = c == 0 ? 0.3 : c == 1 ? 0.3 : 0.4;
                q[0] += b * xyz[3 * tri[21 + c]];
                q[1] += b * xyz[3 * tri[21 + c] + 1];
            }
            for (uint32_t v = 0; v < nv; ++v) {
                double e[2] = {xyz[3 * v] - q[0], xyz[3 * v + 1] - q[1]};
                expect_close(d[v], sqrt(e[0] * e[0] + e[1] * e[1]), "needles point", v);
            }
        }
        free(d);
        gs_solver_free(s);
        gs_patch_free(p);
        gs_mesh_free(m);
    }
    free(xyz);
    free(tri);
}

/* Faces of a grid whose cells are not inside the open box (in uv). */
static uint32_t faces_outside(const grid *g, const double *box, uint32_t *faces)
{
    uint32_t n = 0;
    for (uint32_t j = 0; j < g->ny; ++j)
        for (uint32_t i = 0; i < g->nx; ++i) {
            const double *a = g->uv + 2 * gv(g, i, j), *c = g->uv + 2 * gv(g, i + 1, j + 1);
            double mx = 0.5 * (a[0] + c[0]), my = 0.5 * (a[1] + c[1]);
            if (mx > box[0] && mx < box[1] && my > box[2] && my < box[3]) continue;
            faces[n++] = 2 * (j * g->nx + i);
            faces[n++] = 2 * (j * g->nx + i) + 1;
        }
    return n;
}

/* Taut strings: an L-shaped domain (reflex corner = boundary pseudo-source)
 * and a square with a square hole, both as patches of a larger grid, so the
 * patch numbering is exercised too. Also folded: still flat intrinsically. */
static void test_taut_strings(void)
{
    for (int variant = 0; variant < 3; ++variant) {
        /* 0: L shape [0,2]^2 minus (1,2)^2 ; 1: [0,3]^2 minus (1,2)^2 ;
         * 2: the holed square, folded */
        double W = variant == 0 ? 2 : 3;
        uint32_t n = variant == 0 ? 8 : 12;
        grid g = make_grid(n, n, W, W, 0);
        if (variant == 2) fold(&g, W);
        double box[4] = {1, 2, 1, 2};
        double corners_l[] = {1, 1, 1, 2, 2, 1};
        double corners_h[] = {1, 1, 1, 2, 2, 1, 2, 2};
        const double *corners = variant == 0 ? corners_l : corners_h;
        int nc = variant == 0 ? 3 : 4;
        gs_mesh *m = mesh_of(g.xyz, g.nv, g.tri, g.nf);
        if (!m) {
            free_grid(&g);
            continue;
        }
        uint32_t *faces = malloc(g.nf * sizeof *faces);
        uint32_t nfp = faces_outside(&g, box, faces);
        gs_patch *p = NULL;
        gs_error err;
        int rc = gs_patch_create(m, faces, nfp, &p, &err);
        CHECK_MSG(rc == GS_OK, "patch: %s", err.message);
        gs_solver *s = NULL;
        if (rc == GS_OK) CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
        uint32_t pnv = gs_patch_num_vertices(p);
        double *d = malloc((pnv ? pnv : 1) * sizeof *d);
        char what[64];
        snprintf(what, sizeof what, "taut string %d", variant);
        for (int k = 0; s && k < 6; ++k) {
            /* a random patch vertex as the source */
            uint32_t ls = (uint32_t)(rnd() * pnv);
            gs_source src = gs_source_vertex(ls);
            if (solve(s, &src, 1, 0, d)) continue;
            const double *sp = g.uv + 2 * gs_patch_vertex_to_mesh(p, ls);
            for (uint32_t v = 0; v < pnv; ++v) {
                const double *q = g.uv + 2 * gs_patch_vertex_to_mesh(p, v);
                expect_close(d[v], taut(sp, q, box, corners, nc), what, v);
            }
        }
        free(d);
        free(faces);
        gs_solver_free(s);
        gs_patch_free(p);
        gs_mesh_free(m);
        free_grid(&g);
    }
}

/* A patch of two blocks of a grid that touch at one vertex only (a bow-tie
 * vertex): paths from one block to the other pass through it. */
static void test_bowtie(void)
{
    grid g = make_grid(8, 8, 2, 2, 0);
    gs_mesh *m = mesh_of(g.xyz, g.nv, g.tri, g.nf);
    if (!m) {
        free_grid(&g);
        return;
    }
    uint32_t faces[128], n = 0;
    for (uint32_t j = 0; j < 8; ++j)
        for (uint32_t i = 0; i < 8; ++i)
            if ((i < 4 && j < 4) || (i >= 4 && j >= 4)) {
                faces[n++] = 2 * (j * 8 + i);
                faces[n++] = 2 * (j * 8 + i) + 1;
            }
    gs_patch *p = NULL;
    CHECK(gs_patch_create(m, faces, n, &p, NULL) == GS_OK);
    gs_solver *s = NULL;
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
    uint32_t pnv = gs_patch_num_vertices(p);
    CHECK(pnv == 2 * 25 - 1);
    double *d = malloc(pnv * sizeof *d);
    const double c[2] = {1, 1};
    for (int k = 0; s && k < 4; ++k) {
        uint32_t ls = (uint32_t)(rnd() * pnv);
        gs_source src = gs_source_vertex(ls);
        if (solve(s, &src, 1, 0, d)) continue;
        const double *sp = g.uv + 2 * gs_patch_vertex_to_mesh(p, ls);
        int s_low = sp[0] + sp[1] < 2;
        for (uint32_t v = 0; v < pnv; ++v) {
            const double *q = g.uv + 2 * gs_patch_vertex_to_mesh(p, v);
            int q_low = q[0] + q[1] < 2;
            double want = (s_low == q_low || (q[0] == 1 && q[1] == 1) ||
                           (sp[0] == 1 && sp[1] == 1))
                              ? dist2(sp, q)
                              : dist2(sp, c) + dist2(c, q);
            expect_close(d[v], want, "bow-tie", v);
        }
    }
    /* a point source in the upper block */
    uint32_t lf = n - 5; /* a face of the upper block */
    gs_source src = gs_source_point(lf, 0.2, 0.5, 0.3);
    if (s && !solve(s, &src, 1, 0, d)) {
        const uint32_t *tri = g.tri + 3 * gs_patch_face_to_mesh(p, lf);
        double q0[2] = {0, 0}, b[3] = {0.2, 0.5, 0.3};
        for (int k = 0; k < 3; ++k) {
            q0[0] += b[k] * g.uv[2 * tri[k]];
            q0[1] += b[k] * g.uv[2 * tri[k] + 1];
        }
        for (uint32_t v = 0; v < pnv; ++v) {
            const double *q = g.uv + 2 * gs_patch_vertex_to_mesh(p, v);
            int q_low = q[0] + q[1] < 2;
            double want = q_low ? dist2(q0, c) + dist2(c, q) : dist2(q0, q);
            expect_close(d[v], want, "bow-tie point", v);
        }
    }
    free(d);
    gs_solver_free(s);
    gs_patch_free(p);
    gs_mesh_free(m);
    free_grid(&g);
}

/* The surface of the unit cube, n x n cells per face: from a corner, the
 * far corner is at sqrt(5) and the centre of a far face at sqrt(2.5). */
static void test_cube(void)
{
    const uint32_t n = 6;
    uint32_t nv0 = 6 * (n + 1) * (n + 1);
    double *xyz = malloc(3 * nv0 * sizeof *xyz);
    uint32_t *tri = malloc(3 * 12 * n * n * sizeof *tri);
    uint32_t *id = malloc(nv0 * sizeof *id);
    uint32_t nv = 0, nf = 0;
    /* faces of the cube: origin o, axes a, b (a x b = outward normal) */
    const double F[6][9] = {{0, 0, 0, 0, 1, 0, 1, 0, 0}, {0, 0, 1, 1, 0, 0, 0, 1, 0},
                            {0, 0, 0, 1, 0, 0, 0, 0, 1}, {0, 1, 0, 0, 0, 1, 1, 0, 0},
                            {0, 0, 0, 0, 0, 1, 0, 1, 0}, {1, 0, 0, 0, 1, 0, 0, 0, 1}};
    for (int fc = 0; fc < 6; ++fc) {
        for (uint32_t j = 0; j <= n; ++j)
            for (uint32_t i = 0; i <= n; ++i) {
                double p[3];
                for (int k = 0; k < 3; ++k)
                    p[k] = F[fc][k] + F[fc][3 + k] * i / n + F[fc][6 + k] * j / n;
                uint32_t found = GS_NONE; /* weld shared cube edges */
                for (uint32_t w = 0; w < nv && found == GS_NONE; ++w)
                    if (fabs(xyz[3 * w] - p[0]) + fabs(xyz[3 * w + 1] - p[1]) +
                            fabs(xyz[3 * w + 2] - p[2]) < 1e-12)
                        found = w;
                if (found == GS_NONE) {
                    memcpy(xyz + 3 * nv, p, sizeof p);
                    found = nv++;
                }
                id[j * (n + 1) + i] = found;
            }
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t a = id[j * (n + 1) + i], b = id[j * (n + 1) + i + 1],
                         c = id[(j + 1) * (n + 1) + i + 1], d = id[(j + 1) * (n + 1) + i];
                uint32_t t[6] = {a, b, c, a, c, d};
                memcpy(tri + 3 * nf, t, sizeof t);
                nf += 2;
            }
    }
    CHECK(nv == 6 * n * n + 2);
    gs_mesh *m = mesh_of(xyz, nv, tri, nf);
    if (m) {
        gs_patch *p = whole(m);
        double *d = malloc(nv * sizeof *d);
        uint32_t src_v = GS_NONE, far = GS_NONE, mid = GS_NONE;
        for (uint32_t v = 0; v < nv; ++v) {
            const double *x = xyz + 3 * v;
            if (x[0] == 0 && x[1] == 0 && x[2] == 0) src_v = v;
            if (x[0] == 1 && x[1] == 1 && x[2] == 1) far = v;
            if (fabs(x[0] - 0.5) < 1e-12 && fabs(x[1] - 0.5) < 1e-12 && x[2] == 1) mid = v;
        }
        gs_source src = gs_source_vertex(src_v);
        if (gs_distance_field(p, GS_METHOD_EXACT, &src, 1, 0, d, NULL) == GS_OK) {
            expect_close(d[far], sqrt(5.0), "cube far corner", far);
            expect_close(d[mid], sqrt(2.5), "cube far face centre", mid);
            /* on the three faces at the source, distances are Euclidean */
            for (uint32_t v = 0; v < nv; ++v) {
                const double *x = xyz + 3 * v;
                if (x[0] == 0 || x[1] == 0 || x[2] == 0)
                    expect_close(d[v], sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), "cube",
                                 v);
            }
        }
        free(d);
        gs_patch_free(p);
        gs_mesh_free(m);
    }
    free(xyz);
    free(tri);
    free(id);
}

/* A bumpy height field (saddles everywhere) for the contract tests. */
static gs_mesh *bumpy(grid *g)
{
    *g = make_grid(24, 20, 3, 2.5, 0.25);
    for (uint32_t v = 0; v < g->nv; ++v) {
        double u = g->uv[2 * v], w = g->uv[2 * v + 1];
        g->xyz[3 * v + 2] = 0.35 * sin(3 * u) * cos(2.5 * w) + 0.05 * rnd();
    }
    return mesh_of(g->xyz, g->nv, g->tri, g->nf);
}

static void test_contract(void)
{
    grid g;
    gs_mesh *m = bumpy(&g);
    if (!m) {
        free_grid(&g);
        return;
    }
    gs_patch *p = whole(m);
    uint32_t nv = g.nv;
    gs_solver *s = NULL, *sg = NULL;
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, NULL) == GS_OK);
    CHECK(gs_solver_create(p, GS_METHOD_GRAPH, &sg, NULL) == GS_OK);
    if (!s || !sg) goto out;
    double *a1 = malloc(nv * sizeof(double)), *a2 = malloc(nv * sizeof(double)),
           *b = malloc(nv * sizeof(double)), *c = malloc(nv * sizeof(double)),
           *mn = malloc(nv * sizeof(double));

    /* symmetry d(x,y) = d(y,x), lower bounds and edge Lipschitz bound */
    uint32_t pts[6];
    double rows[6][6];
    for (int i = 0; i < 6; ++i) pts[i] = (uint32_t)(rnd() * nv);
    for (int i = 0; i < 6; ++i) {
        gs_source src = gs_source_vertex(pts[i]);
        if (solve(s, &src, 1, 0, a1)) continue;
        solve(sg, &src, 1, 0, b);
        for (int j = 0; j < 6; ++j) rows[i][j] = a1[pts[j]];
        for (uint32_t v = 0; v < nv; ++v) {
            const double *x = g.xyz + 3 * v, *y = g.xyz + 3 * pts[i];
            double e = sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                            (x[2] - y[2]) * (x[2] - y[2]));
            CHECK_MSG(a1[v] >= e * (1 - 1e-13), "below the straight distance at %u", v);
            CHECK_MSG(a1[v] <= b[v] * (1 + 1e-13), "above the edge-graph distance at %u", v);
        }
        for (uint32_t f = 0; f < g.nf; ++f)
            for (int k = 0; k < 3; ++k) {
                uint32_t u = g.tri[3 * f + k], w = g.tri[3 * f + (k + 1) % 3];
                const double *x = g.xyz + 3 * u, *y = g.xyz + 3 * w;
                double e = sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                (x[2] - y[2]) * (x[2] - y[2]));
                CHECK_MSG(fabs(a1[u] - a1[w]) <= e * (1 + 1e-12), "edge %u-%u", u, w);
            }
    }
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < i; ++j)
            expect_close(rows[i][j], rows[j][i], "symmetry", pts[j]);

    /* several sources = pointwise min of single sources (vertex + points) */
    gs_source multi[3] = {gs_source_vertex(pts[0]), gs_source_point(17, 0.2, 0.7, 0.1),
                          gs_source_point(555, 0.6, 0, 0.4)};
    for (uint32_t v = 0; v < nv; ++v) mn[v] = INFINITY;
    for (int k = 0; k < 3; ++k) {
        if (solve(s, &multi[k], 1, 0, a1)) continue;
        for (uint32_t v = 0; v < nv; ++v)
            if (a1[v] < mn[v]) mn[v] = a1[v];
    }
    if (!solve(s, multi, 3, 0, a1))
        for (uint32_t v = 0; v < nv; ++v) expect_close(a1[v], mn[v], "multi-source", v);

    /* no state leaks: A, B (another source, a bound), A again: bit-identical */
    gs_source srcA = gs_source_point(301, 0.1, 0.2, 0.7), srcB = gs_source_vertex(pts[3]);
    solve(s, &srcA, 1, 0, a1);
    solve(s, &srcB, 1, 0.5, b);
    solve(s, multi, 3, 0, c);
    solve(s, &srcA, 1, 0, a2);
    CHECK_MSG(memcmp(a1, a2, nv * sizeof(double)) == 0, "solve A, B, A: A changed");
    uint64_t wc1, wc2, wp;
    gs_solver_last_stats(s, &wc1, &wp, NULL);
    CHECK(wc1 > 0 && wp > 0);
    solve(s, &srcA, 1, 0, a2);
    gs_solver_last_stats(s, &wc2, NULL, NULL);
    CHECK(wc1 == wc2);

    /* max_distance: exact up to the bound, above it or +inf beyond */
    for (int k = 0; k < 3; ++k) {
        double bound = 0.3 + 0.6 * k;
        gs_source src = gs_source_vertex(pts[1]);
        solve(s, &src, 1, 0, a1);
        solve(s, &src, 1, bound, b);
        int n_exact = 0;
        for (uint32_t v = 0; v < nv; ++v) {
            if (a1[v] <= bound) {
                expect_close(b[v], a1[v], "max_distance", v);
                n_exact++;
            } else {
                CHECK_MSG(b[v] > bound, "vertex %u: %.17g with bound %g (exact %.17g)", v, b[v],
                          bound, a1[v]);
            }
        }
        CHECK(n_exact > 1);
        uint64_t wcb;
        gs_solver_last_stats(s, &wcb, NULL, NULL);
        CHECK(wcb > 0);
    }
    free(a1);
    free(a2);
    free(b);
    free(c);
    free(mn);
out:
    gs_solver_free(s);
    gs_solver_free(sg);
    gs_patch_free(p);
    gs_mesh_free(m);
    free_grid(&g);
}

/* Two separate grids plus an unreferenced vertex: +inf across. */
static void test_components(void)
{
    grid g = make_grid(4, 4, 1, 1, 0.2);
    uint32_t nv = 2 * g.nv + 1, nf = 2 * g.nf;
    double *xyz = malloc(3 * nv * sizeof *xyz);
    uint32_t *tri = malloc(3 * nf * sizeof *tri);
    for (uint32_t v = 0; v < g.nv; ++v) {
        memcpy(xyz + 3 * v, g.xyz + 3 * v, 3 * sizeof(double));
        memcpy(xyz + 3 * (g.nv + v), g.xyz + 3 * v, 3 * sizeof(double));
        xyz[3 * (g.nv + v) + 2] = 5; /* a copy above */
    }
    xyz[3 * (nv - 1)] = xyz[3 * (nv - 1) + 1] = xyz[3 * (nv - 1) + 2] = 0.5;
    for (uint32_t k = 0; k < 3 * g.nf; ++k) {
        tri[k] = g.tri[k];
        tri[3 * g.nf + k] = g.tri[k] + g.nv;
    }
    gs_mesh *m = mesh_of(xyz, nv, tri, nf);
    if (m) {
        gs_patch *p = whole(m);
        double *d = malloc(nv * sizeof *d);
        gs_source src = gs_source_vertex(3);
        if (gs_distance_field(p, GS_METHOD_EXACT, &src, 1, 0, d, NULL) == GS_OK) {
            for (uint32_t v = 0; v < g.nv; ++v) CHECK(isfinite(d[v]));
            for (uint32_t v = g.nv; v < nv; ++v) CHECK_MSG(isinf(d[v]) && d[v] > 0, "vertex %u", v);
        }
        /* the unreferenced vertex as a source: itself 0, all else +inf */
        src = gs_source_vertex(nv - 1);
        if (gs_distance_field(p, GS_METHOD_EXACT, &src, 1, 0, d, NULL) == GS_OK) {
            CHECK(d[nv - 1] == 0);
            for (uint32_t v = 0; v + 1 < nv; ++v) CHECK(isinf(d[v]));
        }
        /* one source per component: everything finite */
        gs_source two[2] = {gs_source_vertex(0), gs_source_point(g.nf + 3, 0.3, 0.3, 0.4)};
        if (gs_distance_field(p, GS_METHOD_EXACT, two, 2, 0, d, NULL) == GS_OK)
            for (uint32_t v = 0; v + 1 < nv; ++v) CHECK(isfinite(d[v]));
        free(d);
        gs_patch_free(p);
        gs_mesh_free(m);
    }
    free(xyz);
    free(tri);
    free_grid(&g);
}

/* Method names both ways; a NULL result pointer is an argument error (it
 * was written through). */
static void test_method_names(void)
{
    gs_method m = GS_METHOD_GRAPH;
    gs_error err = {0};
    CHECK(gs_method_from_name("heat", &m, &err) == GS_OK && m == GS_METHOD_HEAT);
    CHECK(gs_method_from_name("Exact", &m, &err) == GS_EARG && strstr(err.message, "unknown method 'Exact'"));
    CHECK(gs_method_from_name(NULL, &m, &err) == GS_EARG && m == GS_METHOD_HEAT);
    CHECK(gs_method_from_name("heat", NULL, &err) == GS_EARG && strstr(err.message, "method is NULL"));
    CHECK(gs_method_name((gs_method)5) == NULL && gs_method_name((gs_method)-1) == NULL);
    CHECK(gs_method_from_name("dgg", &m, &err) == GS_OK && m == GS_METHOD_DGG && !strcmp(gs_method_name(m), "dgg"));
}

/* Needle triangles that pass mesh validation (an octahedron with one vertex
 * moved to x = 2^32 - 1: aspect ratio 4e9) made the window propagation run
 * for hours (windows bouncing along the needles); the exact solver, and the
 * methods that start from it (fmm, heat), now give up with GS_EINTERNAL. */
static void test_needle_octahedron(void)
{
    double xyz[18] = {1, 0, 0, 4294967295.0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    uint32_t tri[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    gs_mesh *m = NULL;
    gs_patch *p = NULL;
    gs_error err = {0};
    CHECK(gs_mesh_create(xyz, 6, tri, 8, &m, &err) == GS_OK);
    if (!m || gs_patch_create(m, NULL, 0, &p, &err)) {
        gs_mesh_free(m);
        return;
    }
    double d[6];
    gs_source src = gs_source_vertex(0);
    const gs_method methods[2] = {GS_METHOD_EXACT, GS_METHOD_HEAT};
    for (int k = 0; k < 2; ++k) {
        int rc = gs_distance_field(p, methods[k], &src, 1, 0, d, &err);
        CHECK_MSG(rc == GS_EINTERNAL && strstr(err.message, "exact solver: gave up after"), "%s: %d %s",
                  gs_method_name(methods[k]), rc, err.message);
    }
    CHECK(gs_distance_field(p, GS_METHOD_GRAPH, &src, 1, 0, d, &err) == GS_OK && d[1] > 4294967295.0 && d[1] < 4294967298.0);
    gs_patch_free(p);
    gs_mesh_free(m);
}


/* gs_patch_create's connectivity (from the mesh's: twins, lengths, angles)
 * against gs__topo_build of the patch's own faces: equal bit for bit, for
 * blobs, scattered faces (pinched vertices, bow-ties) and the whole mesh
 * as a face list, on a bumpy sphere (saddles, boundary vertices). */
static void test_patch_topology(void)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_generate("sphere:3", &m, &err) == GS_OK, "generate: %s", err.message);
    if (!m) return;
    uint32_t nv = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    double *xyz = malloc(3 * sizeof(double) * nv);
    uint32_t *faces = malloc(sizeof(uint32_t) * nf);
    for (uint32_t v = 0; v < nv; ++v) {
        double s = 1 + 0.3 * (rnd() - 0.5);
        for (int k = 0; k < 3; ++k) xyz[3 * v + k] = s * m->xyz[3 * v + k];
    }
    gs_mesh *b = mesh_of(xyz, nv, m->tri, nf);
    for (int trial = 0; b && trial < 12; ++trial) {
        uint32_t n = 0;
        double r = trial < 4 ? 0.3 + 0.4 * trial : 0, keep = trial < 4 ? 1 : trial < 11 ? 0.2 + 0.1 * trial : 1;
        const double *c = b->xyz + 3 * (size_t)(uint32_t)(rnd() * nv);
        for (uint32_t f = 0; f < nf; ++f) {
            const double *q = b->xyz + 3 * (size_t)b->tri[3 * f];
            double d2 = 0;
            for (int k = 0; k < 3; ++k) d2 += (q[k] - c[k]) * (q[k] - c[k]);
            if ((r == 0 || d2 < r * r) && rnd() < keep) faces[n++] = f;
        }
        for (uint32_t i = n; i > 1; --i) { /* any order */
            uint32_t j = (uint32_t)(rnd() * i), t = faces[i - 1];
            faces[i - 1] = faces[j], faces[j] = t;
        }
        gs_patch *p = NULL;
        CHECK_MSG(gs_patch_create(b, faces, n, &p, &err) == GS_OK, "patch: %s", err.message);
        if (!p) continue;
        gs__topo t;
        CHECK_MSG(gs__topo_build(&t, p->nv, p->xyz, p->nf, p->tri, GS_TOPO_ALLOW_NONMANIFOLD_VERTICES, NULL, &err) ==
                      GS_OK, "topo: %s", err.message);
        const gs__topo *u = p->topo;
        size_t nh = 3 * (size_t)p->nf;
        CHECK(t.nv == u->nv && t.nf == u->nf && t.n_edges == u->n_edges);
        CHECK(!memcmp(t.opp, u->opp, nh * sizeof *t.opp) && !memcmp(t.len, u->len, nh * sizeof *t.len) &&
              !memcmp(t.angle, u->angle, nh * sizeof *t.angle) && !memcmp(t.vc, u->vc, nh * sizeof *t.vc));
        CHECK(!memcmp(t.vc_start, u->vc_start, (t.nv + 1) * sizeof *t.vc_start) &&
              !memcmp(t.vangle, u->vangle, t.nv * sizeof *t.vangle) && !memcmp(t.vflag, u->vflag, t.nv));
        for (uint32_t i = 0; i < n; ++i) CHECK(gs_patch_face_to_mesh(p, i) == faces[i]);
        for (uint32_t v = 1; v < p->nv; ++v) CHECK(p->vmap[v - 1] < p->vmap[v]);
        gs__topo_free(&t);
        gs_patch_free(p);
    }
    /* bad lists: a face twice, a face out of range */
    uint32_t two[2] = {3, 3}, out[1] = {nf};
    gs_patch *p = NULL;
    CHECK(gs_patch_create(b, two, 2, &p, &err) == GS_EARG && !p && strstr(err.message, "listed twice"));
    CHECK(gs_patch_create(b, out, 1, &p, &err) == GS_EARG && !p && strstr(err.message, "out of range"));
    free(xyz);
    free(faces);
    gs_mesh_free(b);
    gs_mesh_free(m);
}

/* gs__solver_path_bounded: bounded by 1.01 times the exact distance it
 * finds the same path length as gs_solver_path (vertex and point ends, on
 * a bumpy sphere: saddles as pseudo-sources); bounded below it, no path. */
static void test_bounded_path(void)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK(gs_mesh_generate("sphere:3", &m, &err) == GS_OK);
    if (!m) return;
    uint32_t nv = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    double *xyz = malloc(3 * sizeof(double) * nv);
    for (uint32_t v = 0; v < nv; ++v) {
        double s = 1 + 0.2 * (rnd() - 0.5);
        for (int k = 0; k < 3; ++k) xyz[3 * v + k] = s * m->xyz[3 * v + k];
    }
    gs_mesh *b = mesh_of(xyz, nv, m->tri, nf);
    gs_patch *p = b ? whole(b) : NULL;
    gs_solver *s = NULL;
    CHECK(p && gs_solver_create(p, GS_METHOD_EXACT, &s, &err) == GS_OK);
    for (int i = 0; s && i < 40; ++i) {
        gs_source x = i % 2 ? gs_source_vertex((uint32_t)(rnd() * nv)) : gs_source_point((uint32_t)(rnd() * nf), 0.2, 0.3, 0.5);
        gs_source y = i % 4 < 2 ? gs_source_vertex((uint32_t)(rnd() * nv)) : gs_source_point((uint32_t)(rnd() * nf), 0.6, 0.1, 0.3);
        gs_path *a = NULL, *c = NULL, *e = NULL;
        CHECK(gs_solver_path(s, &x, &y, &a, &err) == GS_OK);
        double d = gs_path_length(a);
        if (!(d > 0 && d < INFINITY)) {
            gs_path_free(a);
            continue;
        }
        CHECK(gs__solver_path_bounded(s, &x, &y, 1.01 * d, &c, &err) == GS_OK);
        CHECK_MSG(c && fabs(gs_path_length(c) - d) <= 1e-12 * d, "bounded path %d: %.17g, unbounded %.17g", i,
                  c ? gs_path_length(c) : NAN, d);
        CHECK(gs__solver_path_bounded(s, &x, &y, 0.99 * d, &e, &err) == GS_OK);
        CHECK(e && gs_path_num_points(e) == 0 && gs_path_length(e) == INFINITY);
        gs_path_free(a), gs_path_free(c), gs_path_free(e);
    }
    gs_solver_free(s);
    gs_patch_free(p);
    gs_mesh_free(b);
    gs_mesh_free(m);
    free(xyz);
}

int main(void)
{
    test_patch_topology();
    test_bounded_path();
    test_method_names();
    test_needle_octahedron();
    test_single_triangle();
    test_flat_sheets();
    test_needles();
    test_taut_strings();
    test_bowtie();
    test_cube();
    test_contract();
    test_components();
    printf("worst relative error against closed forms: %.3g\n", g_worst);
    return gs__test_finish("test_exact_basic");
}
