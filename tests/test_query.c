/* test_query.c - point-to-point queries (paper sec. 3.2) on the hand-made
 * database of tests/util/db_fixture.c: same-leaf, cross-leaf against brute force and a
 * no-reject reference, symmetry, unreachable, batch and field; and the
 * section 5 error measures on hand-made fields. */
#include "check.h"
#include "db_fixture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

/* Reference without quick reject: all common curves, via gs__fun_pair_min. */
static double ref_no_reject(const fixture *f, uint32_t x, uint32_t y)
{
    uint32_t a = f->leaf[x], b = f->leaf[y];
    while (a != b) { /* the fixture's leaves: climb the deeper one */
        if (f->nodes[a].depth >= f->nodes[b].depth) a = f->nodes[a].parent;
        else b = f->nodes[b].parent;
    }
    double best = INFINITY;
    for (; a != GS_NONE; a = f->nodes[a].parent)
        for (uint32_t j = 0; j < f->nodes[a].n_curves; ++j) {
            uint32_t k = f->nodes[a].curve_prefix + j;
            const gs__fun *fx = &f->funs[f->fun_start[x] + k], *fy = &f->funs[f->fun_start[y] + k];
            if (fx->minval == INFINITY || fy->minval == INFINITY) continue;
            double d = gs__fun_pair_min(fx, fy, NULL);
            if (d < best) best = d;
        }
    return best;
}

/* Brute force, independent of gs__fun_pair_min: dense scan of the values. */
static double ref_dense(const fixture *f, uint32_t x, uint32_t y)
{
    uint32_t a = f->leaf[x], b = f->leaf[y];
    while (a != b) {
        if (f->nodes[a].depth >= f->nodes[b].depth) a = f->nodes[a].parent;
        else b = f->nodes[b].parent;
    }
    double best = INFINITY;
    for (; a != GS_NONE; a = f->nodes[a].parent)
        for (uint32_t j = 0; j < f->nodes[a].n_curves; ++j) {
            uint32_t k = f->nodes[a].curve_prefix + j;
            const gs__fun *fx = &f->funs[f->fun_start[x] + k], *fy = &f->funs[f->fun_start[y] + k];
            if (fx->minval == INFINITY || fy->minval == INFINITY) continue;
            for (int i = 0; i <= 200000; ++i) {
                double u = -1 + i / 100000.0, s = gs__fun_value(fx, u) + gs__fun_value(fy, u);
                if (s < best) best = s;
            }
        }
    return best;
}

static double euclid(const fixture *f, uint32_t x, uint32_t y)
{
    double s = 0;
    for (int i = 0; i < 3; ++i) s += (f->xyz[3 * x + i] - f->xyz[3 * y + i]) * (f->xyz[3 * x + i] - f->xyz[3 * y + i]);
    return sqrt(s);
}

static void test_pairs(int leaf_exact)
{
    fixture f;
    gs_db *db = fixture_db(&f, leaf_exact);
    if (!db) return;
    uint32_t n_clamped = 0;
    for (uint32_t x = 0; x < FX_NV; ++x)
        for (uint32_t y = 0; y < FX_NV; ++y) {
            double d = gs_db_distance(db, x, y);
            CHECK(d == gs_db_distance(db, y, x)); /* symmetry, bit-exact */
            if (x == y) {
                CHECK(d == 0);
            } else if (x == 6 || y == 6) {
                CHECK(d == INFINITY);
            } else if (f.leaf[x] == f.leaf[y]) {
                /* a leaf table's largest entry is its scale: a float */
                CHECK_NEAR(d, (leaf_exact ? 1.25 : 1.0) * euclid(&f, x, y), leaf_exact ? 1e-7 * d : 1e-15);
            } else {
                /* the query never answers below the straight-line distance */
                double e = euclid(&f, x, y), r = fmax(ref_no_reject(&f, x, y), e);
                n_clamped += r == e;
                /* the file stores each function within 1e-3 of its
                 * minimum (16-bit coefficients, float32 shift) */
                CHECK_MSG(fabs(d - r) <= 1e-3 * r + 1e-12 || (d == INFINITY && r == INFINITY), "%u %u: %.17g vs %.17g",
                          x, y, d, r);
                double b = fmax(ref_dense(&f, x, y), e);
                CHECK_MSG(fabs(d - b) <= 1e-3 * b + 1e-12 || (d == INFINITY && b == INFINITY),
                          "%u %u: %.17g vs dense %.17g", x, y, d, b);
            }
        }
    CHECK_MSG(n_clamped > 0, "the fixture should exercise the Euclidean lower bound");
    /* analytic: leaves 1 and 3 share only the root's path curve, where both
     * functions are a + b (u - t0)^2 with interior minimiser */
    for (uint32_t x = 0; x < 2; ++x)
        for (uint32_t y = 2; y < 4; ++y) {
            uint64_t i = f.fun_start[x], j = f.fun_start[y];
            double b1 = f.qb[i], b2 = f.qb[j], t1 = f.qt[i], t2 = f.qt[j];
            double want = f.qa[i] + f.qa[j] + b1 * b2 / (b1 + b2) * (t1 - t2) * (t1 - t2);
            CHECK_NEAR(gs_db_distance(db, x, y), fmax(want, euclid(&f, x, y)), 1e-3 * want);
        }
    /* vertex 5 reaches the root's curve from nowhere: no common finite curve */
    CHECK(gs_db_distance(db, 0, 5) == INFINITY && gs_db_distance(db, 5, 1) == INFINITY);
    CHECK(isfinite(gs_db_distance(db, 2, 5))); /* via the loop only */
    CHECK(isnan(gs_db_distance(db, 0, FX_NV)) && isnan(gs_db_distance(db, GS_NONE, 0)));
    CHECK(isnan(gs_db_distance(NULL, 0, 1)));
    gs_db_free(db);
}

static void test_batch_field(void)
{
    fixture f;
    gs_db *db = fixture_db(&f, 0);
    if (!db) return;
    uint32_t pairs[2 * FX_NV * FX_NV];
    double out[FX_NV * FX_NV], field[FX_NV];
    for (uint32_t x = 0; x < FX_NV; ++x)
        for (uint32_t y = 0; y < FX_NV; ++y) pairs[2 * (x * FX_NV + y)] = x, pairs[2 * (x * FX_NV + y) + 1] = y;
    gs_error err = {0};
    CHECK(gs_db_distances(db, pairs, FX_NV * FX_NV, out, &err) == GS_OK);
    for (uint32_t x = 0; x < FX_NV; ++x) {
        CHECK(gs_db_field(db, x, field, &err) == GS_OK);
        for (uint32_t y = 0; y < FX_NV; ++y) {
            double d = gs_db_distance(db, x, y);
            CHECK(memcmp(&d, &out[x * FX_NV + y], 8) == 0);
            CHECK(memcmp(&d, &field[y], 8) == 0);
        }
    }
    pairs[5] = 99;
    CHECK(gs_db_distances(db, pairs, 4, out, &err) == GS_EARG && strstr(err.message, "pair 2") && isnan(out[2]));
    CHECK(gs_db_field(db, FX_NV, field, &err) == GS_EARG);
    CHECK(gs_db_field(db, 0, NULL, &err) == GS_EARG);
    CHECK(gs_db_distances(db, pairs, 0, NULL, &err) == GS_OK);
    gs_db_free(db);
}

static void test_errors(void)
{
    double exact[7] = {0, 1, 2, 0, INFINITY, 4, 5};
    double approx[7] = {0, 1.1, 2.6, 0.3, 2, -1, NAN};
    gs_field_errors e;
    gs_error err;
    CHECK(gs_field_errors_compute(exact, approx, 7, 0, &e, &err) == GS_OK);
    CHECK_NEAR(e.me, 0.2, 1e-15);
    CHECK_NEAR(e.rmse, sqrt(0.05), 1e-15);
    CHECK_NEAR(e.max, 0.3, 1e-15);
    CHECK(e.n_used == 2 && e.n_skipped == 2 && e.n_invalid == 2);
    /* the source is left out whatever it holds; exact 0 at y != source skipped */
    approx[0] = 123;
    CHECK(gs_field_errors_compute(exact, approx, 7, 0, &e, &err) == GS_OK && e.n_used == 2);
    CHECK(gs_field_errors_compute(exact, approx, 7, 3, &e, &err) == GS_OK);
    CHECK(e.n_skipped == 2 && e.n_used == 2 && e.n_invalid == 2); /* y=0 (d=0), y=4 (inf) */
    CHECK(gs_field_errors_compute(exact, approx, 1, 0, &e, &err) == GS_OK && e.n_used == 0 && isnan(e.me));
    CHECK(gs_field_errors_compute(exact, approx, 7, 7, &e, &err) == GS_EARG);
    CHECK(gs_field_errors_compute(NULL, approx, 7, 0, &e, &err) == GS_EARG);
}

/* The robust reference on the stored functions: every common curve of x
 * and y (no quick reject), the functions decoded from the file's blocks,
 * gs__fun_pair_min; at least the straight segment. */
static double ref_stored(const gs_db *db, uint32_t x, uint32_t y)
{
    uint32_t lx = db->leaf[x], ly = db->leaf[y];
    if (x == y) return 0.0;
    if (lx == GS_NONE || ly == GS_NONE) return INFINITY;
    uint32_t a = lx, b = ly;
    while (a != b) {
        if (db->nodes[a].depth >= db->nodes[b].depth) a = db->nodes[a].parent;
        else b = db->nodes[b].parent;
    }
    const double *p = db->xyz + 3 * (size_t)x, *q = db->xyz + 3 * (size_t)y;
    double e = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    if (lx == ly) return -1; /* same leaf: not this reference's business */
    double best = INFINITY;
    uint32_t K = db->nodes[a].curve_prefix + db->nodes[a].n_curves;
    gs__fun fx[64], fy[64];
    double cx[64][GS_FUN_MAX_DEGREE + 1], cy[64][GS_FUN_MAX_DEGREE + 1];
    for (int v = 0; v < 2; ++v) {
        uint32_t z = v ? y : x;
        const unsigned char *end, *r = gs__db_record(db, z, &end);
        uint32_t nf = db->nodes[v ? ly : lx].curve_prefix;
        const unsigned char *blk = r + GS__DB_MIN_BYTES * (size_t)nf;
        for (uint32_t k = 0; k < K && k < 64; ++k) {
            float mv = gs__db_min_get(r, k);
            gs__fun *f = v ? &fy[k] : &fx[k];
            memset(f, 0, sizeof *f);
            f->minval = mv;
            if (mv == INFINITY) continue;
            gs__db_fblock bl;
            memset(&bl, 0, sizeof bl);
            double *c = v ? cy[k] : cx[k];
            if (!gs__db_fblock_parse(blk, (uint64_t)(end - blk), &bl) || bl.sampled || !gs__db_fblock_coef(&bl, c)) {
                CHECK_MSG(0, "vertex %u: function %u's block", z, k);
                return NAN;
            }
            *f = (gs__fun){GS_FUN_CHEBYSHEV, bl.degree, bl.squared, bl.closed, bl.shift, mv, c};
            blk += bl.bytes;
        }
    }
    for (uint32_t k = 0; k < K && k < 64; ++k)
        if (fx[k].minval < INFINITY && fy[k].minval < INFINITY) {
            double d = gs__fun_pair_min(&fx[k], &fy[k], NULL);
            best = d < best ? d : best;
        }
    return best < e ? e : best;
}

/* Built databases of generated meshes (paths, loops, holes, two
 * components): the built and the saved-and-opened database answer bit for
 * bit alike, pairs as fields; every answer is the robust minimiser's over
 * the stored functions (never below it beyond rounding, close to it); the
 * batch gives the single queries' answers with bad ids anywhere. */
static void test_built(const char *spec)
{
    gs_mesh *m = NULL;
    gs_db *built = NULL, *opened = NULL;
    gs_error err = {0};
    char path[] = "/tmp/geosep-test-XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0) close(fd);
    CHECK_MSG(gs_mesh_generate(spec, &m, &err) == GS_OK, "%s: %s", spec, err.message);
    CHECK(m && gs_db_build(m, NULL, &built, NULL, &err) == GS_OK);
    CHECK(built && gs_db_save(built, path, &err) == GS_OK);
    CHECK(gs_db_open(path, &opened, &err) == GS_OK);
    remove(path);
    if (!built || !opened) goto done;
    CHECK(gs_db_verify(opened, &err) == GS_OK);
    uint32_t n = gs_mesh_num_vertices(m), bad = 0, finite = 0, below = 0, far = 0;
    double sum = 0.0, worst = 0.0;
    double *f1 = malloc(sizeof *f1 * n), *f2 = malloc(sizeof *f2 * n);
    for (uint32_t x = 0; x < n && f1 && f2; ++x) {
        CHECK(gs_db_field(built, x, f1, NULL) == GS_OK && gs_db_field(opened, x, f2, NULL) == GS_OK);
        for (uint32_t y = 0; y < n; ++y) {
            double a = gs_db_distance(built, x, y), b = gs_db_distance(opened, x, y);
            bad += memcmp(&a, &b, 8) != 0 || memcmp(&a, &f1[y], 8) != 0 || memcmp(&b, &f2[y], 8) != 0 ||
                   a != gs_db_distance(built, y, x);
            finite += isfinite(a) && a > 0;
            if (y % 7 || x == y) continue; /* the robust reference on a sample */
            double r = ref_stored(opened, x, y);
            if (r < 0 || !isfinite(r)) {
                bad += r == INFINITY && a != INFINITY;
                continue;
            }
            double rel = (a - r) / r;
            below += rel < -1e-7; /* rounding: the two stop their Newton steps at different u
                                   * (plate:1400 with curve pieces: a few pairs below by up to 5e-8) */
            far += rel > 1e-3;
            sum += rel, worst = fmax(worst, fabs(rel));
        }
    }
    printf("  %s: answers above the robust minimiser's by %.2g on average, worst %.2g\n", spec,
           sum / ((double)n * n / 7), worst);
    CHECK_MSG(bad == 0, "%s: %u answers differ between built and opened, pair and field, or asymmetric", spec, bad);
    CHECK_MSG(finite >= n * (n - 1) / 2 - n, "%s: too few finite answers (%u)", spec, finite);
    CHECK_MSG(below == 0, "%s: %u answers below the robust minimiser's", spec, below);
    CHECK_MSG(far * 1000 <= (uint64_t)n * n / 7, "%s: %u answers above the robust minimiser's by > 1e-3", spec, far);
    uint32_t pairs[2 * 1000];
    double o1[1000];
    for (uint32_t i = 0; i < 2000; ++i) pairs[i] = (uint32_t)((i * 2654435761u) % n);
    /* The batch prefetches pairs ahead of the one it answers: with bad ids
     * (at the start, inside and at the end of its look-ahead), equal ids
     * and batches shorter than the look-ahead, it still gives the single
     * queries' answers bit for bit and names the first bad pair. */
    pairs[2 * 0] = n, pairs[2 * 3 + 1] = n, pairs[2 * 7] = GS_NONE, pairs[2 * 998 + 1] = n + 5;
    pairs[2 * 8] = pairs[2 * 8 + 1], pairs[2 * 999] = pairs[2 * 999 + 1];
    static const uint32_t lens[] = {1, 2, 3, 4, 5, 7, 8, 9, 12, 17, 100, 998};
    for (uint32_t from = 0; from < 2; ++from)
        for (size_t q = 0; q < sizeof lens / sizeof *lens; ++q) {
            uint32_t len = lens[q], diff = 0, first_bad = GS_NONE;
            for (uint32_t i = 0; i < len && first_bad == GS_NONE; ++i)
                if (pairs[2 * (from + i)] >= n || pairs[2 * (from + i) + 1] >= n) first_bad = i;
            char want[32];
            snprintf(want, sizeof want, "pair %u (", first_bad);
            int rc = gs_db_distances(opened, pairs + 2 * from, len, o1, &err);
            CHECK_MSG(first_bad == GS_NONE ? rc == GS_OK : rc == GS_EARG && strstr(err.message, want),
                      "%s: batch of %u from %u: status %d (%s)", spec, len, from, rc, rc ? err.message : "");
            for (uint32_t i = 0; i < len; ++i) {
                double d = gs_db_distance(opened, pairs[2 * (from + i)], pairs[2 * (from + i) + 1]);
                diff += memcmp(&d, &o1[i], 8) != 0;
            }
            CHECK_MSG(diff == 0, "%s: batch of %u from %u: %u answers differ from single queries", spec, len, from,
                      diff);
        }
    CHECK(gs_db_distances(opened, pairs, 1000, o1, &err) == GS_EARG);
    CHECK(isnan(o1[0]) && isnan(o1[3]) && isnan(o1[7]) && isnan(o1[998]) && o1[8] == 0.0 && o1[999] == 0.0);
    free(f1);
    free(f2);
done:
    gs_db_free(built);
    gs_db_free(opened);
    gs_mesh_free(m);
}

int main(void)
{
    test_pairs(0);
    test_pairs(1);
    test_batch_field();
    test_errors();
    test_built("torus:40,20"); /* loops */
    test_built("plate:1400");  /* paths, holes */
    test_built("two:10");      /* two components: unreachable pairs */
    return gs__test_finish("test_query");
}
