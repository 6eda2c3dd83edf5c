/* test_leaf_exact.c - the leaf_exact build option (paper sec. 3.1, matrix D):
 * every same-leaf query answers the exact whole-mesh distance to the tables'
 * 16-bit step, whatever the build method (checked against unbounded
 * whole-mesh fields), which beats the
 * Euclidean answer on curved meshes and across holes; other queries are
 * unchanged; tables are symmetric with a zero diagonal; results do not depend
 * on the thread count; save/open keeps every answer bit for bit and the info
 * reports the tables. */
#include "check.h"
#include "geosep.h"
#include "db/db_internal.h"
#include "partition/tree.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t g_vmax = 0; /* 0: the default leaf size */

static gs_db *build(const gs_mesh *m, gs_method method, int leaf_exact, uint32_t threads)
{
    gs_build_options o;
    gs_build_options_default(&o);
    if (g_vmax) o.vmax = g_vmax;
    o.method = method;
    o.leaf_exact = leaf_exact;
    o.threads = threads;
    gs_db *db = NULL;
    gs_error e = {0};
    int rc = gs_db_build(m, &o, &db, NULL, &e);
    CHECK_MSG(rc == GS_OK, "build (leaf_exact %d): %s", leaf_exact, e.message);
    return db;
}

/* The tree the builder uses for the default options. */
static gs__tree *tree_of(const gs_mesh *m)
{
    gs_build_options o;
    gs_build_options_default(&o);
    gs__tree_options to;
    gs__tree_options_default(&to);
    to.vmax = g_vmax ? g_vmax : o.vmax;
    to.seed = o.seed;
    to.sample_spacing = o.sample_spacing;
    gs__tree *t = NULL;
    gs_error e = {0};
    int rc = gs__tree_build(m, &to, &t, &e);
    CHECK_MSG(rc == GS_OK, "tree: %s", e.message);
    return t;
}

static int rel_equal(double a, double b, double tol)
{
    if (isinf(a) || isinf(b)) return a == b;
    return fabs(a - b) <= tol * fmax(fabs(a), fabs(b)) + 1e-300;
}

static double euclid(const gs_mesh *m, uint32_t x, uint32_t y)
{
    const double *p = gs_mesh_positions(m) + 3 * (size_t)x, *q = gs_mesh_positions(m) + 3 * (size_t)y;
    return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

/* Every same-leaf pair against the unbounded whole-mesh field of `method`.
 * The tables hold 16-bit values against the leaf's largest distance s
 * (doc/database-format.md): each answer is within s / (2 * 65534) of the
 * exact distance (and never below the Euclidean one), so within 0.08% of
 * it for every pair with d >= s / 100. Returns the number of pairs where
 * the exact answer is clearly longer than the Euclidean distance (what the
 * tables fix). */
static uint64_t check_leaves(const char *spec, const gs_mesh *m, const gs__tree *t, const gs_db *dx,
                             const gs_db *d0, gs_method method)
{
    uint32_t nv = gs_mesh_num_vertices(m);
    gs_patch *whole = NULL;
    gs_solver *s = NULL;
    CHECK(gs_patch_create(m, NULL, 0, &whole, NULL) == GS_OK);
    CHECK(gs_solver_create(whole, method, &s, NULL) == GS_OK);
    double *f = malloc(nv * sizeof *f), *fd = malloc(nv * sizeof *fd), *ex = NULL;
    uint64_t n_pairs = 0, n_better = 0, n_bad = 0, n_asym = 0, n_changed = 0, n_field = 0, n_far = 0;
    double worst_abs = 0.0, worst_far = 0.0; /* |error| / s, and relative for d >= s / 100 */
    for (uint32_t l = 0; l < t->n_nodes; ++l) {
        const gs__tree_node *nd = &t->nodes[l];
        if (nd->child[0] != GS_NONE) continue;
        uint32_t n = nd->n_verts;
        double *grown = realloc(ex, ((size_t)n * n + 1) * sizeof *ex);
        if (!grown) break;
        ex = grown;
        double top = 0.0; /* the leaf's largest finite exact distance */
        for (uint32_t i = 0; i < n; ++i) {
            gs_source src = gs_source_vertex(t->verts[nd->vert_start + i]);
            CHECK(gs_solver_solve(s, &src, 1, 0, f, NULL) == GS_OK);
            for (uint32_t j = 0; j < n; ++j) {
                double d = f[t->verts[nd->vert_start + j]];
                ex[(size_t)i * n + j] = d;
                if (d < INFINITY && d > top) top = d;
            }
        }
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t x = t->verts[nd->vert_start + i];
            CHECK(gs_db_field(dx, x, fd, NULL) == GS_OK);
            for (uint32_t j = 0; j < n; ++j) {
                uint32_t y = t->verts[nd->vert_start + j];
                double a = gs_db_distance(dx, x, y), b = gs_db_distance(dx, y, x), d = ex[(size_t)i * n + j];
                /* the table holds the smaller of d(x,y), d(y,x) (leaves.c) */
                if (ex[(size_t)j * n + i] < d) d = ex[(size_t)j * n + i];
                n_pairs++;
                if (x == y) {
                    CHECK(a == 0);
                    continue;
                }
                double err = isinf(a) || isinf(d) ? (a == d ? 0.0 : INFINITY) : fabs(a - d);
                if (top > 0 && err / top > worst_abs) worst_abs = err / top;
                if (d >= top / 100 && d > 0 && d < INFINITY) {
                    n_far++;
                    if (err / d > worst_far) worst_far = err / d;
                }
                if (!(err <= top / (2.0 * 65534) * (1 + 1e-6) + 1e-12 * d) && n_bad++ < 5)
                    fprintf(stderr, "%s: leaf %u: d(%u,%u) = %.17g, exact %.17g (leaf's largest %.17g)\n", spec, l,
                            x, y, a, d, top);
                CHECK(a >= euclid(m, x, y) * (1 - 1e-12));
                n_asym += a != b;
                n_field += fd[y] != a;
                if (a > euclid(m, x, y) * (1 + 1e-6)) n_better++;
            }
            /* a few other-leaf queries are exactly those of the plain database */
            for (uint32_t y = (x * 7919u) % nv, k = 0; k < 16; ++k, y = (y + 97) % nv)
                if (t->leaf_of_vertex[y] != l) n_changed += gs_db_distance(dx, x, y) != gs_db_distance(d0, x, y);
        }
    }
    CHECK_MSG(n_bad == 0, "%s: %llu of %llu same-leaf pairs off the exact field by more than the 16-bit step", spec,
              (unsigned long long)n_bad, (unsigned long long)n_pairs);
    CHECK_MSG(worst_far <= 8e-4, "%s: relative error %.3g%% for a pair with d >= s/100", spec, 100 * worst_far);
    CHECK_MSG(n_asym == 0, "%s: %llu asymmetric pairs", spec, (unsigned long long)n_asym);
    CHECK_MSG(n_field == 0, "%s: %llu pairs where gs_db_field disagrees", spec, (unsigned long long)n_field);
    CHECK_MSG(n_changed == 0, "%s: %llu other-leaf answers changed", spec, (unsigned long long)n_changed);
    printf("%s (%s): %llu same-leaf pairs within the 16-bit step (largest error %.2g of the leaf's largest "
           "distance; %.4f%% relative for the %llu pairs with d >= 1%% of it), %llu longer than Euclidean\n",
           spec, gs_method_name(method), (unsigned long long)n_pairs, worst_abs, 100 * worst_far,
           (unsigned long long)n_far, (unsigned long long)n_better);
    free(ex);
    free(f);
    free(fd);
    gs_solver_free(s);
    gs_patch_free(whole);
    return n_better;
}

/* The plain database answers same-leaf queries with the Euclidean distance. */
static void check_plain_is_euclidean(const gs_mesh *m, const gs__tree *t, const gs_db *d0)
{
    uint64_t bad = 0;
    for (uint32_t l = 0; l < t->n_nodes; ++l) {
        const gs__tree_node *nd = &t->nodes[l];
        if (nd->child[0] != GS_NONE) continue;
        for (uint32_t i = 0; i < nd->n_verts; ++i)
            for (uint32_t j = 0; j < nd->n_verts; ++j) {
                uint32_t x = t->verts[nd->vert_start + i], y = t->verts[nd->vert_start + j];
                bad += !rel_equal(gs_db_distance(d0, x, y), euclid(m, x, y), 1e-12);
            }
    }
    CHECK_MSG(bad == 0, "%llu same-leaf answers of the plain database are not Euclidean", (unsigned long long)bad);
}

static void check_mesh(const char *spec, gs_method method, int want_better)
{
    gs_mesh *m = NULL;
    gs_error e = {0};
    int rc = gs_mesh_generate(spec, &m, &e);
    CHECK_MSG(rc == GS_OK, "%s: %s", spec, e.message);
    if (rc) return;
    gs__tree *t = tree_of(m);
    gs_db *dx = build(m, method, 1, 2), *d0 = build(m, method, 0, 2);
    if (t && dx && d0) {
        /* the tables are exact whatever the method (leaves.c) */
        uint64_t better = check_leaves(spec, m, t, dx, d0, GS_METHOD_EXACT);
        if (want_better) CHECK_MSG(better > 0, "%s: no same-leaf pair improves on Euclidean", spec);
        check_plain_is_euclidean(m, t, d0);
        /* local numbers in 8 bits, or 16 when a leaf has more than 256 vertices */
        uint32_t big = 0;
        for (uint32_t l = 0; l < t->n_nodes; ++l)
            if (t->nodes[l].child[0] == GS_NONE && t->nodes[l].n_verts > big) big = t->nodes[l].n_verts;
        CHECK_MSG((dx->leaf_local16 != NULL) == (big > 256) && (dx->leaf_local8 != NULL) == (big <= 256),
                  "%s: largest leaf %u, 16-bit local numbers %d", spec, big, dx->leaf_local16 != NULL);
        CHECK_MSG(g_vmax <= 256 || big > 256, "%s: vmax %u but no leaf above 256 vertices (%u)", spec, g_vmax, big);
    }
    gs_db_free(dx);
    gs_db_free(d0);
    gs__tree_free(t);
    gs_mesh_free(m);
}

/* All pairs (x, y) for x in a sample, bit for bit. */
static uint64_t n_differ(const gs_db *a, const gs_db *b, uint32_t nv)
{
    uint64_t n = 0;
    double *fa = malloc(nv * sizeof *fa), *fb = malloc(nv * sizeof *fb);
    for (uint32_t x = 0; x < nv; x += 7) {
        CHECK(gs_db_field(a, x, fa, NULL) == GS_OK);
        CHECK(gs_db_field(b, x, fb, NULL) == GS_OK);
        n += memcmp(fa, fb, nv * sizeof *fa) != 0;
        for (uint32_t y = 0; y < nv; y += 3) {
            double p = gs_db_distance(a, x, y), q = gs_db_distance(b, x, y);
            n += memcmp(&p, &q, sizeof p) != 0;
        }
    }
    free(fa);
    free(fb);
    return n;
}

static void check_roundtrip_and_threads(void)
{
    gs_mesh *m = NULL;
    CHECK(gs_mesh_generate("peaks:30", &m, NULL) == GS_OK);
    if (!m) return;
    uint32_t nv = gs_mesh_num_vertices(m);
    gs_db *dx = build(m, GS_METHOD_EXACT, 1, 2), *d1 = build(m, GS_METHOD_EXACT, 1, 1);
    gs_db *d0 = build(m, GS_METHOD_EXACT, 0, 2);
    if (!dx || !d1 || !d0) goto out;
    CHECK_MSG(n_differ(dx, d1, nv) == 0, "1 and 2 threads give different answers");

    const char *p1 = GEOSEP_BINARY_DIR "/test_leaf_exact_1.gsdb", *p0 = GEOSEP_BINARY_DIR "/test_leaf_exact_0.gsdb";
    gs_error e = {0};
    CHECK_MSG(gs_db_save(dx, p1, &e) == GS_OK, "%s", e.message);
    CHECK_MSG(gs_db_save(d0, p0, &e) == GS_OK, "%s", e.message);
    gs_db *rx = NULL, *r0 = NULL;
    CHECK_MSG(gs_db_open(p1, &rx, &e) == GS_OK, "%s", e.message);
    CHECK_MSG(gs_db_open(p0, &r0, &e) == GS_OK, "%s", e.message);
    if (rx && r0) {
        CHECK_MSG(n_differ(dx, rx, nv) == 0, "answers change after save/open");
        gs_db_info ix, i0, ibuilt;
        CHECK(gs_db_get_info(rx, &ix, NULL) == GS_OK);
        CHECK(gs_db_get_info(r0, &i0, NULL) == GS_OK);
        CHECK(gs_db_get_info(dx, &ibuilt, NULL) == GS_OK);
        CHECK(ix.leaf_exact == 1 && ibuilt.leaf_exact == 1);
        CHECK(i0.leaf_exact == 0);
        CHECK(ix.file_bytes == ibuilt.file_bytes);
        /* on top: 2 bytes per pair of a leaf's vertices, a byte per vertex,
         * 16 per node, each section padded to 8 bytes */
        gs__tree *t = tree_of(m);
        uint64_t entries = 0;
        for (uint32_t l = 0; t && l < t->n_nodes; ++l)
            if (t->nodes[l].child[0] == GS_NONE)
                entries += (uint64_t)t->nodes[l].n_verts * (t->nodes[l].n_verts - 1) / 2;
        uint64_t want = 2 * entries + nv + 16 * (uint64_t)(t ? t->n_nodes : 0);
        gs__tree_free(t);
        CHECK_MSG(ix.file_bytes - i0.file_bytes >= want + 3 * 32 && ix.file_bytes - i0.file_bytes <= want + 3 * 32 + 14,
                  "%llu vs %llu + %llu", (unsigned long long)ix.file_bytes, (unsigned long long)i0.file_bytes,
                  (unsigned long long)want);
        CHECK(ix.cost == i0.cost); /* the separator functions are unchanged */
    }
    gs_db_free(rx);
    gs_db_free(r0);
    remove(p1);
    remove(p0);
out:
    gs_db_free(dx);
    gs_db_free(d1);
    gs_db_free(d0);
    gs_mesh_free(m);
}

/* Two components and unreferenced-free generators: the tables still build
 * and cross-component queries stay infinite. */
static void check_two_components(void)
{
    gs_mesh *m = NULL;
    CHECK(gs_mesh_generate("two:12", &m, NULL) == GS_OK);
    if (!m) return;
    gs__tree *t = tree_of(m);
    gs_db *dx = build(m, GS_METHOD_EXACT, 1, 2), *d0 = build(m, GS_METHOD_EXACT, 0, 2);
    if (t && dx && d0) {
        check_leaves("two:12", m, t, dx, d0, GS_METHOD_EXACT);
        uint32_t nv = gs_mesh_num_vertices(m);
        CHECK(isinf(gs_db_distance(dx, 0, nv - 1)));
    }
    gs_db_free(dx);
    gs_db_free(d0);
    gs__tree_free(t);
    gs_mesh_free(m);
}

int main(void)
{
    check_mesh("cylinder:24,20", GS_METHOD_EXACT, 1);
    check_mesh("peaks:30", GS_METHOD_EXACT, 1);
    check_mesh("plate:1400", GS_METHOD_EXACT, 1);
    check_mesh("torus:40,16", GS_METHOD_EXACT, 1);
    check_mesh("peaks:24", GS_METHOD_GRAPH, 1);
    check_mesh("peaks:24", GS_METHOD_FMM, 1); /* fmm's tables had +inf pairs before they were exact */
    /* leaves of up to 600 vertices: 16-bit local numbers (format flags bit 1) */
    g_vmax = 600;
    check_mesh("peaks:30", GS_METHOD_EXACT, 1);
    g_vmax = 0;
    check_roundtrip_and_threads();
    check_two_components();
    return gs__test_finish("test_leaf_exact");
}
