/* test_sep.c - the SEP database end to end (paper sec. 3-5): build on
 * meshes like the paper's Table 1 (Square, Holes, Peaks; bunny-5k from
 * ../shared), compare database fields with exact fields (ME, RMSE as section
 * 5 defines them, and cost), check the query invariants (d(x,x) = 0,
 * symmetry, triangle inequality within the measured error, unreachable
 * pairs) and the save/open round trip. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct target {
    const char *name, *spec; /* spec: generator spec, or NULL for a shared mesh */
    const char *shared_mesh, *shared_gt;
    double me, rmse, cost;   /* the paper's Table 1 row (fractions)             */
    double g_me, g_rmse, g_cost; /* what this version guarantees (asserted)     */
} target;

/* The paper prints one decimal of a percentage: 0.1 covers values < 0.15.
 * The asserted guards are the paper's values where we meet them, else the
 * level this version reaches with a margin (doc/accuracy.md: the gap to the paper).
 * Costs: the fits certified between their samples and the long curves fitted
 * in pieces (doc/accuracy.md) store more numbers than the paper's fits,
 * checked only at their samples; guards at the measured cost + ~5%. */
static const target targets[] = {
    {"Square (grid 30x30)", "grid:30,30", NULL, NULL, 0.0015, 0.0025, 16.8, 0.0015, 0.0025, 19.4},
    {"Holes (plate, ~1400 v)", "plate:1400", NULL, NULL, 0.0015, 0.0065, 26.0, 0.0015, 0.0065, 29.0},
    {"Peaks (50x50)", "peaks:50", NULL, NULL, 0.0025, 0.0035, 37.5, 0.0030, 0.0055, 66},
    /* the same heights on MATLAB's surf(peaks(50)) grid (x, y = 1..50): the
     * paper does not say which Peaks it used (doc/accuracy.md) */
    {"Peaks, surf coordinates", "peaks:50,49", NULL, NULL, 0.0025, 0.0035, 37.5, 0.0025, 0.0035, 37.5},
    {"Bunny (bunny-5k)", NULL, "meshes/bunny-5k.obj", "groundtruth/bunny-5k.gt", 0.0045, 0.0135, 72.2,
     0.0045, 0.0135, 88},
};

static void exact_fields(const gs_mesh *m, const uint32_t *src, uint32_t k, double *out)
{
    gs_patch *p;
    gs_solver *s;
    gs_error err;
    uint32_t n = gs_mesh_num_vertices(m);
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    CHECK(gs_solver_create(p, GS_METHOD_EXACT, &s, &err) == GS_OK);
    for (uint32_t j = 0; j < k; ++j) {
        gs_source so = gs_source_vertex(src[j]);
        CHECK(gs_solver_solve(s, &so, 1, 0, out + (size_t)j * n, &err) == GS_OK);
    }
    gs_solver_free(s);
    gs_patch_free(p);
}

static uint64_t rng_state = 12345;
static uint32_t rnd(uint32_t n)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((rng_state >> 33) % n);
}

/* d(x,x) = 0, symmetry, triangle inequality within the measured error. */
static void invariants(const gs_db *db, uint32_t n, double max_err)
{
    double worst_sym = 0, worst_tri = 0;
    for (int t = 0; t < 20000; ++t) {
        uint32_t x = rnd(n), y = rnd(n), z = rnd(n);
        CHECK(gs_db_distance(db, x, x) == 0);
        double a = gs_db_distance(db, x, y), b = gs_db_distance(db, y, x);
        if (a > 0) worst_sym = fmax(worst_sym, fabs(a - b) / a);
        double xz = gs_db_distance(db, x, z), zy = gs_db_distance(db, z, y);
        if (a > 0 && isfinite(a)) worst_tri = fmax(worst_tri, (a - (xz + zy)) / a);
    }
    CHECK_MSG(worst_sym <= 1e-12, "symmetry violated by %.3g relative", worst_sym);
    CHECK_MSG(worst_tri <= 2 * max_err + 1e-12,
              "triangle inequality violated by %.3g relative (max error %.3g)", worst_tri, max_err);
    printf("    invariants: symmetry %.2g, triangle inequality excess %.2g (allowed %.2g)\n", worst_sym,
           worst_tri, 2 * max_err);
}

static void round_trip(const gs_db *db, uint32_t n)
{
    char path[] = "/tmp/geosep-test-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    close(fd);
    gs_error err;
    gs_db *back = NULL;
    CHECK(gs_db_save(db, path, &err) == GS_OK);
    CHECK(gs_db_open(path, &back, &err) == GS_OK);
    int same = back != NULL;
    for (int t = 0; same && t < 5000; ++t) {
        uint32_t x = rnd(n), y = rnd(n);
        double a = gs_db_distance(db, x, y), b = gs_db_distance(back, x, y);
        same = memcmp(&a, &b, sizeof a) == 0;
    }
    CHECK_MSG(same, "queries differ after save/open");
    gs_db_free(back);
    unlink(path);
}

static void run_target(const target *t)
{
    gs_mesh *m = NULL;
    gs_error err;
    gs_gt *gt = NULL;
    if (t->spec) {
        CHECK(gs_mesh_generate(t->spec, &m, &err) == GS_OK);
    } else {
        const char *mp = gs_test_shared_path(t->shared_mesh), *gp;
        if (!mp) {
            printf("%s: skipped (../shared not found)\n", t->name);
            return;
        }
        CHECK(gs_mesh_load(mp, GS_FORMAT_AUTO, &m, &err) == GS_OK);
        gp = gs_test_shared_path(t->shared_gt);
        if (!gp || gs_gt_read(gp, &gt, &err) != GS_OK) {
            printf("%s: skipped (no ground truth)\n", t->name);
            gs_mesh_free(m);
            return;
        }
    }
    if (!m) return;
    uint32_t n = gs_mesh_num_vertices(m);
    uint32_t k = gt ? gt->n_sources : 16;
    uint32_t *src = malloc(k * sizeof *src);
    double *exact = malloc((size_t)k * n * sizeof *exact);
    if (gt) {
        memcpy(src, gt->sources, k * sizeof *src);
        memcpy(exact, gt->dist, (size_t)k * n * sizeof *exact);
    } else {
        CHECK(gs_mesh_random_vertices(m, k, 1, src, &err) == GS_OK);
        exact_fields(m, src, k, exact);
    }
    gs_build_options o;
    gs_build_options_default(&o);
    gs_db *db = NULL;
    gs_build_stats st;
    int rc = gs_db_build(m, &o, &db, &st, &err);
    CHECK_MSG(rc == GS_OK, "%s: build failed: %s", t->name, err.message);
    if (rc == GS_OK) {
        gs_db_info info;
        CHECK(gs_db_get_info(db, &info, &err) == GS_OK);
        gs_test_errs e = gs_test_db_errors(db, src, k, exact, n);
        printf("%-24s n=%5u  ME %.3f%% (paper <= %.2f)  RMSE %.3f%% (<= %.2f)  max %.2f%%  cost %.1f (<= %.1f)"
               "  depth %.1f/%u  build %.2f s\n",
               t->name, n, 100 * e.me, 100 * t->me, 100 * e.rmse, 100 * t->rmse, 100 * e.max, info.cost,
               t->cost, info.avg_depth, info.max_depth, st.seconds_total);
        printf("    paper's row met: ME %s, RMSE %s, cost %s\n", e.me <= t->me ? "yes" : "no",
               e.rmse <= t->rmse ? "yes" : "no", info.cost <= t->cost ? "yes" : "no");
        CHECK_MSG(e.me <= t->g_me, "%s: ME %.4f%% above %.2f%%", t->name, 100 * e.me, 100 * t->g_me);
        CHECK_MSG(e.rmse <= t->g_rmse, "%s: RMSE %.4f%% above %.2f%%", t->name, 100 * e.rmse, 100 * t->g_rmse);
        CHECK_MSG(info.cost <= t->g_cost, "%s: cost %.2f above %.1f", t->name, info.cost, t->g_cost);
        invariants(db, n, e.max);
        round_trip(db, n);
    }
    gs_db_free(db);
    free(src);
    free(exact);
    gs_gt_free(gt);
    gs_mesh_free(m);
}

/* Two components: pairs across them are unreachable. */
static void unreachable(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("two:12", &m, &err) == GS_OK);
    gs_db *db = NULL;
    CHECK(gs_db_build(m, NULL, &db, NULL, &err) == GS_OK);
    uint32_t n = gs_mesh_num_vertices(m);
    CHECK(isinf(gs_db_distance(db, 0, n - 1)));
    CHECK(isfinite(gs_db_distance(db, 0, n / 2 - 1)));
    CHECK(isnan(gs_db_distance(db, 0, n)));
    gs_db_free(db);
    gs_mesh_free(m);
}

static long file_bytes(const char *path, unsigned char **data)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    *data = malloc(n > 0 ? (size_t)n : 1);
    if (fread(*data, 1, (size_t)n, f) != (size_t)n) n = -1;
    fclose(f);
    return n;
}

/* The same mesh and options give the same file, whatever the thread count. */
static void reproducible(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("peaks:30", &m, &err) == GS_OK);
    char p1[] = "/tmp/geosep-rep1-XXXXXX", p2[] = "/tmp/geosep-rep2-XXXXXX";
    close(mkstemp(p1));
    close(mkstemp(p2));
    const char *paths[2] = {p1, p2};
    for (int t = 0; t < 2; ++t) {
        gs_build_options o;
        gs_build_options_default(&o);
        o.threads = (uint32_t)(t + 1);
        gs_db *db = NULL;
        CHECK(gs_db_build(m, &o, &db, NULL, &err) == GS_OK);
        CHECK(gs_db_save(db, paths[t], &err) == GS_OK);
        gs_db_free(db);
    }
    unsigned char *a = NULL, *b = NULL;
    long na = file_bytes(p1, &a), nb = file_bytes(p2, &b);
    CHECK_MSG(na > 0 && na == nb && memcmp(a, b, (size_t)na) == 0,
              "1 and 2 threads give different databases (%ld vs %ld bytes)", na, nb);
    free(a);
    free(b);
    unlink(p1);
    unlink(p2);
    gs_mesh_free(m);
}

/* The build variants: the paper's vertex sources, SEPsam, graph fields. */
static void variants(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("grid:20,20", &m, &err) == GS_OK);
    uint32_t n = gs_mesh_num_vertices(m), src[8];
    CHECK(gs_mesh_random_vertices(m, 8, 5, src, &err) == GS_OK);
    double *exact = malloc((size_t)8 * n * sizeof *exact);
    exact_fields(m, src, 8, exact);
    for (int v = 0; v < 3; ++v) {
        gs_build_options o;
        gs_build_options_default(&o);
        if (v == 0) o.vertex_sources = 1;
        if (v == 1) o.sampled = 1;
        if (v == 2) o.method = GS_METHOD_GRAPH;
        gs_db *db = NULL;
        int rc = gs_db_build(m, &o, &db, NULL, &err);
        CHECK_MSG(rc == GS_OK, "variant %d: %s", v, err.message);
        if (rc) continue;
        gs_test_errs e = gs_test_db_errors(db, src, 8, exact, n);
        gs_db_info info;
        CHECK(gs_db_get_info(db, &info, &err) == GS_OK);
        /* the default source mode follows the method: vertices for graph fields */
        CHECK(info.vertex_sources == (v == 0 || v == 2) && info.sampled == (v == 1) &&
              info.method == (v == 2 ? GS_METHOD_GRAPH : GS_METHOD_EXACT));
        /* exact fields compress to well under 1% (SEPsam's discrete minimum
         * overestimates close pairs by up to a sample spacing); graph fields
         * compress the graph's own, longer distances: ~12% on a grid */
        double bound = v == 2 ? 0.2 : (v == 1 ? 0.004 : 0.005);
        printf("variant %s: ME %.3f%%, RMSE %.3f%%, cost %.1f\n",
               v == 0 ? "vertex sources" : (v == 1 ? "sampled (SEPsam)" : "graph fields"), 100 * e.me,
               100 * e.rmse, info.cost);
        CHECK_MSG(e.me <= bound, "variant %d: ME %.4f%% above %.2f%%", v, 100 * e.me, 100 * bound);
        gs_db_free(db);
    }
    free(exact);
    gs_mesh_free(m);
}

int main(void)
{
    for (size_t i = 0; i < sizeof targets / sizeof *targets; ++i) run_target(&targets[i]);
    unreachable();
    reproducible();
    variants();
    return gs_test_finish("test_sep");
}
