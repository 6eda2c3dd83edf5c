/* generate.c - gs_mesh_generate: synthetic meshes for tests and demos (grid,
 * peaks, plate with holes, cylinder, frustum, cube, torus, trefoil-knot
 * tube, icosphere, two
 * grids), parsed strictly from a spec string. Every mesh is consistently
 * oriented: faces are counter-clockwise seen from +z (flat meshes) or from
 * outside (closed and tube-like surfaces). Validated like any other mesh. */
#include "mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GEN_MAX_VERTICES (1u << 26) /* keeps 3*nv and 3*nf far below 2^32  */
#define GEN_MAX_ARGS 4
#define GEN_MIN_SIZE 1e-30 /* sizes: edges stay inside [GS_MESH_MIN_EDGE, */
#define GEN_MAX_SIZE 1e30  /* GS_MESH_MAX_EDGE] at any allowed resolution */

/* ---- growable vertex / face arrays ------------------------------------- */

typedef struct gen {
    double *xyz;
    uint32_t nv, cap_v;
    uint32_t *tri;
    uint32_t nf, cap_f;
    int oom;
} gen;

static uint32_t gen_vertex(gen *g, double x, double y, double z)
{
    if (g->nv == g->cap_v) {
        uint32_t cap = g->cap_v ? 2 * g->cap_v : 256;
        double *p = gs__realloc(g->xyz, 3 * (size_t)cap, sizeof *p);
        if (!p) {
            g->oom = 1;
            return 0;
        }
        g->xyz = p;
        g->cap_v = cap;
    }
    double *p = g->xyz + 3 * (size_t)g->nv;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return g->nv++;
}

static void gen_tri(gen *g, uint32_t a, uint32_t b, uint32_t c)
{
    if (g->nf == g->cap_f) {
        uint32_t cap = g->cap_f ? 2 * g->cap_f : 512;
        uint32_t *p = gs__realloc(g->tri, 3 * (size_t)cap, sizeof *p);
        if (!p) {
            g->oom = 1;
            return;
        }
        g->tri = p;
        g->cap_f = cap;
    }
    uint32_t *t = g->tri + 3 * (size_t)g->nf++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

static double gen_dist2(const gen *g, uint32_t a, uint32_t b)
{
    const double *p = g->xyz + 3 * (size_t)a, *q = g->xyz + 3 * (size_t)b;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

/* A quad a,b,c,d (counter-clockwise) as two triangles, split along the
 * shorter diagonal (a-c on ties, which keeps regular grids uniform). */
static void gen_quad(gen *g, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    if (g->oom) return;
    if (gen_dist2(g, b, d) < gen_dist2(g, a, c) * (1 - 1e-12)) {
        gen_tri(g, a, b, d);
        gen_tri(g, b, c, d);
    } else {
        gen_tri(g, a, b, c);
        gen_tri(g, a, c, d);
    }
}

/* ---- a small uint64 -> uint32 hash map (welding, edge midpoints) ------- */

typedef struct gen_map {
    uint64_t *key;
    uint32_t *val;
    size_t mask;
} gen_map;

#define GEN_EMPTY UINT64_MAX

static int map_init(gen_map *m, size_t expected)
{
    size_t cap = 64;
    while (cap < 2 * expected) cap *= 2;
    m->key = gs__malloc(cap, sizeof *m->key);
    m->val = gs__malloc(cap, sizeof *m->val);
    m->mask = cap - 1;
    if (!m->key || !m->val) return -1;
    for (size_t i = 0; i < cap; ++i) m->key[i] = GEN_EMPTY;
    return 0;
}

static void map_free(gen_map *m)
{
    free(m->key);
    free(m->val);
}

/* Slot of key: either holding it or empty. The map never fills up. */
static size_t map_slot(const gen_map *m, uint64_t key)
{
    uint64_t h = key * 0x9E3779B97F4A7C15ull;
    size_t i = (size_t)(h ^ (h >> 29)) & m->mask;
    while (m->key[i] != GEN_EMPTY && m->key[i] != key) i = (i + 1) & m->mask;
    return i;
}

/* ---- size checks -------------------------------------------------------- */

static int check_size(uint64_t nv, uint64_t nf, const char *spec, gs_error *err)
{
    if (nv > GEN_MAX_VERTICES || nf > 2 * (uint64_t)GEN_MAX_VERTICES + 16)
        return gs__fail(err, GS_ELIMIT,
                        "mesh spec \"%s\": %llu vertices / %llu faces exceed the generator "
                        "limit of %u vertices",
                        spec, (unsigned long long)nv, (unsigned long long)nf, GEN_MAX_VERTICES);
    return GS_OK;
}

/* ---- flat grids and height fields -------------------------------------- */

/* An nx x ny vertex grid on [x0,x0+w] x [y0,y0+h]; z from fz (or 0). */
static void grid_block(gen *g, uint32_t nx, uint32_t ny, double x0, double y0, double w,
                       double h, double (*fz)(double, double))
{
    uint32_t base = g->nv;
    for (uint32_t j = 0; j < ny; ++j)
        for (uint32_t i = 0; i < nx; ++i) {
            double x = x0 + w * i / (nx - 1), y = y0 + h * j / (ny - 1);
            gen_vertex(g, x, y, fz ? fz(x, y) : 0.0);
        }
    for (uint32_t j = 0; j + 1 < ny; ++j)
        for (uint32_t i = 0; i + 1 < nx; ++i) {
            uint32_t a = base + j * nx + i;
            gen_quad(g, a, a + 1, a + 1 + nx, a + nx);
        }
}

static double peaks_z(double x, double y)
{
    return 3 * (1 - x) * (1 - x) * exp(-x * x - (y + 1) * (y + 1)) -
           10 * (x / 5 - x * x * x - pow(y, 5)) * exp(-x * x - y * y) -
           exp(-(x + 1) * (x + 1) - y * y) / 3;
}

typedef struct gen_args {
    const char *spec;
    uint32_t n[2];   /* integer arguments */
    double r[2];     /* real arguments (defaults filled in) */
} gen_args;

static int make_grid(gen *g, const gen_args *a, gs_error *err)
{
    int rc = check_size((uint64_t)a->n[0] * a->n[1], 2 * (uint64_t)a->n[0] * a->n[1], a->spec, err);
    if (!rc) grid_block(g, a->n[0], a->n[1], 0, 0, a->r[0], a->r[1], NULL);
    return rc;
}

/* MATLAB's peaks(N) on [-3,3]^2; with a side W the same heights sit on a
 * W x W grid centred on the origin (x and y scaled by W/6, z unchanged):
 * peaks:50,49 is the mesh `surf(peaks(50))` draws, whose x and y are the
 * column and row numbers 1..50. */
static int make_peaks(gen *g, const gen_args *a, gs_error *err)
{
    int rc = check_size((uint64_t)a->n[0] * a->n[0], 2 * (uint64_t)a->n[0] * a->n[0], a->spec, err);
    if (rc) return rc;
    uint32_t base = g->nv;
    grid_block(g, a->n[0], a->n[0], -3, -3, 6, 6, peaks_z);
    double s = a->r[0] / 6; /* 1 for the default: the classic mesh, bit for bit */
    if (!g->oom && s != 1)
        for (uint32_t v = base; v < g->nv; ++v) g->xyz[3 * (size_t)v] *= s, g->xyz[3 * (size_t)v + 1] *= s;
    return GS_OK;
}

/* A flat N x N grid on [0,1]^2 graded towards the origin: vertex (i, j) at
 * ((i/(N-1))^P, (j/(N-1))^P), cells from (1/(N-1))^P to about P/(N-1) wide
 * (a boundary layer's grading; P = 7, N = 40: needles 7e-12 wide and 0.2
 * long). Flat and convex: every distance is the straight one. */
static int make_graded(gen *g, const gen_args *a, gs_error *err)
{
    double P = a->r[0];
    if (!(P >= 1 && P <= 8))
        return gs__fail(err, GS_EARG, "mesh spec \"%s\": the grading exponent P = %g must be from 1 to 8; "
                        "expected graded:N[,P]", a->spec, P);
    int rc = check_size((uint64_t)a->n[0] * a->n[0], 2 * (uint64_t)a->n[0] * a->n[0], a->spec, err);
    if (rc) return rc;
    uint32_t base = g->nv;
    grid_block(g, a->n[0], a->n[0], 0, 0, 1, 1, NULL);
    for (uint32_t v = base; !g->oom && v < g->nv; ++v) {
        uint32_t i = (v - base) % a->n[0], j = (v - base) / a->n[0];
        g->xyz[3 * (size_t)v] = pow((double)i / (a->n[0] - 1), P);
        g->xyz[3 * (size_t)v + 1] = pow((double)j / (a->n[0] - 1), P);
    }
    return GS_OK;
}

static int make_two(gen *g, const gen_args *a, gs_error *err)
{
    int rc = check_size(2 * (uint64_t)a->n[0] * a->n[0], 4 * (uint64_t)a->n[0] * a->n[0], a->spec, err);
    if (rc) return rc;
    grid_block(g, a->n[0], a->n[0], 0, 0, 1, 1, NULL);
    grid_block(g, a->n[0], a->n[0], 2, 0, 1, 1, NULL);
    return GS_OK;
}

/* ---- plate with holes ---------------------------------------------------
 * [0,1]^2 split into 2 x 2 blocks of side 1/2 on a lattice of (2M+1)^2
 * points. Three blocks hold a centred round hole (a regular 4M-gon); the
 * ring between hole and block square is meshed in polar layout: 4M spokes,
 * K rings spaced geometrically from the hole's edge length to the lattice
 * spacing. The fourth block is a plain grid. Shared lattice points are one
 * vertex, so the plate is a manifold with 1 + 3 boundary loops. */

static const double plate_radius[4] = {0.15, 0.10, 0.12, 0.0}; /* blocks (0,0) (1,0) (0,1) (1,1) */

/* Rings between a hole of radius r and the block square for M cells a side. */
static uint32_t plate_rings(uint32_t M, double r)
{
    double h0 = 2 * M_PI * r / (4.0 * M), h1 = 0.5 / M;
    double gap = 0.5 * (0.25 + 0.25 * sqrt(2.0)) - r; /* mean hole-to-square distance */
    double k = fabs(h1 - h0) < 1e-3 * h1 ? gap / h1 : gap * log(h1 / h0) / (h1 - h0);
    return k < 1 ? 1 : (uint32_t)lround(k);
}

static uint64_t plate_count(uint32_t M)
{
    uint64_t n = (uint64_t)(2 * M + 1) * (2 * M + 1);
    for (int b = 0; b < 4; ++b)
        if (plate_radius[b] > 0)
            n += 4 * (uint64_t)M * plate_rings(M, plate_radius[b]) - (uint64_t)(M - 1) * (M - 1);
    return n;
}

typedef struct plate_ctx {
    gen *g;
    uint32_t M, L;   /* cells per block side; lattice points per side */
    uint32_t *lat;   /* L*L vertex ids, GS_NONE until used */
} plate_ctx;

static uint32_t plate_lattice(plate_ctx *c, uint32_t I, uint32_t J)
{
    uint32_t *id = &c->lat[(size_t)J * c->L + I];
    if (*id == GS_NONE) *id = gen_vertex(c->g, (double)I / (c->L - 1), (double)J / (c->L - 1), 0);
    return *id;
}

/* Lattice coordinates of point p of the perimeter of the block with lower
 * left corner (I0,J0), counter-clockwise from the lower right corner. */
static void plate_perimeter(uint32_t M, uint32_t p, uint32_t I0, uint32_t J0, uint32_t *I,
                            uint32_t *J)
{
    uint32_t side = p / M, s = p % M;
    switch (side) {
    case 0: *I = I0 + M; *J = J0 + s; break;
    case 1: *I = I0 + M - s; *J = J0 + M; break;
    case 2: *I = I0; *J = J0 + M - s; break;
    default: *I = I0 + s; *J = J0; break;
    }
}

static int plate_hole_block(plate_ctx *c, uint32_t bx, uint32_t by, double r)
{
    uint32_t M = c->M, P = 4 * M, K = plate_rings(M, r);
    uint32_t I0 = bx * M, J0 = by * M;
    double cx = 0.25 + 0.5 * bx, cy = 0.25 + 0.5 * by;
    double h0 = 2 * M_PI * r / P, h1 = 0.5 / M;
    double q = K > 1 ? pow(h1 / h0, 1.0 / (K - 1)) : 1, total = 0;
    for (uint32_t k = 0; k < K; ++k) total += pow(q, k);
    uint32_t *ring = gs__malloc((size_t)(K + 1) * P, sizeof *ring);
    if (!ring) return -1;
    double s = 0;
    for (uint32_t k = 0; k <= K; ++k) {
        for (uint32_t p = 0; p < P; ++p) {
            uint32_t I, J;
            plate_perimeter(M, p, I0, J0, &I, &J);
            if (k == K) {
                ring[(size_t)k * P + p] = plate_lattice(c, I, J);
                continue;
            }
            double th = -M_PI / 4 + 2 * M_PI * p / P;
            double hx = cx + r * cos(th), hy = cy + r * sin(th);
            double sx = (double)I / (c->L - 1), sy = (double)J / (c->L - 1);
            ring[(size_t)k * P + p] = gen_vertex(c->g, (1 - s) * hx + s * sx, (1 - s) * hy + s * sy, 0);
        }
        if (k < K) s += pow(q, k) / total;
        if (k + 1 == K) s = 1;
    }
    for (uint32_t k = 0; k < K; ++k)
        for (uint32_t p = 0; p < P; ++p) {
            uint32_t p1 = (p + 1) % P;
            /* inner(p) -> outer(p) -> outer(p+1) -> inner(p+1): counter-clockwise */
            gen_quad(c->g, ring[(size_t)k * P + p], ring[(size_t)(k + 1) * P + p],
                     ring[(size_t)(k + 1) * P + p1], ring[(size_t)k * P + p1]);
        }
    free(ring);
    return 0;
}

static void plate_plain_block(plate_ctx *c, uint32_t bx, uint32_t by)
{
    uint32_t I0 = bx * c->M, J0 = by * c->M;
    for (uint32_t j = 0; j < c->M; ++j)
        for (uint32_t i = 0; i < c->M; ++i) {
            uint32_t I = I0 + i, J = J0 + j;
            uint32_t a = plate_lattice(c, I, J), b = plate_lattice(c, I + 1, J);
            uint32_t d = plate_lattice(c, I + 1, J + 1), e = plate_lattice(c, I, J + 1);
            gen_quad(c->g, a, b, d, e);
        }
}

static int make_plate(gen *g, const gen_args *a, gs_error *err)
{
    /* the M whose vertex count is closest to N (counts grow with M) */
    uint32_t M = 2;
    while (M < 4096 && plate_count(M + 1) <= a->n[0]) ++M;
    uint64_t lo = plate_count(M), hi = plate_count(M + 1);
    if (lo < a->n[0] && hi - a->n[0] < a->n[0] - lo) ++M;
    int rc = check_size(plate_count(M), 2 * plate_count(M), a->spec, err);
    if (rc) return rc;
    plate_ctx c = {g, M, 2 * M + 1, NULL};
    c.lat = gs__malloc((size_t)c.L * c.L, sizeof *c.lat);
    if (!c.lat) return gs__fail(err, GS_ENOMEM, "out of memory generating \"%s\"", a->spec);
    for (size_t i = 0; i < (size_t)c.L * c.L; ++i) c.lat[i] = GS_NONE;
    for (uint32_t b = 0; b < 4 && !g->oom; ++b) {
        if (plate_radius[b] <= 0)
            plate_plain_block(&c, b % 2, b / 2);
        else if (plate_hole_block(&c, b % 2, b / 2, plate_radius[b]))
            g->oom = 1;
    }
    free(c.lat);
    return GS_OK;
}

/* ---- tubes: cylinder and frustum ----------------------------------------
 * NU vertices around, NV rings from z = 0 to z = H; ring j has radius
 * R * (1 - taper * j / (NV-1)). Faces are planar quads split in two, so the
 * surface is a prism (cylinder) or a truncated pyramid (cone). */

static void tube(gen *g, uint32_t nu, uint32_t nv, double R, double H, double taper)
{
    for (uint32_t j = 0; j < nv; ++j) {
        double t = (double)j / (nv - 1), rad = R * (1 - taper * t);
        for (uint32_t i = 0; i < nu; ++i) {
            double u = 2 * M_PI * i / nu;
            gen_vertex(g, rad * cos(u), rad * sin(u), H * t);
        }
    }
    for (uint32_t j = 0; j + 1 < nv; ++j)
        for (uint32_t i = 0; i < nu; ++i) {
            uint32_t i1 = (i + 1) % nu;
            gen_quad(g, j * nu + i, j * nu + i1, (j + 1) * nu + i1, (j + 1) * nu + i);
        }
}

static int make_cylinder(gen *g, const gen_args *a, gs_error *err)
{
    uint64_t n = (uint64_t)a->n[0] * a->n[1];
    int rc = check_size(n, 2 * n, a->spec, err);
    if (!rc) tube(g, a->n[0], a->n[1], a->r[0], a->r[1], 0.0);
    return rc;
}

/* The cone with base radius R is cut at height H where its radius is R/4
 * (so its apex would be at 4H/3): a frustum, free of the singular apex. */
static int make_cone(gen *g, const gen_args *a, gs_error *err)
{
    uint64_t n = (uint64_t)a->n[0] * a->n[1];
    int rc = check_size(n, 2 * n, a->spec, err);
    if (!rc) tube(g, a->n[0], a->n[1], a->r[0], a->r[1], 0.75);
    return rc;
}

/* ---- torus -------------------------------------------------------------- */

static int make_torus(gen *g, const gen_args *a, gs_error *err)
{
    uint32_t nu = a->n[0], nv = a->n[1];
    double R = a->r[0], r = a->r[1];
    if (!(r < R))
        return gs__fail(err, GS_EARG, "mesh spec \"%s\": the tube radius r = %g must be "
                        "smaller than the ring radius R = %g; expected torus:NU,NV[,R,r] with R > r",
                        a->spec, r, R);
    uint64_t n = (uint64_t)nu * nv;
    int rc = check_size(n, 2 * n, a->spec, err);
    if (rc) return rc;
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
            gen_vertex(g, (R + r * cos(v)) * cos(u), (R + r * cos(v)) * sin(u), r * sin(v));
        }
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            uint32_t i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            gen_quad(g, i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1);
        }
    return GS_OK;
}

/* ---- knot: a tube around a (2,3) torus knot (trefoil) -------------------
 * Centre line c(t) = ((2 + cos 3t) cos 2t, (2 + cos 3t) sin 2t, sin 3t),
 * t in [0, 2 pi): NU rings along it, NV vertices around each, at distance r
 * in the plane of its Frenet normal and binormal (the curvature never
 * vanishes, so the frame is smooth and closes up). The tube winds and bends
 * tightly: a hard case for separator functions and same-leaf distances. */

static void knot_frame(double t, double c[3], double n[3], double b[3])
{
    double s3 = sin(3 * t), c3 = cos(3 * t), s2 = sin(2 * t), c2 = cos(2 * t), rr = 2 + c3;
    double d1[3] = {-3 * s3 * c2 - 2 * rr * s2, -3 * s3 * s2 + 2 * rr * c2, 3 * c3};
    double d2[3] = {-9 * c3 * c2 + 12 * s3 * s2 - 4 * rr * c2, -9 * c3 * s2 - 12 * s3 * c2 - 4 * rr * s2,
                    -9 * s3};
    c[0] = rr * c2, c[1] = rr * s2, c[2] = s3;
    double bx[3] = {d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0]};
    double lb = sqrt(bx[0] * bx[0] + bx[1] * bx[1] + bx[2] * bx[2]);
    double lt = sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
    for (int k = 0; k < 3; ++k) b[k] = bx[k] / lb;
    n[0] = (b[1] * d1[2] - b[2] * d1[1]) / lt;
    n[1] = (b[2] * d1[0] - b[0] * d1[2]) / lt;
    n[2] = (b[0] * d1[1] - b[1] * d1[0]) / lt;
}

static int make_knot(gen *g, const gen_args *a, gs_error *err)
{
    uint32_t nu = a->n[0], nv = a->n[1];
    double r = a->r[0];
    if (!(r <= 0.5))
        return gs__fail(err, GS_EARG, "mesh spec \"%s\": the tube radius r = %g must be at most 0.5 "
                        "(the tube would cross itself); expected knot:NU,NV[,r]", a->spec, r);
    uint64_t n = (uint64_t)nu * nv;
    int rc = check_size(n, 2 * n, a->spec, err);
    if (rc) return rc;
    for (uint32_t i = 0; i < nu; ++i) {
        double c[3], nn[3], b[3];
        knot_frame(2 * M_PI * i / nu, c, nn, b);
        for (uint32_t j = 0; j < nv; ++j) {
            double v = 2 * M_PI * j / nv, cv = r * cos(v), sv = r * sin(v);
            gen_vertex(g, c[0] + cv * nn[0] + sv * b[0], c[1] + cv * nn[1] + sv * b[1], c[2] + cv * nn[2] + sv * b[2]);
        }
    }
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            uint32_t i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            gen_quad(g, i * nv + j, i * nv + j1, i1 * nv + j1, i1 * nv + j); /* outward */
        }
    return GS_OK;
}

/* ---- cube: six N x N grids welded along the edges ----------------------- */

/* Per face: origin and the two lattice directions u, v with u x v outward. */
static const int cube_frame[6][3][3] = {
    {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, /* z = 0, normal -z */
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, /* z = S, normal +z */
    {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, /* y = 0, normal -y */
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, /* y = S, normal +y */
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, /* x = 0, normal -x */
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, /* x = S, normal +x */
};

static uint32_t cube_vertex(gen *g, gen_map *m, uint32_t N, double S, int f, uint32_t a, uint32_t b)
{
    uint32_t l[3];
    for (int k = 0; k < 3; ++k)
        l[k] = cube_frame[f][0][k] * N + cube_frame[f][1][k] * a + cube_frame[f][2][k] * b;
    uint64_t key = ((uint64_t)l[0] * (N + 1) + l[1]) * (N + 1) + l[2];
    size_t i = map_slot(m, key);
    if (m->key[i] == GEN_EMPTY) {
        m->key[i] = key;
        m->val[i] = gen_vertex(g, S * l[0] / N, S * l[1] / N, S * l[2] / N);
    }
    return m->val[i];
}

static int make_cube(gen *g, const gen_args *a, gs_error *err)
{
    uint32_t N = a->n[0];
    uint64_t nv = 6 * (uint64_t)N * N + 2;
    int rc = check_size(nv, 2 * nv, a->spec, err);
    if (rc) return rc;
    gen_map m;
    if (map_init(&m, (size_t)nv)) {
        map_free(&m);
        return gs__fail(err, GS_ENOMEM, "out of memory generating \"%s\"", a->spec);
    }
    for (int f = 0; f < 6; ++f)
        for (uint32_t b = 0; b < N; ++b)
            for (uint32_t i = 0; i < N; ++i) {
                uint32_t v00 = cube_vertex(g, &m, N, a->r[0], f, i, b);
                uint32_t v10 = cube_vertex(g, &m, N, a->r[0], f, i + 1, b);
                uint32_t v11 = cube_vertex(g, &m, N, a->r[0], f, i + 1, b + 1);
                uint32_t v01 = cube_vertex(g, &m, N, a->r[0], f, i, b + 1);
                gen_quad(g, v00, v10, v11, v01);
            }
    map_free(&m);
    return GS_OK;
}

/* ---- icosphere ---------------------------------------------------------- */

static void unit(double *p)
{
    double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; ++k) p[k] /= l;
}

/* The icosahedron: vertices (0, +-1, +-phi) and cyclic permutations; its
 * faces are the triples at mutual distance 2, oriented outward. */
static void icosahedron(gen *g)
{
    const double t = (1 + sqrt(5.0)) / 2;
    for (int c = 0; c < 3; ++c)
        for (int s = 0; s < 4; ++s) {
            double p[3];
            p[c] = 0;
            p[(c + 1) % 3] = (s & 1) ? -1 : 1;
            p[(c + 2) % 3] = (s & 2) ? -t : t;
            unit(p);
            gen_vertex(g, p[0], p[1], p[2]);
        }
    double e2 = gen_dist2(g, 0, 1) < gen_dist2(g, 0, 2) ? gen_dist2(g, 0, 1) : gen_dist2(g, 0, 2);
    for (uint32_t a = 0; a < 12; ++a)
        for (uint32_t b = a + 1; b < 12; ++b)
            for (uint32_t c = b + 1; c < 12; ++c) {
                if (fabs(gen_dist2(g, a, b) - e2) > 1e-9 || fabs(gen_dist2(g, b, c) - e2) > 1e-9 ||
                    fabs(gen_dist2(g, a, c) - e2) > 1e-9)
                    continue;
                const double *p = g->xyz + 3 * a, *q = g->xyz + 3 * b, *r = g->xyz + 3 * c;
                double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
                double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                               u[0] * v[1] - u[1] * v[0]};
                if (n[0] * p[0] + n[1] * p[1] + n[2] * p[2] > 0)
                    gen_tri(g, a, b, c);
                else
                    gen_tri(g, a, c, b);
            }
}

static uint32_t midpoint(gen *g, gen_map *m, uint32_t a, uint32_t b)
{
    uint64_t key = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
    size_t i = map_slot(m, key);
    if (m->key[i] == GEN_EMPTY) {
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = 0.5 * (g->xyz[3 * (size_t)a + k] + g->xyz[3 * (size_t)b + k]);
        unit(p);
        m->key[i] = key;
        m->val[i] = gen_vertex(g, p[0], p[1], p[2]);
    }
    return m->val[i];
}

/* Split every face of g in four, midpoints pushed to the unit sphere. */
static int subdivide(gen *g)
{
    uint32_t nf = g->nf;
    uint32_t *old = gs__malloc(3 * (size_t)nf, sizeof *old);
    gen_map m;
    if (!old || map_init(&m, 3 * (size_t)nf / 2)) {
        free(old);
        return -1;
    }
    memcpy(old, g->tri, 3 * (size_t)nf * sizeof *old);
    g->nf = 0;
    for (uint32_t f = 0; f < nf && !g->oom; ++f) {
        uint32_t a = old[3 * f], b = old[3 * f + 1], c = old[3 * f + 2];
        uint32_t ab = midpoint(g, &m, a, b), bc = midpoint(g, &m, b, c), ca = midpoint(g, &m, c, a);
        gen_tri(g, a, ab, ca);
        gen_tri(g, ab, b, bc);
        gen_tri(g, ca, bc, c);
        gen_tri(g, ab, bc, ca);
    }
    map_free(&m);
    free(old);
    return 0;
}

static int make_sphere(gen *g, const gen_args *a, gs_error *err)
{
    icosahedron(g);
    for (uint32_t s = 0; s < a->n[0] && !g->oom; ++s)
        if (subdivide(g)) g->oom = 1;
    (void)err;
    return GS_OK;
}

/* ---- the spec table and the parser -------------------------------------- */

typedef struct gen_kind {
    const char *name, *usage;
    int n_int;             /* required integer arguments            */
    uint32_t int_min[2], int_max;
    int n_real;            /* optional real arguments (all or none) */
    double real_def[2];
    int (*make)(gen *g, const gen_args *a, gs_error *err);
} gen_kind;

static const gen_kind kinds[] = {
    {"grid", "grid:NX,NY[,W,H]", 2, {2, 2}, 1u << 24, 2, {1, 1}, make_grid},
    {"peaks", "peaks:N[,W]", 1, {2, 0}, 1u << 24, 1, {6, 0}, make_peaks},
    {"plate", "plate:N", 1, {50, 0}, GEN_MAX_VERTICES, 0, {0, 0}, make_plate},
    {"cylinder", "cylinder:NU,NV[,R,H]", 2, {3, 2}, 1u << 24, 2, {1, 1}, make_cylinder},
    {"cone", "cone:NU,NV[,R,H]", 2, {3, 2}, 1u << 24, 2, {1, 1}, make_cone},
    {"cube", "cube:N[,S]", 1, {1, 0}, 1u << 12, 1, {1, 0}, make_cube},
    {"torus", "torus:NU,NV[,R,r]", 2, {3, 3}, 1u << 24, 2, {1, 0.4}, make_torus},
    {"knot", "knot:NU,NV[,r]", 2, {8, 3}, 1u << 24, 1, {0.4, 0}, make_knot},
    {"sphere", "sphere:N", 1, {0, 0}, 9, 0, {0, 0}, make_sphere},
    {"two", "two:N", 1, {2, 0}, 1u << 24, 0, {0, 0}, make_two},
    {"graded", "graded:N[,P]", 1, {2, 0}, 1u << 12, 1, {3, 0}, make_graded},
};
#define N_KINDS (sizeof kinds / sizeof kinds[0])

static const char accepted[] =
    "accepted: grid:NX,NY[,W,H] peaks:N[,W] plate:N cylinder:NU,NV[,R,H] cone:NU,NV[,R,H] "
    "cube:N[,S] torus:NU,NV[,R,r] knot:NU,NV[,r] sphere:N two:N graded:N[,P]";

/* Split s (after the colon) into comma-separated tokens; 0 on success. */
static int split_args(const char *s, char tok[GEN_MAX_ARGS][64], int *n)
{
    *n = 0;
    if (!*s) return 0;
    for (;;) {
        const char *e = strchr(s, ',');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        if (*n == GEN_MAX_ARGS || len == 0 || len >= 64) return -1;
        memcpy(tok[*n], s, len);
        tok[(*n)++][len] = 0;
        if (!e) return 0;
        s = e + 1;
    }
}

static int parse_uint(const char *t, uint32_t lo, uint32_t hi, uint32_t *out)
{
    uint64_t v = 0;
    if (!*t) return -1;
    for (; *t; ++t) {
        if (*t < '0' || *t > '9') return -1;
        v = v * 10 + (uint64_t)(*t - '0');
        if (v > hi) return -1;
    }
    if (v < lo) return -1;
    *out = (uint32_t)v;
    return 0;
}

/* Strict: digits with an optional '.' and exponent ("2", "0.5", ".5", "1e3");
 * no blanks, sign, hex, inf or nan, which strtod alone would accept. */
static int parse_real(const char *t, double *out)
{
    const char *p = t;
    int digits = 0;
    while (*p >= '0' && *p <= '9') ++p, ++digits;
    if (*p == '.')
        for (++p; *p >= '0' && *p <= '9'; ++p) ++digits;
    if (!digits) return -1;
    if (*p == 'e' || *p == 'E') {
        ++p;
        if (*p == '+' || *p == '-') ++p;
        if (!(*p >= '0' && *p <= '9')) return -1;
        while (*p >= '0' && *p <= '9') ++p;
    }
    if (*p) return -1;
    char *end;
    double v = strtod(t, &end);
    if (*end || !(v >= GEN_MIN_SIZE && v <= GEN_MAX_SIZE)) return -1;
    *out = v;
    return 0;
}

static int parse_args(const gen_kind *k, const char *spec, const char *rest, gen_args *a,
                      gs_error *err)
{
    char tok[GEN_MAX_ARGS][64];
    int n;
    if (split_args(rest, tok, &n) || (n != k->n_int && n != k->n_int + k->n_real))
        return gs__fail(err, GS_EARG,
                        "bad mesh spec \"%s\": %s takes %d integer%s%s; expected %s",
                        spec, k->name, k->n_int, k->n_int > 1 ? "s" : "",
                        k->n_real ? " then optionally sizes" : "", k->usage);
    for (int i = 0; i < k->n_int; ++i)
        if (parse_uint(tok[i], k->int_min[i], k->int_max, &a->n[i]))
            return gs__fail(err, GS_EARG,
                            "bad mesh spec \"%s\": argument %d (\"%s\") must be an integer "
                            "from %u to %u; expected %s",
                            spec, i + 1, tok[i], k->int_min[i], k->int_max, k->usage);
    for (int i = 0; i < k->n_real; ++i) {
        a->r[i] = k->real_def[i];
        if (n > k->n_int && parse_real(tok[k->n_int + i], &a->r[i]))
            return gs__fail(err, GS_EARG,
                            "bad mesh spec \"%s\": argument %d (\"%s\") must be a plain "
                            "decimal number from %g to %g; expected %s",
                            spec, k->n_int + i + 1, tok[k->n_int + i], GEN_MIN_SIZE, GEN_MAX_SIZE,
                            k->usage);
    }
    return GS_OK;
}

static const gen_kind *find_kind(const char *spec, const char **rest)
{
    const char *colon = strchr(spec, ':');
    if (!colon) return NULL;
    size_t len = (size_t)(colon - spec);
    for (size_t i = 0; i < N_KINDS; ++i)
        if (strlen(kinds[i].name) == len && !memcmp(kinds[i].name, spec, len)) {
            *rest = colon + 1;
            return &kinds[i];
        }
    return NULL;
}

int gs_mesh_generate(const char *spec, gs_mesh **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_mesh_generate: out is NULL");
    *out = NULL;
    if (!spec) return gs__fail(err, GS_EARG, "gs_mesh_generate: spec is NULL; %s", accepted);
    const char *rest = NULL;
    const gen_kind *k = find_kind(spec, &rest);
    if (!k)
        return gs__fail(err, GS_EARG, "bad mesh spec \"%s\": unknown kind or missing ':'; %s",
                        spec, accepted);
    gen_args a = {spec, {0, 0}, {0, 0}};
    int rc = parse_args(k, spec, rest, &a, err);
    if (rc) return rc;
    gen g = {0};
    rc = k->make(&g, &a, err);
    if (!rc && g.oom) rc = gs__fail(err, GS_ENOMEM, "out of memory generating \"%s\"", spec);
    if (rc) {
        free(g.xyz);
        free(g.tri);
        return rc;
    }
    return gs__mesh_adopt(g.xyz, g.nv, g.tri, g.nf, NULL, out, err);
}
