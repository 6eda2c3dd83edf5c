/* bench/points.c - accuracy of the surface-point queries (gs_db_point_*,
 * src/query/points.c) against exact polyhedral distances:
 *  - point -> vertex: N random points of random faces (uniform in the face)
 *    x every vertex, the database's gs_db_point_field against the exact
 *    solver started at the point (gs_source_point); beside it the same
 *    interpolation fed with exact vertex distances (its own error), the
 *    plain formula without the straight corner pairs, and the vertex
 *    queries' error from each point's first corner (vertex -> vertex);
 *  - point -> point: N points x N other points, the second set inserted as
 *    vertices (their faces split 1-to-3: the same surface) so that the
 *    exact solver started at each first point gives the exact distances.
 * Relative error |d^ - d| / d over pairs with exact d > 0 and finite:
 * mean, 99th and 99.9th percentiles, max. Also the point pairs' query time.
 * Usage: bench_points MESH DB [--points N] [--seed S]   (N 200, S 1)
 * Env: GS_BENCH_WORST=K lists the K worst pairs of each kind;
 * GS_BENCH_CHECK=1 checks the point pairs' reference against the triangle
 * inequality through the second point's corners (its own exact field). */
#include "bench_util.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t rng_state;
static double urand(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static double dist2(const double *a, const double *b)
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

/* relative errors, kept for the percentile */
typedef struct errs {
    double *e;
    size_t n, cap;
} errs;

static void add(errs *s, double got, double want)
{
    if (!(want > 0) || !isfinite(want)) return;
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1 << 16;
        s->e = realloc(s->e, sizeof *s->e * s->cap);
        if (!s->e) {
            fprintf(stderr, "out of memory\n");
            exit(1);
        }
    }
    s->e[s->n++] = fabs(got - want) / want;
}

/* The worst pairs (env GS_BENCH_WORST=K: list the K worst of each kind):
 * the point's face and weights, the target, the exact distance in mean
 * edge lengths, the target's distance in edges from the point's face. */
typedef struct worst {
    double e, got, want;
    uint32_t face, target, hops;
    double b[3];
} worst;
static int n_worst;
static worst *worst_list;
static int n_listed;

static void note(double got, double want, uint32_t face, const double *b, uint32_t target, uint32_t hops)
{
    if (!n_worst || !(want > 0) || !isfinite(want)) return;
    double e = fabs(got - want) / want;
    if (n_listed == n_worst && e <= worst_list[n_worst - 1].e) return;
    int i = n_listed < n_worst ? n_listed++ : n_worst - 1;
    while (i > 0 && worst_list[i - 1].e < e) worst_list[i] = worst_list[i - 1], --i;
    worst_list[i] = (worst){e, got, want, face, target, hops, {b[0], b[1], b[2]}};
}

static void list_worst(const char *what, double edge)
{
    if (!n_worst) return;
    printf("  worst %s:\n", what);
    for (int i = 0; i < n_listed; ++i) {
        const worst *w = &worst_list[i];
        printf("    %6.2f%%  got %.6g exact %.6g (%.2f edges)  face %u (%.3f %.3f %.3f) -> %u, %u edge hops\n",
               100 * w->e, w->got, w->want, w->want / edge, w->face, w->b[0], w->b[1], w->b[2], w->target, w->hops);
    }
    n_listed = 0;
}

/* Edge hops from the face's corners to every vertex (BFS). */
static void hops_from(const gs_mesh *m, const uint32_t *c, uint32_t *h)
{
    uint32_t n = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    const uint32_t *t = gs_mesh_faces(m);
    for (uint32_t v = 0; v < n; ++v) h[v] = UINT32_MAX;
    for (int i = 0; i < 3; ++i) h[c[i]] = 0;
    for (uint32_t r = 0, changed = 1; changed; ++r) {
        changed = 0;
        for (uint32_t f = 0; f < nf; ++f)
            for (int i = 0; i < 3; ++i)
                if (h[t[3 * f + i]] == r)
                    for (int j = 0; j < 3; ++j)
                        if (h[t[3 * f + j]] == UINT32_MAX) h[t[3 * f + j]] = r + 1, changed = 1;
    }
}

static double mean_edge(const gs_mesh *m)
{
    const uint32_t *t = gs_mesh_faces(m);
    const double *x = gs_mesh_positions(m);
    uint32_t nf = gs_mesh_num_faces(m);
    double s = 0;
    for (uint32_t f = 0; f < nf; ++f)
        for (int i = 0; i < 3; ++i) s += sqrt(dist2(x + 3 * (size_t)t[3 * f + i], x + 3 * (size_t)t[3 * f + (i + 1) % 3]));
    return s / (3.0 * nf);
}

static void show(const char *what, errs *s)
{
    double sum = 0;
    if (s->n == 0) { /* a tiny mesh: no pair of this kind (e.g. every point within a face's corners) */
        printf("  %-58s no pairs\n", what);
        free(s->e);
        memset(s, 0, sizeof *s);
        return;
    }
    qsort(s->e, s->n, sizeof *s->e, cmp_double);
    for (size_t i = 0; i < s->n; ++i) sum += s->e[i];
    printf("  %-58s mean %.3f%%  p99 %.3f%%  p99.9 %.3f%%  max %.2f%%  (%zu pairs)\n", what, 100 * sum / s->n,
           100 * s->e[s->n * 99 / 100], 100 * s->e[s->n * 999 / 1000], 100 * s->e[s->n - 1], s->n);
    free(s->e);
    memset(s, 0, sizeof *s);
}

typedef struct pt {
    uint32_t face, c[3];
    double b[3], x[3];
} pt;

static pt random_point(const gs_mesh *m, const char *avoid)
{
    pt p;
    uint32_t nf = gs_mesh_num_faces(m);
    do p.face = (uint32_t)(urand() * nf) % nf;
    while (avoid && avoid[p.face]);
    double r1 = urand(), r2 = urand();
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    p.b[0] = 1 - r1 - r2, p.b[1] = r1, p.b[2] = r2;
    memcpy(p.c, gs_mesh_faces(m) + 3 * (size_t)p.face, sizeof p.c);
    const double *xyz = gs_mesh_positions(m);
    for (int j = 0; j < 3; ++j) p.x[j] = p.b[0] * xyz[3 * p.c[0] + j] + p.b[1] * xyz[3 * p.c[1] + j] + p.b[2] * xyz[3 * p.c[2] + j];
    return p;
}

static gs_surface_point sp(const pt *p)
{
    return gs_surface_point_make(p->c[0], p->c[1], p->c[2], p->b[0], p->b[1], p->b[2]);
}

static void die(const char *what, const gs_error *e)
{
    fprintf(stderr, "%s: %s\n", what, e->message);
    exit(1);
}

/* sum_{i<k} b_i b_k |c_i - c_k|^2 */
static double edge_term(const double *xyz, const pt *p)
{
    double s = 0;
    for (int i = 0; i < 3; ++i)
        for (int k = i + 1; k < 3; ++k) s += p->b[i] * p->b[k] * dist2(xyz + 3 * p->c[i], xyz + 3 * p->c[k]);
    return s;
}

static void point_to_vertex(const gs_mesh *m, const gs_db *db, int np)
{
    uint32_t n = gs_mesh_num_vertices(m);
    const double *xyz = gs_mesh_positions(m);
    gs_error e = {0};
    gs_patch *all = NULL;
    gs_solver *s = NULL;
    if (gs_patch_create(m, NULL, 0, &all, &e) || gs_solver_create(all, GS_METHOD_EXACT, &s, &e)) die("solver", &e);
    double *ex = malloc(sizeof *ex * n), *f = malloc(sizeof *f * n), *ev[3], *dv[3];
    for (int i = 0; i < 3; ++i) ev[i] = malloc(sizeof *ev[i] * n), dv[i] = malloc(sizeof *dv[i] * n);
    errs api = {0}, floor_ = {0}, plain = {0}, vv = {0};
    uint32_t *hop = malloc(sizeof *hop * n);
    for (int k = 0; k < np; ++k) {
        pt p = random_point(m, NULL);
        if (n_worst) hops_from(m, p.c, hop);
        gs_source src = gs_source_point(p.face, p.b[0], p.b[1], p.b[2]);
        gs_surface_point q = sp(&p);
        if (gs_solver_solve(s, &src, 1, 0, ex, &e)) die("solve", &e);
        if (gs_db_point_field(db, &q, f, &e)) die("point field", &e);
        for (int i = 0; i < 3; ++i) {
            gs_source sv = gs_source_vertex(p.c[i]);
            if (gs_solver_solve(s, &sv, 1, 0, ev[i], &e) || gs_db_field(db, p.c[i], dv[i], &e)) die("corner", &e);
        }
        double cross = edge_term(xyz, &p);
        for (uint32_t y = 0; y < n; ++y) {
            double lo = sqrt(dist2(p.x, xyz + 3 * (size_t)y)), se = -cross, sd = -cross;
            for (int i = 0; i < 3; ++i) se += p.b[i] * ev[i][y] * ev[i][y], sd += p.b[i] * dv[i][y] * dv[i][y];
            add(&api, f[y], ex[y]);
            note(f[y], ex[y], p.face, p.b, y, n_worst ? hop[y] : 0);
            add(&floor_, fmax(se > 0 ? sqrt(se) : 0, lo), ex[y]);
            add(&plain, fmax(sd > 0 ? sqrt(sd) : 0, lo), ex[y]);
            add(&vv, dv[0][y], ev[0][y]);
        }
    }
    printf("point -> vertex (%d random points x %u vertices):\n", np, n);
    show("database (gs_db_point_field)", &api);
    show("same formula, every corner pair a vertex query", &plain);
    show("same formula with exact vertex distances (its own error)", &floor_);
    show("vertex -> vertex, database, from each point's first corner", &vv);
    list_worst("point -> vertex", mean_edge(m));
    free(hop);
    free(ex);
    free(f);
    for (int i = 0; i < 3; ++i) free(ev[i]), free(dv[i]);
    gs_solver_free(s);
    gs_patch_free(all);
}

static void point_to_point(const gs_mesh *m, const gs_db *db, int np)
{
    uint32_t n = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    const double *xyz = gs_mesh_positions(m);
    const uint32_t *tri = gs_mesh_faces(m);
    if ((uint32_t)np > nf / 4) np = (int)(nf / 4);
    char *taken = calloc(nf, 1);
    pt *q = malloc(sizeof *q * np);
    for (int k = 0; k < np; ++k) q[k] = random_point(m, taken), taken[q[k].face] = 1;
    /* the mesh with q[k] as vertex n + k: its face split 1-to-3 (face ids of
     * the other faces kept) */
    double *x2 = malloc(sizeof *x2 * 3 * (n + np));
    uint32_t *t2 = malloc(sizeof *t2 * 3 * (nf + 2 * (size_t)np));
    memcpy(x2, xyz, sizeof *x2 * 3 * n);
    memcpy(t2, tri, sizeof *t2 * 3 * nf);
    for (int k = 0; k < np; ++k) {
        uint32_t v = n + k, a = q[k].c[0], b = q[k].c[1], c = q[k].c[2], *t = t2 + 3 * (size_t)q[k].face;
        memcpy(x2 + 3 * (size_t)v, q[k].x, sizeof q[k].x);
        t[0] = a, t[1] = b, t[2] = v;
        t = t2 + 3 * (nf + 2 * (size_t)k);
        t[0] = b, t[1] = c, t[2] = v, t[3] = c, t[4] = a, t[5] = v;
    }
    gs_error e = {0};
    gs_mesh *m2 = NULL;
    gs_patch *all = NULL;
    gs_solver *s = NULL;
    if (gs_mesh_create(x2, n + np, t2, nf + 2 * np, &m2, &e) || gs_patch_create(m2, NULL, 0, &all, &e) ||
        gs_solver_create(all, GS_METHOD_EXACT, &s, &e))
        die("split mesh", &e);
    double *ex = malloc(sizeof *ex * (n + np)), *ec = malloc(sizeof *ec * (n + np)), tq = 0;
    errs api = {0}, vv = {0};
    uint32_t *hop = malloc(sizeof *hop * n);
    int check = getenv("GS_BENCH_CHECK") != NULL;
    for (int k = 0; k < np; ++k) {
        pt p = random_point(m, taken); /* not a split face: same face id in m2 */
        if (n_worst) hops_from(m, p.c, hop);
        gs_source src = gs_source_point(p.face, p.b[0], p.b[1], p.b[2]), sv = gs_source_vertex(p.c[0]);
        if (gs_solver_solve(s, &src, 1, 0, ex, &e) || gs_solver_solve(s, &sv, 1, 0, ec, &e)) die("solve", &e);
        gs_surface_point a = sp(&p);
        for (int j = 0; j < np; ++j) {
            gs_surface_point b = sp(&q[j]);
            double t = now(), d = gs_db_point_distance(db, &a, &b);
            tq += now() - t;
            add(&api, d, ex[n + j]);
            if (check) { /* the reference against the triangle inequality through q's corners */
                double hi = INFINITY, lo = 0;
                for (int i = 0; i < 3; ++i) {
                    double g = sqrt(dist2(q[j].x, xyz + 3 * (size_t)q[j].c[i]));
                    hi = fmin(hi, ex[q[j].c[i]] + g), lo = fmax(lo, ex[q[j].c[i]] - g);
                }
                if (ex[n + j] > hi * (1 + 1e-9) || ex[n + j] < lo * (1 - 1e-9))
                    printf("    reference %g outside [%g, %g]: face %u -> face %u\n", ex[n + j], lo, hi, p.face,
                           q[j].face);
            }
            if (n_worst) {
                uint32_t h = UINT32_MAX;
                for (int i = 0; i < 3; ++i) h = hop[q[j].c[i]] < h ? hop[q[j].c[i]] : h;
                note(d, ex[n + j], p.face, p.b, q[j].face, h);
            }
            add(&vv, gs_db_distance(db, p.c[0], q[j].c[0]), ec[q[j].c[0]]);
        }
    }
    printf("point -> point (%d x %d random points, exact distances on the mesh with the second set inserted):\n", np, np);
    show("database (gs_db_point_distance)", &api);
    show("vertex -> vertex, database, first corner to first corner", &vv);
    list_worst("point -> point (target: the second point's face; hops: to its nearest corner)", mean_edge(m));
    free(hop);
    printf("  (%.0f ns per point pair, timed with the exact pairs in between: see bench_query)\n",
           1e9 * tq / ((double)np * np));
    free(ex);
    free(ec);
    free(x2);
    free(t2);
    free(q);
    free(taken);
    gs_solver_free(s);
    gs_patch_free(all);
    gs_mesh_free(m2);
}

int main(int argc, char **argv)
{
    const char *mp = NULL, *dp = NULL;
    int np = 200;
    uint64_t seed = 1;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--points") && i + 1 < argc) np = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc) seed = strtoull(argv[++i], NULL, 10);
        else if (!mp) mp = argv[i];
        else if (!dp) dp = argv[i];
    }
    if (!mp || !dp || np < 1) {
        printf("usage: %s MESH DB [--points N] [--seed S]\n"
               "  DB built from MESH, e.g. geosep build ../shared/meshes/bunny-5k.obj -o bunny-5k.gsdb\n",
               argv[0]);
        return 2;
    }
    const char *w = getenv("GS_BENCH_WORST");
    n_worst = w ? atoi(w) : 0;
    if (n_worst > 0) worst_list = malloc(sizeof *worst_list * n_worst);
    else n_worst = 0;
    rng_state = 0x9E3779B97F4A7C15ull ^ (seed * 0xD1B54A32D192ED03ull);
    gs_error e = {0};
    gs_mesh *m = NULL;
    gs_db *db = NULL;
    if (gs_mesh_load(mp, GS_FORMAT_AUTO, &m, &e)) die(mp, &e);
    if (gs_db_open(dp, &db, &e)) die(dp, &e);
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    if (info.n_vertices != gs_mesh_num_vertices(m) ||
        memcmp(gs_db_positions(db), gs_mesh_positions(m), sizeof(double) * 3 * info.n_vertices)) {
        fprintf(stderr, "%s is not the mesh of %s\n", mp, dp);
        return 1;
    }
    printf("%s (%u vertices), %s, seed %llu\n", mp, gs_mesh_num_vertices(m), dp, (unsigned long long)seed);
    point_to_vertex(m, db, np);
    point_to_point(m, db, np);
    gs_db_free(db);
    gs_mesh_free(m);
    return 0;
}
