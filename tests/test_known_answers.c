/* test_known_answers.c - GS_METHOD_EXACT against distances known in closed
 * form on generated meshes: flat grids (Euclidean), a plate with polygonal
 * holes and a notched patch (taut strings, by brute-force visibility graphs),
 * the unrolled prism and truncated pyramid, cube unfoldings, two components,
 * plus invariants (symmetry, triangle inequality, bounds) on curved meshes.
 * Every check prints what it compared. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- helpers ------------------------------------------------------------ */

static gs_mesh *generate(const char *spec)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    int rc = gs_mesh_generate(spec, &m, &err);
    CHECK_MSG(rc == GS_OK, "gs_mesh_generate(\"%s\"): %s", spec, err.message);
    return m;
}

static gs_patch *whole(const gs_mesh *m)
{
    gs_patch *p = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK, "patch: %s", err.message);
    return p;
}

/* Solve; on failure report it as a failed check and return nonzero. */
static int solve(const gs_patch *p, gs_method method, const gs_source *src, uint32_t n,
                 double max_d, double *dist, const char *what)
{
    gs_error err = {0};
    int rc = gs_distance_field(p, method, src, n, max_d, dist, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s solve failed (%d): %s", what, gs_method_name(method), rc,
              err.message);
    if (rc) printf("%-46s SOLVE FAILED: %s\n", what, err.message);
    return rc;
}

/* Compare got[] with want[] where want is not NaN; tolerance abs + rel*|want|.
 * want = +inf requires got = +inf. Prints one line; one CHECK per call. */
static void compare(const char *what, const double *got, const double *want, uint32_t n,
                    double abs_tol, double rel_tol)
{
    uint32_t compared = 0, bad = 0, first = GS_NONE;
    double worst = 0;
    for (uint32_t i = 0; i < n; ++i) {
        if (isnan(want[i])) continue;
        compared++;
        double e = isinf(want[i]) ? (got[i] == want[i] ? 0 : INFINITY) : fabs(got[i] - want[i]);
        if (isnan(e)) e = INFINITY;
        if (e > worst) worst = e;
        if (e > abs_tol + rel_tol * fabs(want[i]) || (isinf(want[i]) && e != 0)) {
            if (!bad) first = i;
            bad++;
        }
    }
    printf("%-46s %5u values, max err %.2e (tol %.0e + %.0e rel): %s\n", what, compared, worst,
           abs_tol, rel_tol, bad ? "FAIL" : "ok");
    CHECK_MSG(bad == 0 && compared > 0, "%s: %u of %u differ; first vertex %u: got %.17g, want %.17g",
              what, bad, compared, first, first == GS_NONE ? 0 : got[first],
              first == GS_NONE ? 0 : want[first]);
}

/* The reference values are checked first against the edge-graph distances
 * (an upper bound of the exact ones, so want <= graph), which validates this
 * test's own geometry independently of the exact solver; then the exact
 * solver must reproduce them. */
static void known(const gs_patch *p, const gs_source *src, uint32_t n_src, const double *want,
                  uint32_t n, double abs_tol, double rel_tol, const char *what)
{
    double *got = malloc(n * sizeof *got);
    char line[160];
    if (!solve(p, GS_METHOD_GRAPH, src, n_src, 0, got, what)) {
        uint32_t bad = 0, compared = 0;
        for (uint32_t i = 0; i < n; ++i) {
            if (isnan(want[i])) continue;
            compared++;
            bad += !(want[i] <= got[i] + abs_tol + rel_tol * fabs(got[i])) && !(isinf(want[i]) && isinf(got[i]));
        }
        snprintf(line, sizeof line, "%s [reference <= graph]", what);
        printf("%-46s %5u values, %u above the graph distance: %s\n", line, compared, bad,
               bad ? "FAIL" : "ok");
        CHECK_MSG(bad == 0, "%s: %u reference values exceed the graph distance", what, bad);
    }
    snprintf(line, sizeof line, "%s [exact]", what);
    if (!solve(p, GS_METHOD_EXACT, src, n_src, 0, got, line)) compare(line, got, want, n, abs_tol, rel_tol);
    free(got);
}

static const double *pos(const gs_mesh *m, uint32_t v) { return gs_mesh_positions(m) + 3 * (size_t)v; }

/* Mesh vertex closest to (x, y, z). */
static uint32_t nearest(const gs_mesh *m, double x, double y, double z)
{
    double q[3] = {x, y, z}, best = INFINITY;
    uint32_t arg = 0;
    for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v)
        if (gs__test_dist3(pos(m, v), q) < best) {
            best = gs__test_dist3(pos(m, v), q);
            arg = v;
        }
    return arg;
}

static void point_of(const gs_mesh *m, const gs_source *s, double p[3])
{
    if (s->face == GS_NONE) {
        memcpy(p, pos(m, s->vertex), sizeof(double) * 3);
        return;
    }
    const uint32_t *t = gs_mesh_faces(m) + 3 * (size_t)s->face;
    for (int k = 0; k < 3; ++k)
        p[k] = s->bary[0] * pos(m, t[0])[k] + s->bary[1] * pos(m, t[1])[k] + s->bary[2] * pos(m, t[2])[k];
}

/* ---- flat grids: Euclidean ---------------------------------------------- */

static void test_grid(void)
{
    gs_mesh *m = generate("grid:21,17,2,1.5");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m);
    double size = 2.5, *got = malloc(n * sizeof *got), *want = malloc(n * sizeof *want);
    gs_source src[3] = {gs_source_vertex(0), gs_source_vertex(8 * 21 + 13),
                        gs_source_point(101, 0.2, 0.3, 0.5)};
    const char *names[3] = {"grid: from corner vertex 0", "grid: from interior vertex",
                            "grid: from point in face 101"};
    for (int s = 0; s < 3; ++s) {
        double q[3];
        point_of(m, &src[s], q);
        for (uint32_t v = 0; v < n; ++v) want[v] = gs__test_dist3(pos(m, v), q);
        known(p, &src[s], 1, want, n, 1e-12 * size, 0, names[s]);
    }
    /* several sources: the pointwise minimum */
    for (uint32_t v = 0; v < n; ++v) {
        double q[3], d = INFINITY;
        for (int s = 0; s < 3; ++s) {
            point_of(m, &src[s], q);
            d = fmin(d, gs__test_dist3(pos(m, v), q));
        }
        want[v] = d;
    }
    known(p, src, 3, want, n, 1e-12 * size, 0, "grid: three sources (pointwise min)");
    /* max_distance: exact up to the bound, beyond it inf or > bound */
    double q[3], bound = 0.7;
    point_of(m, &src[1], q);
    if (!solve(p, GS_METHOD_EXACT, &src[1], 1, bound, got, "grid: max_distance 0.7")) {
        uint32_t beyond_bad = 0;
        for (uint32_t v = 0; v < n; ++v) {
            want[v] = gs__test_dist3(pos(m, v), q);
            if (want[v] > bound) {
                if (!(got[v] > bound) && want[v] > bound + 1e-12 * size) {
                    printf("  vertex %u: distance %.17g beyond the bound, got %.17g\n", v, want[v], got[v]);
                    beyond_bad++;
                }
                want[v] = NAN;
            }
        }
        compare("grid: max_distance 0.7, vertices within", got, want, n, 1e-12 * size, 0);
        printf("%-46s %u vertices beyond the bound not > bound\n", "grid: max_distance 0.7, beyond",
               beyond_bad);
        CHECK(beyond_bad == 0);
    }
    free(got);
    free(want);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- planar polygonal domains: taut strings ----------------------------
 * A domain is the plane minus convex obstacles, each given as directed edges
 * with the obstacle's interior on their right (the way a mesh's boundary
 * edges run around a hole). Shortest paths bend only at obstacle vertices, so
 * Dijkstra over the visibility graph of source, targets and those vertices
 * is exact. Segments that only graze an obstacle are visible. */

typedef struct obstacle {
    uint32_t n;
    double (*a)[2], (*b)[2]; /* edge k runs from a[k] to b[k] */
} obstacle;

typedef struct domain {
    uint32_t n_obs;
    obstacle *obs;
} domain;

/* Does the segment pq pass through the open interior of the convex o? */
static int blocks(const obstacle *o, const double *p, const double *q)
{
    const double eps = 1e-10;
    double t0 = 0, t1 = 1;
    for (uint32_t k = 0; k < o->n; ++k) {
        double ex = o->b[k][0] - o->a[k][0], ey = o->b[k][1] - o->a[k][1], l = hypot(ex, ey);
        /* signed distance to the edge's line, negative on the inside */
        double g0 = (ex * (p[1] - o->a[k][1]) - ey * (p[0] - o->a[k][0])) / l;
        double g1 = (ex * (q[1] - o->a[k][1]) - ey * (q[0] - o->a[k][0])) / l;
        if (g0 >= -eps && g1 >= -eps) return 0;
        if (g0 < -eps && g1 < -eps) continue;
        double t = (-eps - g0) / (g1 - g0);
        if (g0 >= -eps)
            t0 = fmax(t0, t);
        else
            t1 = fmin(t1, t);
        if (t1 - t0 <= 1e-12) return 0;
    }
    return t1 - t0 > 1e-12;
}

static int visible(const domain *d, const double *p, const double *q)
{
    for (uint32_t i = 0; i < d->n_obs; ++i)
        if (blocks(&d->obs[i], p, q)) return 0;
    return 1;
}

/* Shortest path lengths in the domain from src to each of n targets. */
static void taut_distances(const domain *d, const double *src, const double (*tgt)[2],
                           uint32_t n, double *out)
{
    uint32_t nn = 1;
    for (uint32_t i = 0; i < d->n_obs; ++i) nn += d->obs[i].n;
    double (*node)[2] = malloc(nn * sizeof *node), *dn = malloc(nn * sizeof *dn);
    char *done = calloc(nn, 1);
    node[0][0] = src[0];
    node[0][1] = src[1];
    for (uint32_t i = 0, k = 1; i < d->n_obs; ++i)
        for (uint32_t j = 0; j < d->obs[i].n; ++j, ++k) memcpy(node[k], d->obs[i].a[j], sizeof node[k]);
    for (uint32_t k = 0; k < nn; ++k) dn[k] = k ? INFINITY : 0;
    for (;;) { /* dense Dijkstra: few hundred nodes */
        uint32_t u = GS_NONE;
        for (uint32_t k = 0; k < nn; ++k)
            if (!done[k] && isfinite(dn[k]) && (u == GS_NONE || dn[k] < dn[u])) u = k;
        if (u == GS_NONE) break;
        done[u] = 1;
        for (uint32_t k = 0; k < nn; ++k) {
            double w = dn[u] + hypot(node[k][0] - node[u][0], node[k][1] - node[u][1]);
            if (!done[k] && w < dn[k] && visible(d, node[u], node[k])) dn[k] = w;
        }
    }
    for (uint32_t t = 0; t < n; ++t) {
        double best = INFINITY;
        for (uint32_t k = 0; k < nn; ++k) {
            double w = dn[k] + hypot(tgt[t][0] - node[k][0], tgt[t][1] - node[k][1]);
            if (w < best && visible(d, node[k], tgt[t])) best = w;
        }
        out[t] = best;
    }
    free(node);
    free(dn);
    free(done);
}

static void domain_free(domain *d)
{
    for (uint32_t i = 0; i < d->n_obs; ++i) {
        free(d->obs[i].a);
        free(d->obs[i].b);
    }
    free(d->obs);
}

static uint32_t uf_find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) x = p[x] = p[p[x]];
    return x;
}

/* The holes of a flat mesh inside [0,1]^2: its boundary edges not on the
 * square's sides, grouped into loops by shared vertices. */
static void holes_of(const gs_mesh *m, domain *d)
{
    uint32_t nf = gs_mesh_num_faces(m), nv = gs_mesh_num_vertices(m);
    const uint32_t *t = gs_mesh_faces(m);
    /* boundary half-edges: those whose reverse does not occur (brute force) */
    uint32_t *parent = malloc(nv * sizeof *parent), *eh = malloc(3 * (size_t)nf * sizeof *eh), ne = 0;
    for (uint32_t v = 0; v < nv; ++v) parent[v] = v;
    for (uint32_t h = 0; h < 3 * nf; ++h) {
        uint32_t a = t[h], b = t[h % 3 == 2 ? h - 2 : h + 1], twin = 0;
        for (uint32_t g = 0; g < 3 * nf && !twin; ++g)
            twin = t[g] == b && t[g % 3 == 2 ? g - 2 : g + 1] == a;
        const double *pa = pos(m, a), *pb = pos(m, b);
        int on_square = (pa[0] == pb[0] && (pa[0] == 0 || pa[0] == 1)) ||
                        (pa[1] == pb[1] && (pa[1] == 0 || pa[1] == 1));
        if (twin || on_square) continue;
        eh[ne++] = h;
        parent[uf_find(parent, a)] = uf_find(parent, b);
    }
    d->n_obs = 0;
    d->obs = calloc(ne, sizeof *d->obs);
    uint32_t *slot = malloc(nv * sizeof *slot);
    for (uint32_t v = 0; v < nv; ++v) slot[v] = GS_NONE;
    for (uint32_t i = 0; i < ne; ++i) {
        uint32_t h = eh[i], r = uf_find(parent, t[h]);
        if (slot[r] == GS_NONE) {
            slot[r] = d->n_obs++;
            d->obs[slot[r]].a = malloc(ne * sizeof *d->obs[0].a);
            d->obs[slot[r]].b = malloc(ne * sizeof *d->obs[0].b);
        }
        obstacle *o = &d->obs[slot[r]];
        memcpy(o->a[o->n], pos(m, t[h]), 2 * sizeof(double));
        memcpy(o->b[o->n++], pos(m, t[h % 3 == 2 ? h - 2 : h + 1]), 2 * sizeof(double));
    }
    free(slot);
    free(parent);
    free(eh);
}

static void test_plate(void)
{
    gs_mesh *m = generate("plate:1200");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    domain d;
    holes_of(m, &d);
    printf("plate: %u vertices, %u holes with %u, %u, %u edges\n", gs_mesh_num_vertices(m),
           d.n_obs, d.n_obs > 0 ? d.obs[0].n : 0, d.n_obs > 1 ? d.obs[1].n : 0,
           d.n_obs > 2 ? d.obs[2].n : 0);
    CHECK(d.n_obs == 3);
    uint32_t n = gs_mesh_num_vertices(m);
    double (*xy)[2] = malloc(n * sizeof *xy), *got = malloc(n * sizeof *got);
    double *want = malloc(n * sizeof *want);
    for (uint32_t v = 0; v < n; ++v) memcpy(xy[v], pos(m, v), sizeof xy[v]);
    static const double at[4][2] = {{0.5, 0.5}, {0.02, 0.02}, {0.98, 0.3}, {0.25, 0.45}};
    for (int s = 0; s < 4; ++s) {
        uint32_t v0 = nearest(m, at[s][0], at[s][1], 0);
        gs_source src = gs_source_vertex(v0);
        taut_distances(&d, xy[v0], (const double (*)[2])xy, n, want);
        uint32_t around = 0;
        for (uint32_t v = 0; v < n; ++v) around += want[v] > hypot(xy[v][0] - xy[v0][0], xy[v][1] - xy[v0][1]) + 1e-9;
        char what[96];
        snprintf(what, sizeof what, "plate: taut strings from vertex %u (%u bent)", v0, around);
        known(p, &src, 1, want, n, 0, 1e-9, what);
    }
    free(xy);
    free(got);
    free(want);
    domain_free(&d);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- cylinder: the prism unrolled --------------------------------------- */

static void test_cylinder(void)
{
    const uint32_t NU = 24;
    const double R = 1, H = 2;
    gs_mesh *m = generate("cylinder:24,9,1,2");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m);
    double chord = 2 * R * sin(M_PI / NU), perim = NU * chord;
    double *got = malloc(n * sizeof *got), *want = malloc(n * sizeof *want);
    /* vertex j*NU+i unrolls to (i*chord, z) */
    gs_source src[3] = {gs_source_vertex(0), gs_source_vertex(4 * NU + 7), gs_source_point(2 * 31 + 1, 0.1, 0.6, 0.3)};
    for (int s = 0; s < 3; ++s) {
        double su = 0, sz = 0;
        if (src[s].face == GS_NONE) {
            su = (src[s].vertex % NU) * chord;
            sz = pos(m, src[s].vertex)[2];
        } else { /* unroll the corners next to the first one */
            const uint32_t *t = gs_mesh_faces(m) + 3 * (size_t)src[s].face;
            double u0 = (t[0] % NU) * chord;
            for (int k = 0; k < 3; ++k) {
                double u = (t[k] % NU) * chord;
                if (u - u0 > perim / 2) u -= perim;
                if (u0 - u > perim / 2) u += perim;
                su += src[s].bary[k] * u;
                sz += src[s].bary[k] * pos(m, t[k])[2];
            }
        }
        for (uint32_t v = 0; v < n; ++v) {
            double du = (v % NU) * chord - su, dz = pos(m, v)[2] - sz, best = INFINITY;
            for (int k = -1; k <= 1; ++k) best = fmin(best, hypot(du + k * perim, dz));
            want[v] = best;
        }
        char what[64];
        snprintf(what, sizeof what, "cylinder: unrolled, source %d", s);
        known(p, &src[s], 1, want, n, 1e-11 * H, 0, what);
    }
    free(got);
    free(want);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- cone: the truncated pyramid unrolled into a sector -----------------
 * Apex at height 4H/3 (the frustum stops at H where the radius is R/4).
 * Vertex i of a ring unrolls to polar (rho, i*alpha). A homotopy class k of
 * paths spans the angle dphi + k*NU*alpha: if below pi and its straight
 * segment stays outside the top ring's circle, that segment is on the surface
 * and is the class's shortest path; otherwise the class is no shorter than
 * the straight length (below pi) or rho_s + rho_t (pi or more). A pair is
 * checked only when a valid class beats every other class's lower bound. */

static void test_cone(void)
{
    const uint32_t NU = 32;
    const double R = 1, H = 1, apex[3] = {0, 0, 4 * H / 3};
    gs_mesh *m = generate("cone:32,8,1,1");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m);
    double L = gs__test_dist3(pos(m, 0), apex), alpha = 2 * asin(R * sin(M_PI / NU) / L);
    double rho_top = L / 4, total = NU * alpha;
    double *got = malloc(n * sizeof *got), *want = malloc(n * sizeof *want);
    const uint32_t sources[3] = {0, 3 * NU + 5, 6 * NU + 20};
    for (int s = 0; s < 3; ++s) {
        uint32_t sv = sources[s], skipped = 0;
        double rs = gs__test_dist3(pos(m, sv), apex);
        for (uint32_t v = 0; v < n; ++v) {
            double rt = gs__test_dist3(pos(m, v), apex), dphi = ((double)(v % NU) - (double)(sv % NU)) * alpha;
            double valid = INFINITY, lower = INFINITY;
            for (int k = -3; k <= 3; ++k) {
                double a = fabs(dphi + k * total);
                if (a >= M_PI) {
                    lower = fmin(lower, rs + rt);
                    continue;
                }
                double ax = rs, ay = 0, bx = rt * cos(a), by = rt * sin(a);
                double len = hypot(bx - ax, by - ay);
                double tt = len > 0 ? -(ax * (bx - ax) + ay * (by - ay)) / (len * len) : 0;
                tt = fmin(1, fmax(0, tt));
                double closest = hypot(ax + tt * (bx - ax), ay + tt * (by - ay));
                if (closest >= rho_top * (1 - 1e-12))
                    valid = fmin(valid, len);
                else
                    lower = fmin(lower, len);
            }
            want[v] = valid <= lower ? valid : NAN;
            skipped += isnan(want[v]);
        }
        char what[80];
        snprintf(what, sizeof what, "cone: unrolled from vertex %u (%u skipped)", sv, skipped);
        known(p, &(gs_source){sv, GS_NONE, {0, 0, 0}}, 1, want, n, 1e-11 * L, 0, what);
    }
    free(got);
    free(want);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- cube: unfolding onto adjacent faces --------------------------------
 * From the centre c of face (axis a, side s), a point q on an adjacent face
 * (axis b, side t) unfolds across their common edge into the plane of the
 * first face: q' = q with q'_a = s and q'_b = t +- |q_a - s|. That rectangle
 * is convex, so the segment is on the surface. From a face centre it is the
 * shortest: with c = (S/2, S/2) on the top and q = (x, 0, z) on the front,
 * direct is |(x - S/2, 3S/2 - z)|, via the left face |(x + S/2, 3S/2 - z)|,
 * via the right face |(3S/2 - x, 3S/2 - z)|, both >= direct for x in [0,S];
 * routes over more faces are longer still. */

static int face_of(const double *q, double S, int axis_skip, int *axis, int *side_hi)
{
    for (int k = 0; k < 3; ++k) {
        if (k == axis_skip) continue;
        if (q[k] == 0 || q[k] == S) {
            *axis = k;
            *side_hi = q[k] == S;
            return 1;
        }
    }
    return 0;
}

static void test_cube(void)
{
    const double S = 1.5;
    gs_mesh *m = generate("cube:6,1.5");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m);
    double *got = malloc(n * sizeof *got), *want = malloc(n * sizeof *want);
    for (int face = 0; face < 6; ++face) {
        int a = face / 2, hi = face % 2;
        double c[3] = {S / 2, S / 2, S / 2};
        c[a] = hi ? S : 0;
        uint32_t cv = nearest(m, c[0], c[1], c[2]);
        uint32_t same = 0, adjacent = 0;
        for (uint32_t v = 0; v < n; ++v) {
            const double *q = pos(m, v);
            int b, thi;
            want[v] = NAN;
            if (q[a] == c[a]) { /* same face */
                want[v] = gs__test_dist3(q, c);
                same++;
            } else if (face_of(q, S, a, &b, &thi)) {
                double u[3] = {q[0], q[1], q[2]}, t = thi ? S : 0, off = fabs(q[a] - c[a]);
                u[a] = c[a];
                u[b] = thi ? t + off : t - off;
                want[v] = gs__test_dist3(u, c);
                adjacent++;
            }
        }
        char what[96];
        snprintf(what, sizeof what, "cube: face %d centre %u, %u same + %u adjacent", face, cv, same,
                 adjacent);
        known(p, &(gs_source){cv, GS_NONE, {0, 0, 0}}, 1, want, n, 1e-11 * S, 0, what);
    }
    free(got);
    free(want);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- two components ----------------------------------------------------- */

static void test_two(void)
{
    gs_mesh *m = generate("two:9");
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m);
    double *got = malloc(n * sizeof *got), *want = malloc(n * sizeof *want);
    for (int comp = 0; comp < 2; ++comp) {
        uint32_t sv = comp * 81 + 40; /* the centre of grid comp */
        for (uint32_t v = 0; v < n; ++v)
            want[v] = (v / 81 == (uint32_t)comp) ? gs__test_dist3(pos(m, v), pos(m, sv)) : INFINITY;
        char what[64];
        snprintf(what, sizeof what, "two: from vertex %u (other component inf)", sv);
        known(p, &(gs_source){sv, GS_NONE, {0, 0, 0}}, 1, want, n, 1e-12, 0, what);
    }
    free(got);
    free(want);
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* ---- patches of a grid: a notch to go around, a band that disconnects ---- */

/* Faces of grid:31,31 whose centroid is not inside [x0,x1] x [0,y1]. */
static uint32_t keep_faces(const gs_mesh *m, double x0, double x1, double y1, uint32_t *faces)
{
    uint32_t k = 0;
    for (uint32_t f = 0; f < gs_mesh_num_faces(m); ++f) {
        const uint32_t *t = gs_mesh_faces(m) + 3 * (size_t)f;
        double cx = (pos(m, t[0])[0] + pos(m, t[1])[0] + pos(m, t[2])[0]) / 3;
        double cy = (pos(m, t[0])[1] + pos(m, t[1])[1] + pos(m, t[2])[1]) / 3;
        if (!(cx > x0 && cx < x1 && cy < y1)) faces[k++] = f;
    }
    return k;
}

static void check_patch_ids(const gs_patch *p, const gs_mesh *m, double x0, double x1, double y1)
{
    uint32_t bad = 0, nl = gs_patch_num_vertices(p), prev = 0;
    for (uint32_t l = 0; l < nl; ++l) {
        uint32_t v = gs_patch_vertex_to_mesh(p, l);
        if (v >= gs_mesh_num_vertices(m) || gs_patch_vertex_from_mesh(p, v) != l || (l && v <= prev)) bad++;
        prev = v;
    }
    uint32_t removed = 0;
    for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v) {
        const double *q = pos(m, v);
        int inside = q[0] > x0 + 1e-9 && q[0] < x1 - 1e-9 && q[1] < y1 - 1e-9;
        uint32_t l = gs_patch_vertex_from_mesh(p, v);
        if (inside != (l == GS_NONE)) bad++;
        removed += l == GS_NONE;
    }
    printf("%-46s %u local vertices, %u mesh vertices not in it, %u id errors\n",
           "patch: vertex id maps", nl, removed, bad);
    CHECK(bad == 0);
    CHECK(gs_patch_vertex_to_mesh(p, nl) == GS_NONE);
}

static void test_patch(void)
{
    const double x0 = 0.4, x1 = 0.6, y1 = 0.7; /* grid lines of the 30 x 30 grid */
    gs_mesh *m = generate("grid:31,31");
    if (!m) return;
    uint32_t *faces = malloc(gs_mesh_num_faces(m) * sizeof *faces);
    uint32_t nf = keep_faces(m, x0, x1, y1, faces);
    gs_patch *p = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_patch_create(m, faces, nf, &p, &err) == GS_OK, "%s", err.message);
    if (p) {
        check_patch_ids(p, m, x0, x1, y1);
        /* the notch as an obstacle: clockwise, interior on the right */
        double A[4][2] = {{x0, -10}, {x0, y1}, {x1, y1}, {x1, -10}}, B[4][2]; /* far below */
        for (int k = 0; k < 4; ++k) memcpy(B[k], A[(k + 1) % 4], sizeof B[k]);
        obstacle o = {4, A, B};
        domain d = {1, &o};
        uint32_t nl = gs_patch_num_vertices(p);
        double (*xy)[2] = calloc(nl ? nl : 1, sizeof *xy), *got = malloc(nl * sizeof *got);
        double *want = malloc(nl * sizeof *want);
        for (uint32_t l = 0; l < nl; ++l) memcpy(xy[l], pos(m, gs_patch_vertex_to_mesh(p, l)), sizeof xy[l]);
        uint32_t lv = gs_patch_vertex_from_mesh(p, 6 * 31 + 6); /* (0.2, 0.2) */
        taut_distances(&d, xy[lv], (const double (*)[2])xy, nl, want);
        double detour = 0;
        for (uint32_t l = 0; l < nl; ++l) detour = fmax(detour, want[l] - hypot(xy[l][0] - xy[lv][0], xy[l][1] - xy[lv][1]));
        printf("patch: largest detour around the notch %.3f\n", detour);
        CHECK(detour > 0.5);
        known(p, &(gs_source){lv, GS_NONE, {0, 0, 0}}, 1, want, nl, 0, 1e-9,
              "patch: notch, taut strings from (0.2,0.2)");
        /* a surface point in local face 0 */
        gs_source sp = gs_source_point(0, 0.25, 0.25, 0.5);
        const uint32_t *t = gs_mesh_faces(m) + 3 * (size_t)gs_patch_face_to_mesh(p, 0);
        double q[2] = {0, 0};
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 2; ++c) q[c] += sp.bary[k] * pos(m, t[k])[c];
        taut_distances(&d, q, (const double (*)[2])xy, nl, want);
        known(p, &sp, 1, want, nl, 0, 1e-9, "patch: notch, taut strings from a point");
        free(xy);
        free(got);
        free(want);
    }
    gs_patch_free(p);
    /* a full-height band: the right part is unreachable */
    nf = keep_faces(m, x0, x1, 2, faces);
    p = NULL;
    CHECK_MSG(gs_patch_create(m, faces, nf, &p, &err) == GS_OK, "%s", err.message);
    if (p) {
        uint32_t nl = gs_patch_num_vertices(p), lv = gs_patch_vertex_from_mesh(p, 0);
        double *got = malloc(nl * sizeof *got), *want = malloc(nl * sizeof *want);
        for (uint32_t l = 0; l < nl; ++l) {
            const double *q = pos(m, gs_patch_vertex_to_mesh(p, l));
            want[l] = q[0] <= x0 + 1e-9 ? hypot(q[0], q[1]) : INFINITY;
        }
        known(p, &(gs_source){lv, GS_NONE, {0, 0, 0}}, 1, want, nl, 1e-12, 0,
              "patch: band removed, right side inf");
        free(got);
        free(want);
    }
    gs_patch_free(p);
    free(faces);
    gs_mesh_free(m);
}

/* ---- invariants on curved meshes ---------------------------------------- */

#define N_SRC 6

typedef struct inv_count {
    uint32_t sym, self, tri, graph, eucl, lip;
    double sym_err;
} inv_count;

static void check_fields(const gs_mesh *m, const uint32_t *sv, double **d, double **g, double tol,
                         inv_count *c)
{
    uint32_t n = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    const uint32_t *t = gs_mesh_faces(m);
    for (int i = 0; i < N_SRC; ++i) {
        c->self += d[i][sv[i]] != 0;
        for (int j = 0; j < N_SRC; ++j) {
            double e = fabs(d[i][sv[j]] - d[j][sv[i]]);
            c->sym_err = fmax(c->sym_err, e);
            c->sym += e > tol;
            for (uint32_t v = 0; v < n; ++v) /* d(i,v) <= d(i,j) + d(j,v) */
                c->tri += d[i][v] > d[i][sv[j]] + d[j][v] + tol;
        }
        for (uint32_t v = 0; v < n; ++v) {
            c->graph += d[i][v] > g[i][v] + tol;
            c->eucl += d[i][v] < gs__test_dist3(pos(m, v), pos(m, sv[i])) - tol;
        }
        for (uint32_t h = 0; h < 3 * nf; ++h) {
            uint32_t a = t[h], b = t[h % 3 == 2 ? h - 2 : h + 1];
            c->lip += fabs(d[i][a] - d[i][b]) > gs__test_dist3(pos(m, a), pos(m, b)) + tol;
        }
    }
}

static void test_invariants(const char *spec)
{
    gs_mesh *m = generate(spec);
    gs_patch *p = m ? whole(m) : NULL;
    if (!p) goto done;
    uint32_t n = gs_mesh_num_vertices(m), sv[N_SRC];
    gs_mesh_report r;
    gs_mesh_get_report(m, &r, NULL);
    double diag = gs__test_dist3(r.bbox_min, r.bbox_max), tol = 1e-12 * diag;
    double *d[N_SRC], *g[N_SRC];
    int failed = 0;
    for (int i = 0; i < N_SRC; ++i) {
        sv[i] = (uint32_t)(((uint64_t)i * 2654435761u + 17) % n);
        d[i] = malloc(n * sizeof(double));
        g[i] = malloc(n * sizeof(double));
        gs_source s = gs_source_vertex(sv[i]);
        failed |= solve(p, GS_METHOD_EXACT, &s, 1, 0, d[i], spec);
        failed |= solve(p, GS_METHOD_GRAPH, &s, 1, 0, g[i], spec);
    }
    if (!failed) {
        inv_count c = {0};
        check_fields(m, sv, d, g, tol, &c);
        printf("%s: %d sources x %u vertices (tol %.1e): symmetry %u bad (max %.1e), d(x,x) %u, "
               "triangle %u, > graph %u, < euclid %u, edge-Lipschitz %u\n",
               spec, N_SRC, n, tol, c.sym, c.sym_err, c.self, c.tri, c.graph, c.eucl, c.lip);
        CHECK_MSG(c.sym == 0, "%s: symmetry", spec);
        CHECK_MSG(c.self == 0, "%s: d(x,x) != 0", spec);
        CHECK_MSG(c.tri == 0, "%s: triangle inequality", spec);
        CHECK_MSG(c.graph == 0, "%s: exact > graph", spec);
        CHECK_MSG(c.eucl == 0, "%s: exact < euclidean", spec);
        CHECK_MSG(c.lip == 0, "%s: |d(u)-d(v)| > |uv|", spec);
    }
    for (int i = 0; i < N_SRC; ++i) {
        free(d[i]);
        free(g[i]);
    }
done:
    gs_patch_free(p);
    gs_mesh_free(m);
}

int main(void)
{
    test_grid();
    test_plate();
    test_cylinder();
    test_cone();
    test_cube();
    test_two();
    test_patch();
    test_invariants("peaks:25");
    test_invariants("torus:24,12");
    test_invariants("sphere:2");
    return gs__test_finish("test_known_answers");
}
