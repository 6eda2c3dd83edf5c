/* test_accuracy.c - the accuracy targets of the default build (issue 17,
 * doc/accuracy.md): on generated hard cases over ALL vertex pairs (exact
 * fields from every vertex, solved here; runs without ../shared), and on
 * the shared meshes up to 10,000 vertices against their ground truth when
 * ../shared is present.
 * Gated: ME, RMSE (the paper's, per source, averaged), p99.9 and max over
 * all pairs, near-pair ME (exact d < 10% of the median exact d). The bounds
 * are the targets, or where a mesh does not reach one yet, its measured
 * value with a small margin (named below: a regression still fails).
 * GEOSEP_QUICK=1 (the sanitizer run): the generated meshes only. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct bounds {
    double me, rmse, p999, max, near_me;
} bounds;

/* The targets. */
static const bounds targets = {0.0030, 0.0060, 0.02, 0.05, 0.005};

static void gate(const char *name, const gs_error_stats *st, const bounds *b, double bytes_per_vertex,
                 double cost)
{
    printf("%-18s ME %.3f%%  RMSE %.3f%%  p99 %.3f%%  p99.9 %.3f%%  max %.2f%%  near-pair ME %.3f%%  "
           "(%llu pairs; %.1f numbers, %.0f bytes per vertex)\n",
           name, 100 * st->me, 100 * st->rmse, 100 * st->p99, 100 * st->p999, 100 * st->max, 100 * st->near_me,
           (unsigned long long)st->n_used, cost, bytes_per_vertex);
    CHECK_MSG(st->n_invalid == 0, "%s: %llu invalid answers", name, (unsigned long long)st->n_invalid);
    CHECK_MSG(st->me <= b->me, "%s: ME %.4f%% > %.4f%%", name, 100 * st->me, 100 * b->me);
    CHECK_MSG(st->rmse <= b->rmse, "%s: RMSE %.4f%% > %.4f%%", name, 100 * st->rmse, 100 * b->rmse);
    CHECK_MSG(st->p999 <= b->p999, "%s: p99.9 %.4f%% > %.4f%%", name, 100 * st->p999, 100 * b->p999);
    CHECK_MSG(st->max <= b->max, "%s: max %.3f%% > %.3f%%", name, 100 * st->max, 100 * b->max);
    /* a coarse mesh may have no pair below 10% of the median (no near pair) */
    CHECK_MSG(st->n_near == 0 || st->near_me <= b->near_me, "%s: near-pair ME %.4f%% > %.4f%%", name,
              100 * st->near_me, 100 * b->near_me);
}

/* Build the default database of m and measure it against k exact fields
 * (sources src, fields exact: k x n). */
static void measure(const char *name, const gs_mesh *m, const uint32_t *src, uint32_t k, const double *exact,
                    const bounds *b)
{
    gs_error err = {0};
    gs_db *db = NULL;
    int rc = gs_db_build(m, NULL, &db, NULL, &err);
    CHECK_MSG(rc == GS_OK, "%s: build: %s", name, err.message);
    if (rc) return;
    uint32_t n = gs_mesh_num_vertices(m);
    double *d = malloc((size_t)n * sizeof *d);
    gs_error_acc *acc = NULL;
    CHECK(d && gs_error_acc_create(&acc, &err) == GS_OK);
    for (uint32_t j = 0; j < k && d && acc; ++j) {
        CHECK(gs_db_field(db, src[j], d, &err) == GS_OK);
        CHECK(gs_error_acc_add(acc, exact + (size_t)j * n, d, n, src[j], &err) == GS_OK);
    }
    gs_error_stats st;
    gs_db_info info;
    if (acc && gs_error_acc_result(acc, 0.1, &st, &err) == GS_OK && gs_db_get_info(db, &info, &err) == GS_OK)
        gate(name, &st, b, info.bytes_per_vertex, info.cost);
    else
        CHECK_MSG(0, "%s: %s", name, err.message);
    gs_error_acc_free(acc);
    free(d);
    gs_db_free(db);
}

/* Mesh m over all vertex pairs. */
static void all_pairs(const char *name, const gs_mesh *m, const bounds *b)
{
    gs_error err = {0};
    uint32_t n = gs_mesh_num_vertices(m);
    uint32_t *src = malloc(n * sizeof *src);
    double *exact = malloc((size_t)n * n * sizeof *exact);
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    CHECK(src && exact && gs_patch_create(m, NULL, 0, &p, &err) == GS_OK &&
          gs_solver_create(p, GS_METHOD_EXACT, &s, &err) == GS_OK);
    for (uint32_t v = 0; v < n && s; ++v) {
        src[v] = v;
        gs_source one = gs_source_vertex(v);
        CHECK(gs_solver_solve(s, &one, 1, 0, exact + (size_t)v * n, &err) == GS_OK);
    }
    if (s) measure(name, m, src, n, exact, b);
    gs_solver_free(s);
    gs_patch_free(p);
    free(exact);
    free(src);
}

/* A generated mesh over all vertex pairs. */
static void generated(const char *spec, const bounds *b)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_generate(spec, &m, &err) == GS_OK, "%s: %s", spec, err.message);
    if (m) all_pairs(spec, m, b);
    gs_mesh_free(m);
}

static double splitmix(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) / 9007199254740992.0;
}

/* A rough surface: the height field 0.2 sin 6x cos 5y on an n x n grid of
 * [0,1]^2, every height moved by up to +-amp/2 grid cells (uniform noise,
 * splitmix64 from seed): geodesics kink at every edge, fits cannot follow
 * them. Over all vertex pairs. */
static void noisy_terrain(uint32_t n, double amp, uint64_t seed, const bounds *b)
{
    char name[64];
    snprintf(name, sizeof name, "terrain:%u,%.1f,%llu", n, amp, (unsigned long long)seed);
    double *xyz = malloc(3 * (size_t)n * n * sizeof *xyz);
    uint32_t *tri = malloc(6 * (size_t)(n - 1) * (n - 1) * sizeof *tri), nf = 0;
    CHECK(xyz && tri);
    if (!xyz || !tri) goto done;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            double x = (double)i / (n - 1), y = (double)j / (n - 1), *p = xyz + 3 * ((size_t)j * n + i);
            p[0] = x, p[1] = y, p[2] = 0.2 * sin(6 * x) * cos(5 * y) + amp * (splitmix(&seed) - 0.5) / (n - 1);
        }
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i, nf += 2) {
            uint32_t a = j * n + i, *t = tri + 3 * (size_t)nf;
            t[0] = a, t[1] = a + 1, t[2] = a + 1 + n, t[3] = a, t[4] = a + 1 + n, t[5] = a + n;
        }
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_create(xyz, n * n, tri, nf, &m, &err) == GS_OK, "%s: %s", name, err.message);
    if (m) all_pairs(name, m, b);
    gs_mesh_free(m);
done:
    free(xyz);
    free(tri);
}

/* A shared mesh against its ground truth (its sources only). */
static void shared(const char *name, const bounds *b)
{
    char obj[4096], gtp[4096];
    if (!gs__test_shared_pair(name, obj, gtp, sizeof obj)) {
        printf("%-16s skipped: not in the shared data\n", name);
        return;
    }
    gs_mesh *m = NULL;
    gs_gt *gt = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_load(obj, GS_FORMAT_AUTO, &m, &err) == GS_OK && gs_gt_read(gtp, &gt, &err) == GS_OK, "%s: %s",
              name, err.message);
    if (m && gt) measure(name, m, gt->sources, gt->n_sources, gt->dist, b);
    gs_gt_free(gt);
    gs_mesh_free(m);
}

int main(void)
{
    /* generated, all pairs (CI); the trefoil tube's tail was near pairs
     * across a curve (13.17% without near pairs: doc/accuracy.md) */
    generated("knot:120,12", &targets);
    generated("cylinder:48,30", &targets);
    generated("cone:48,30", &targets);
    /* meshes of other character, never tuned for (doc/accuracy.md, "Meshes
     * nobody tuned for"; tools/unseen.sh runs the whole sweep): a coarse
     * torus (288 vertices, 2-3 edges across the tube), a cube's sharp edges
     * and corners, a thin knot with hexagonal rings */
    generated("torus:24,12,1,0.35", &targets);
    generated("cube:12", &targets);
    generated("knot:160,6,0.12", &targets);
    /* a noisy height field (2,500 vertices): the largest error was 4.43%
     * (8.8% on another seed) through fits that dip far from their vertex,
     * beyond the near radius; the radius now covers each dip's depth
     * (src/pipeline/build.c, near_radii): 2.19%, gated at 4%. Its ME was
     * 0.330% until rough surfaces got shorter curve pieces at the top of
     * the tree (build.c, mesh_roughness and GS_PIPE_ROUGH_OVER): 0.266%,
     * gated at the target (it fails without them). */
    const bounds rough = {0.0030, 0.0060, 0.02, 0.04, 0.005};
    noisy_terrain(50, 1.5, 3, &rough);
    if (getenv("GEOSEP_QUICK")) return gs__test_finish("test_accuracy");
    if (!gs__test_shared_path("meshes")) {
        printf("shared meshes skipped: no ../shared (GEOSEP_SHARED_DIR)\n");
        return gs__test_finish("test_accuracy");
    }
    shared("spot", &targets);
    shared("bunny-5k", &targets);
    shared("homer", &targets);
    shared("fandisk", &targets);
    shared("rocker-arm", &targets);
    shared("bunny-10k", &targets);
    /* bunny-20k, stanford-bunny and homer-60k: doc/accuracy.md (their builds
     * take minutes each) */
    return gs__test_finish("test_accuracy");
}
