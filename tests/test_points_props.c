/* test_points_props.c - randomized properties of the surface-point queries
 * (gs_db_point_*, src/query/points.c) over generated meshes and several
 * kinds of database (defaults, small leaves, leaf tables, sampled
 * functions, two components, no query cache, the query cache's large
 * layout): thousands of random points inside faces, on edges and at
 * vertices, each also named another way (the other face of
 * its edge, another face of its vertex, the corners in another order, a
 * zero weight written as -0.0 or as a negative within GS_POINT_WEIGHT_MIN);
 * the invariants the header documents must hold bit for bit: symmetry, the
 * same point named either way, vertex points = gs_db_distance, d(p, p) = 0,
 * d >= |p - q|, never negative or NaN, +inf exactly between components, the
 * batch = the single queries (with bad pairs among them) and the field =
 * the single queries. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static uint32_t irand(uint32_t n)
{
    return (uint32_t)(urand() * n) % n;
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* The mesh, the faces around each vertex (CSR) and its components. */
typedef struct meshinfo {
    const gs_mesh *m;
    uint32_t nv, nf;
    const uint32_t *tri;
    const double *xyz;
    uint32_t *vstart, *vface; /* faces of vertex v: vface[vstart[v] .. vstart[v+1]) */
    uint32_t *comp;           /* component of each vertex (union-find roots)       */
} meshinfo;

static uint32_t find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
}

static int info_init(meshinfo *mi, const gs_mesh *m)
{
    mi->m = m, mi->nv = gs_mesh_num_vertices(m), mi->nf = gs_mesh_num_faces(m);
    mi->tri = gs_mesh_faces(m), mi->xyz = gs_mesh_positions(m);
    mi->vstart = calloc(mi->nv + 1, sizeof *mi->vstart);
    mi->vface = malloc(sizeof *mi->vface * 3 * (size_t)mi->nf);
    mi->comp = malloc(sizeof *mi->comp * mi->nv);
    if (!mi->vstart || !mi->vface || !mi->comp) return -1;
    for (size_t k = 0; k < 3 * (size_t)mi->nf; ++k) mi->vstart[mi->tri[k] + 1]++;
    for (uint32_t v = 0; v < mi->nv; ++v) mi->vstart[v + 1] += mi->vstart[v], mi->comp[v] = v;
    uint32_t *fill = calloc(mi->nv, sizeof *fill);
    if (!fill) return -1;
    for (uint32_t f = 0; f < mi->nf; ++f)
        for (int i = 0; i < 3; ++i) {
            uint32_t v = mi->tri[3 * (size_t)f + i];
            mi->vface[mi->vstart[v] + fill[v]++] = f;
            uint32_t a = find(mi->comp, v), b = find(mi->comp, mi->tri[3 * (size_t)f + (i + 1) % 3]);
            mi->comp[a] = b;
        }
    for (uint32_t v = 0; v < mi->nv; ++v) mi->comp[v] = find(mi->comp, v);
    free(fill);
    return 0;
}

static void info_free(meshinfo *mi)
{
    free(mi->vstart);
    free(mi->vface);
    free(mi->comp);
}

/* A point given twice: p and alt (the same point named another way), its
 * position, and a vertex of its face (for the component). */
typedef struct tpoint {
    gs_surface_point p, alt;
    double x[3];
    uint32_t vertex; /* its vertex id if it is a vertex point, else GS_NONE */
    uint32_t anyc;   /* a corner of nonzero weight                          */
} tpoint;

/* A zero weight, written one of the ways that mean 0. */
static double zero(void)
{
    double r = urand();
    return r < 0.5 ? 0.0 : r < 0.75 ? -0.0 : -1e-13;
}

/* The face f named with its corners rotated by r, weights b (in f's order). */
static gs_surface_point on_face(const meshinfo *mi, uint32_t f, int r, const double *b)
{
    const uint32_t *t = mi->tri + 3 * (size_t)f;
    return gs_surface_point_make(t[r % 3], t[(r + 1) % 3], t[(r + 2) % 3], b[r % 3], b[(r + 1) % 3], b[(r + 2) % 3]);
}

/* Position sum_i w_i x(corner_i), with the weights clamped at 0 and
 * normalised. */
static void position(const meshinfo *mi, const gs_surface_point *p, double *x)
{
    double w[3], s = 0;
    for (int i = 0; i < 3; ++i) w[i] = p->weight[i] > 0 ? p->weight[i] : 0, s += w[i];
    for (int c = 0; c < 3; ++c) {
        x[c] = 0;
        for (int i = 0; i < 3; ++i) x[c] += w[i] / s * mi->xyz[3 * (size_t)p->corner[i] + c];
    }
}

static tpoint random_tpoint(const meshinfo *mi)
{
    tpoint t;
    uint32_t f = irand(mi->nf);
    const uint32_t *c = mi->tri + 3 * (size_t)f;
    double b[3], r1 = urand(), r2 = urand(), kind = urand();
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    b[0] = 1 - r1 - r2, b[1] = r1, b[2] = r2;
    t.vertex = GS_NONE;
    if (kind < 0.4) { /* inside the face: the corners in another order */
        t.p = on_face(mi, f, 0, b);
        t.alt = on_face(mi, f, 1 + (int)irand(2), b);
    } else if (kind < 0.75) { /* on an edge (i, j): named by the face across it if there is one */
        int i = (int)irand(3), j = (i + 1) % 3, k = (i + 2) % 3;
        double u = urand();
        b[i] = u, b[j] = 1 - u, b[k] = zero();
        t.p = on_face(mi, f, 0, b);
        uint32_t g = f;
        for (uint32_t s = mi->vstart[c[i]]; s < mi->vstart[c[i] + 1]; ++s) {
            const uint32_t *h = mi->tri + 3 * (size_t)mi->vface[s];
            int has_j = h[0] == c[j] || h[1] == c[j] || h[2] == c[j];
            if (mi->vface[s] != f && has_j) g = mi->vface[s];
        }
        const uint32_t *h = mi->tri + 3 * (size_t)g;
        double w[3];
        for (int q = 0; q < 3; ++q) w[q] = h[q] == c[i] ? u : h[q] == c[j] ? 1 - u : zero();
        t.alt = on_face(mi, g, (int)irand(3), w);
    } else { /* at a vertex: weight 1 in this face, and in another face of it (or {v, v, v}) */
        int i = (int)irand(3);
        uint32_t v = c[i], deg = mi->vstart[v + 1] - mi->vstart[v];
        b[i] = 1, b[(i + 1) % 3] = zero(), b[(i + 2) % 3] = zero();
        t.p = on_face(mi, f, 0, b);
        uint32_t g = mi->vface[mi->vstart[v] + irand(deg)];
        const uint32_t *h = mi->tri + 3 * (size_t)g;
        double w[3];
        for (int q = 0; q < 3; ++q) w[q] = h[q] == v ? 1.0 : zero();
        t.alt = urand() < 0.2 ? gs_surface_point_make(v, v, v, 0.25, 0.5, 0.25) : on_face(mi, g, (int)irand(3), w);
        t.vertex = v;
    }
    position(mi, &t.p, t.x);
    t.anyc = t.p.corner[0];
    for (int q = 0; q < 3; ++q)
        if (t.p.weight[q] > 0) t.anyc = t.p.corner[q];
    return t;
}

typedef struct tally {
    uint32_t asym, alt, vert, self, below, neg, comp, batch, field;
    double worst_below; /* largest (|p - q| - d) / |p - q| seen */
} tally;

static void check_pair(const meshinfo *mi, const gs_db *db, const tpoint *a, const tpoint *b, tally *t)
{
    double d = gs_db_point_distance(db, &a->p, &b->p);
    t->asym += !same_bits(d, gs_db_point_distance(db, &b->p, &a->p));
    t->alt += !same_bits(d, gs_db_point_distance(db, &a->alt, &b->alt)) ||
              !same_bits(d, gs_db_point_distance(db, &b->alt, &a->p));
    if (a->vertex != GS_NONE && b->vertex != GS_NONE)
        t->vert += !same_bits(d, gs_db_distance(db, a->vertex, b->vertex)) ||
                   !same_bits(d, gs_db_distance(db, b->vertex, a->vertex));
    t->self += gs_db_point_distance(db, &a->p, &a->alt) != 0.0 || !same_bits(gs_db_point_distance(db, &a->p, &a->p), 0.0);
    int apart = mi->comp[a->anyc] != mi->comp[b->anyc];
    t->comp += apart ? d != INFINITY : !isfinite(d);
    t->neg += !(d >= 0);
    double e = sqrt((a->x[0] - b->x[0]) * (a->x[0] - b->x[0]) + (a->x[1] - b->x[1]) * (a->x[1] - b->x[1]) +
                    (a->x[2] - b->x[2]) * (a->x[2] - b->x[2]));
    if (!apart && d < e) { /* the test's |p - q| rounds differently from the library's: by a few
                              * ulps of the coordinates (close points cancel) */
        double big = 0;
        for (int c = 0; c < 3; ++c) big = fmax(big, fmax(fabs(a->x[c]), fabs(b->x[c])));
        t->worst_below = fmax(t->worst_below, (e - d) / e);
        t->below += e - d > 1e-14 * e + 4e-15 * big;
    }
}

/* Every property on n random point pairs and nfields fields; reopen: the
 * database saved to memory and opened again (with the full check). */
static void run_ex(const char *spec, const gs_build_options *o, const char *what, int n, int nfields, int reopen)
{
    gs_mesh *m = NULL;
    gs_db *db = NULL;
    gs_error e = {0};
    meshinfo mi = {0};
    tpoint *pts = NULL;
    gs_surface_point *pairs = NULL;
    double *out = NULL, *f = NULL, *g = NULL;
    CHECK_MSG(gs_mesh_generate(spec, &m, &e) == GS_OK, "%s: %s", spec, e.message);
    if (!m) goto done;
    CHECK_MSG(gs_db_build(m, o, &db, NULL, &e) == GS_OK, "%s (%s): build: %s", spec, what, e.message);
    if (db && reopen) {
        gs_db *built = db;
        db = NULL;
        char path[] = "/tmp/geosep-props-XXXXXX";
        int fd = mkstemp(path);
        CHECK(fd >= 0);
        if (fd >= 0) close(fd);
        CHECK(gs_db_save(built, path, &e) == GS_OK);
        CHECK_MSG(gs_db_open_ex(path, GS_DB_OPEN_VERIFY, &db, &e) == GS_OK, "%s", e.message);
        remove(path);
        gs_db_free(built);
    }
    if (!db || info_init(&mi, m)) goto done;
    pts = malloc(sizeof *pts * 2 * (size_t)n);
    pairs = malloc(sizeof *pairs * 2 * (size_t)n);
    out = malloc(sizeof *out * (size_t)n);
    f = malloc(sizeof *f * mi.nv), g = malloc(sizeof *g * mi.nv);
    if (!pts || !pairs || !out || !f || !g) goto done;
    tally t = {0};
    for (int k = 0; k < 2 * n; ++k) pts[k] = random_tpoint(&mi);
    for (int k = 0; k < n; ++k) check_pair(&mi, db, &pts[2 * k], &pts[2 * k + 1], &t);
    /* the batch: the single answers bit for bit, with bad points among the pairs */
    for (int k = 0; k < 2 * n; ++k) pairs[k] = pts[k].p;
    int first_bad = n / 3;
    pairs[2 * first_bad + 1].weight[1] = NAN;
    pairs[2 * (n / 2)].corner[2] = mi.nv;
    CHECK(gs_db_point_distances(db, pairs, (size_t)n, out, &e) == GS_EARG);
    char want[64];
    snprintf(want, sizeof want, "pair %d, point 1: weight 1 is nan", first_bad);
    CHECK_MSG(strstr(e.message, want) != NULL, "%s (%s): '%s' does not name '%s'", spec, what, e.message, want);
    for (int k = 0; k < n; ++k) {
        int bad = k == first_bad || k == n / 2;
        t.batch += bad ? !isnan(out[k]) : !same_bits(out[k], gs_db_point_distance(db, &pts[2 * k].p, &pts[2 * k + 1].p));
    }
    /* fields: each value is the single query; the other name gives the same field */
    for (int k = 0; k < nfields; ++k) {
        const tpoint *a = &pts[k];
        CHECK_MSG(gs_db_point_field(db, &a->p, f, &e) == GS_OK, "%s: %s", spec, e.message);
        CHECK_MSG(gs_db_point_field(db, &a->alt, g, &e) == GS_OK, "%s: %s", spec, e.message);
        t.field += memcmp(f, g, sizeof *f * mi.nv) != 0;
        if (a->vertex != GS_NONE) {
            CHECK(gs_db_field(db, a->vertex, g, NULL) == GS_OK);
            t.field += memcmp(f, g, sizeof *f * mi.nv) != 0;
        }
        for (uint32_t y = 0; y < mi.nv; ++y) {
            gs_surface_point q = gs_surface_point_vertex(y);
            t.field += !same_bits(f[y], gs_db_point_distance(db, &a->p, &q));
        }
    }
    printf("  %-22s %-14s %d pairs, %d fields: |p - q| - d at most %.2g relative\n", spec, what, n, nfields,
           t.worst_below);
    CHECK_MSG(t.asym == 0, "%s (%s): %u pairs not symmetric bit for bit", spec, what, t.asym);
    CHECK_MSG(t.alt == 0, "%s (%s): %u pairs change when the points are named another way", spec, what, t.alt);
    CHECK_MSG(t.vert == 0, "%s (%s): %u vertex pairs differ from gs_db_distance", spec, what, t.vert);
    CHECK_MSG(t.self == 0, "%s (%s): %u points not at 0 from themselves", spec, what, t.self);
    CHECK_MSG(t.below == 0, "%s (%s): %u answers below |p - q| (worst by %.3g)", spec, what, t.below, t.worst_below);
    CHECK_MSG(t.neg == 0, "%s (%s): %u answers negative or NaN", spec, what, t.neg);
    CHECK_MSG(t.comp == 0, "%s (%s): %u answers finite across components or not within one", spec, what, t.comp);
    CHECK_MSG(t.batch == 0, "%s (%s): %u batch answers differ from the single queries", spec, what, t.batch);
    CHECK_MSG(t.field == 0, "%s (%s): %u field values differ from the single queries", spec, what, t.field);
done:
    free(pts);
    free(pairs);
    free(out);
    free(f);
    free(g);
    info_free(&mi);
    gs_db_free(db);
    gs_mesh_free(m);
}

static void run(const char *spec, const gs_build_options *o, const char *what, int n, int nfields)
{
    run_ex(spec, o, what, n, nfields, 0);
}

int main(void)
{
    gs_build_options def, small, exact, sampled;
    gs_build_options_default(&def);
    small = def, small.vmax = 6;
    exact = def, exact.leaf_exact = 1;
    sampled = def, sampled.sampled = 1, sampled.vmax = 12;
    const char *q = getenv("GEOSEP_QUICK");
    int n = q && *q && strcmp(q, "0") ? 1500 : 4000;
    run("grid:12,9,1,1", &def, "defaults", n, 8);
    run("grid:12,9,1,1", &exact, "leaf tables", n, 8);
    run("peaks:16", &small, "vmax 6", n, 8);
    run("peaks:16", &sampled, "sampled", n, 8);
    run("cylinder:12,6,1,2", &def, "defaults", n, 8);
    run("torus:14,8", &small, "vmax 6", n, 8);
    run("cone:10,5", &exact, "leaf tables", n, 8);
    run("sphere:2", &def, "defaults", n, 8);
    run("cube:3", &small, "vmax 6", n, 8);
    run("two:5", &def, "two components", n, 8);
    run("two:5", &exact, "two, leaf tables", n, 8);
    run_ex("peaks:16", &small, "reopened", n, 8, 1);
    run_ex("two:8", &small, "two, reopened", n, 8, 1);
    return gs_test_finish("test_points_props");
}
