/* test_near.c - section 'near_pairs' (src/db/db_near.h, issue 17): the
 * hand-made fixture with near pairs packed, saved, re-opened and queried
 * (stored pairs answer their stored distance, in both orders, all others
 * as without the section); every corruption of the section refused by the
 * structural open or by gs_db_verify, an unverified one queried without a
 * crash; and on a generated mesh, what the build stores: exactly the
 * cross-leaf pairs nearer than the radius that the separators answer off by
 * more than 2%, each answered within its 16-bit rounding of the exact
 * distance (16 significant bits: also on a graded grid whose nearest pairs
 * are 10^4 to 10^6 times nearer than the radius); a format 5 file read. */
#include "check.h"
#include "db/db_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db_fixture.h"

/* ---- the section inside a file ------------------------------------------- */

static unsigned char *table_entry(unsigned char *b, uint32_t id)
{
    uint32_t n_sec;
    memcpy(&n_sec, b + GS__H_SECTIONS, 4);
    for (uint32_t i = 0; i < n_sec; ++i) {
        unsigned char *t = b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * i;
        if (gs__get32(t) == id) return t;
    }
    return NULL;
}

static unsigned char *near_sec(unsigned char *b)
{
    return b + gs__get64(table_entry(b, GS__SEC_NEAR) + 8);
}

/* Recompute every checksum, so that only the checks of the structure and
 * values can object. */
static void reseal(unsigned char *b)
{
    uint32_t n_sec;
    memcpy(&n_sec, b + GS__H_SECTIONS, 4);
    for (uint32_t i = 0; i < n_sec; ++i) {
        unsigned char *t = b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * i;
        gs__put64(t + 24, gs__db_checksum(b + gs__get64(t + 8), (size_t)gs__get64(t + 16), NULL, 0));
    }
    gs__put64(b + GS__DB_CHECKSUM_AT,
              gs__db_checksum(b, GS__DB_CHECKSUM_AT, b + GS__DB_HEADER_BYTES, GS__DB_ENTRY_BYTES * n_sec));
}

/* ---- the fixture with near pairs ---------------------------------------- */

#define RADIUS 1.0
/* cross-leaf pairs (leaves: {0,1}, {2,3}, {4,5}), each at least its
 * Euclidean distance (0-2: 0.632, 1-2: 0.354, 2-4: 0.849) */
static const gs__near_pair PAIRS[] = {{0, 2, 0.75}, {1, 2, 0.5}, {2, 4, 0.9}};
#define N_PAIRS (sizeof PAIRS / sizeof *PAIRS)

static gs_db *near_fixture(fixture *f, const gs__near_pair *p, uint64_t n)
{
    make_fixture(f, 1);
    f->c.near_radius = RADIUS;
    f->c.near_pairs = p;
    f->c.n_near = n;
    gs_db *db = NULL;
    gs_error err = {0};
    CHECK_MSG(gs__db_pack(&f->c, &db, &err) == GS_OK, "pack: %s", err.message);
    return db;
}

static const gs__near_pair *stored(uint32_t x, uint32_t y)
{
    for (size_t i = 0; i < N_PAIRS; ++i)
        if ((PAIRS[i].x == x && PAIRS[i].y == y) || (PAIRS[i].x == y && PAIRS[i].y == x)) return &PAIRS[i];
    return NULL;
}

static void test_fixture(void)
{
    fixture f, g;
    gs_db *db = near_fixture(&f, PAIRS, N_PAIRS), *plain = fixture_db(&g, 1);
    if (!db || !plain) return;
    gs_error err = {0};
    gs_db *again = NULL;
    CHECK_MSG(gs_db_open_memory(db->bytes, (size_t)db->size, &again, &err) == GS_OK, "%s", err.message);
    CHECK(gs_db_verify(db, &err) == GS_OK);
    gs_db_info info;
    CHECK(gs_db_get_info(db, &info, &err) == GS_OK);
    CHECK(info.near_radius == RADIUS && info.n_near_pairs == N_PAIRS);
    CHECK(info.near_bytes == gs__db_near_bytes(FX_NV, N_PAIRS) && info.near_bytes == 32 + 8 + 8 * N_PAIRS);
    CHECK(gs_db_get_info(plain, &info, &err) == GS_OK && info.near_radius == 0 && info.n_near_pairs == 0);
    for (uint32_t x = 0; x < FX_NV; ++x)
        for (uint32_t y = 0; y < FX_NV; ++y) {
            double a = gs_db_distance(db, x, y), b = gs_db_distance(plain, x, y), c = gs_db_distance(again, x, y);
            const gs__near_pair *p = x != y ? stored(x, y) : NULL;
            CHECK(memcmp(&a, &c, sizeof a) == 0);
            if (p)
                CHECK_MSG(fabs(a - p->d) <= 0.5 * RADIUS / 65535 + 1e-15, "(%u, %u): %.17g, stored %.17g", x, y, a,
                          p->d);
            else
                CHECK_MSG(memcmp(&a, &b, sizeof a) == 0, "(%u, %u): %.17g without near pairs %.17g", x, y, a, b);
        }
    /* batches and fields answer as single queries */
    uint32_t pairs[] = {0, 2, 2, 0, 4, 2, 1, 2, 0, 1, 3, 5};
    double out[6], field[FX_NV];
    CHECK(gs_db_distances(db, pairs, 6, out, &err) == GS_OK);
    for (int i = 0; i < 6; ++i) CHECK(out[i] == gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]));
    CHECK(gs_db_field(db, 2, field, &err) == GS_OK);
    for (uint32_t y = 0; y < FX_NV; ++y) CHECK(field[y] == gs_db_distance(db, 2, y));
    /* format 5 (no shifts) is read: distances above radius / 2 need none
     * (the same bytes), and (1, 2)'s is refused (test_corruptions) */
    static const gs__near_pair FAR[] = {{0, 2, 0.75}, {2, 4, 0.9}};
    gs_db *db6 = near_fixture(&g, FAR, 2), *old = NULL;
    unsigned char *v5 = db6 ? malloc((size_t)db6->size) : NULL;
    if (v5) {
        memcpy(v5, db6->bytes, (size_t)db6->size);
        v5[GS__H_VERSION] = 5;
        reseal(v5);
        CHECK_MSG(gs_db_open_memory(v5, (size_t)db6->size, &old, &err) == GS_OK, "format 5: %s", err.message);
        CHECK(old && gs_db_get_info(old, &info, &err) == GS_OK && info.format_version == 5);
        for (uint32_t x = 0; old && x < FX_NV; ++x)
            for (uint32_t y = 0; y < FX_NV; ++y) {
                double a = gs_db_distance(db6, x, y), c = gs_db_distance(old, x, y);
                CHECK(memcmp(&a, &c, sizeof a) == 0);
            }
        CHECK(old && gs_db_distance(old, 0, 2) == gs_db_distance(db, 0, 2));
        gs_db_free(old);
        free(v5);
    }
    gs_db_free(db6);
    /* an empty section: answers as without it */
    gs_db *empty = near_fixture(&g, NULL, 0);
    for (uint32_t x = 0; empty && x < FX_NV; ++x)
        for (uint32_t y = 0; y < FX_NV; ++y) {
            double a = gs_db_distance(empty, x, y), b = gs_db_distance(plain, x, y);
            CHECK(memcmp(&a, &b, sizeof a) == 0);
        }
    CHECK(empty && gs_db_verify(empty, &err) == GS_OK);
    gs_db_free(empty);
    gs_db_free(again);
    gs_db_free(plain);
    gs_db_free(db);
}

/* ---- corruptions ---------------------------------------------------------- */

/* the section: head (radius, step, n, bits, 0), start[0..1] (nv 7: one
 * bucket), then entries of 8 bytes: y u32, q u16, xlow u8, 0 */
#define ENT(b, i) (near_sec(b) + 32 + 8 + 8 * (i))
static void m_radius_nan(unsigned char *b) { gs__putf64(near_sec(b), NAN); }
static void m_radius_neg(unsigned char *b) { gs__putf64(near_sec(b), -1.0); }
static void m_step_big(unsigned char *b) { gs__putf64(near_sec(b) + 8, 1.0); }
static void m_n(unsigned char *b) { gs__put64(near_sec(b) + 16, 2); }
static void m_bits(unsigned char *b) { gs__put32(near_sec(b) + 24, 5); }
static void m_reserved(unsigned char *b) { gs__put32(near_sec(b) + 28, 1); }
static void m_start0(unsigned char *b) { gs__put32(near_sec(b) + 32, 1); }
static void m_start_end(unsigned char *b) { gs__put32(near_sec(b) + 36, 2); }
static void m_y_range(unsigned char *b) { gs__put32(ENT(b, 2), FX_NV); }
static void m_x_not_below(unsigned char *b) { gs__put32(ENT(b, 0), 0); } /* (0, 0) */
static void m_dup(unsigned char *b) { memcpy(ENT(b, 1), ENT(b, 0), 8); }  /* (0, 2) twice */
static void m_xlow(unsigned char *b) { ENT(b, 1)[6] = 16; }
static void m_ent_shift(unsigned char *b) { ENT(b, 1)[7] = GS__NEAR_SHIFT_MAX + 1; }
static void m_v5_shift(unsigned char *b) { b[GS__H_VERSION] = 5, ENT(b, 1)[7] = 1; } /* format 5: no shifts */
static void m_size(unsigned char *b) { gs__put64(table_entry(b, GS__SEC_NEAR) + 16, 16); }
static void m_flag_off(unsigned char *b) { gs__put32(b + GS__H_FLAGS, GS__DB_FLAG_LEAF_EXACT); }

static void test_corruptions(void)
{
    fixture f;
    gs_db *db = near_fixture(&f, PAIRS, N_PAIRS);
    if (!db) return;
    size_t n = (size_t)db->size;
    static const struct {
        void (*fn)(unsigned char *b);
        int open; /* refused by the structural open (else by verify only) */
        const char *expect;
    } cases[] = {
        {m_radius_nan, 1, "section 'near_pairs': radius nan"},
        {m_radius_neg, 1, "section 'near_pairs': radius -1"},
        {m_step_big, 1, "step 1 (radius in (0, 1e100]"},
        {m_n, 1, "but 2 entries for 7 vertices need"},
        {m_bits, 1, "bucket bits 5, reserved 0"},
        {m_reserved, 1, "bucket bits 4, reserved 1"},
        {m_start0, 1, "bucket starts run from 1 to 3"},
        {m_start_end, 1, "bucket starts run from 0 to 2"},
        {m_y_range, 0, "entry 2 is the pair (2, 7)"},
        {m_x_not_below, 0, "entry 0 is the pair (0, 0)"},
        {m_dup, 0, "entry 1 (0, 2) is not after the entry before it"},
        {m_xlow, 0, "entry 1 is the pair (16, 2)"},
        {m_ent_shift, 0, "with shift 65"},
        {m_v5_shift, 0, "with shift 1 (needs x < y < 7, shift <= 0 in format 5)"},
        {m_size, 1, "section table: sections end at"},
        {m_flag_off, 1, "n_sections 10 (flags require 9)"},
    };
    unsigned char *b = malloc(n), *copy = malloc(n);
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        memcpy(b, db->bytes, n);
        cases[i].fn(b);
        reseal(b);
        gs_error err = {0};
        gs_db *d = NULL;
        int rc = gs_db_open_memory(b, n, &d, &err);
        CHECK_MSG(rc == GS_EPARSE && d == NULL && strstr(err.message, cases[i].expect),
                  "case %zu: rc %d, message '%s', expected '%s'", i, rc, err.message, cases[i].expect);
        memcpy(copy, b, n);
        rc = gs__db_attach(copy, n, 0, "case", 0, &d, &err);
        CHECK_MSG((rc != GS_OK) == cases[i].open, "case %zu: structural open rc %d (%s)", i, rc,
                  rc ? err.message : "");
        if (rc) continue;
        for (uint32_t x = 0; x <= FX_NV; ++x) /* any answer, never a crash */
            for (uint32_t y = 0; y <= FX_NV; ++y) (void)gs_db_distance(d, x, y);
        CHECK(gs_db_verify(d, &err) == GS_EPARSE && strstr(err.message, cases[i].expect));
        d->storage = NULL; /* copy is reused: not freed by gs_db_free */
        gs_db_free(d);
    }
    /* every single-bit flip: refused (checksums) by a verifying open; by the
     * structural open or else caught by gs_db_verify after safe queries */
    int undetected = 0, missed = 0;
    for (size_t pos = 0; pos < n; ++pos) {
        memcpy(b, db->bytes, n);
        b[pos] ^= (unsigned char)(1u << (pos % 8));
        gs_error err;
        gs_db *d = NULL;
        if (gs_db_open_memory(b, n, &d, &err) == GS_OK) undetected++, gs_db_free(d);
        memcpy(copy, b, n);
        if (gs__db_attach(copy, n, 0, "flip", 0, &d, &err) != GS_OK) continue;
        for (uint32_t x = 0; x <= FX_NV; ++x)
            for (uint32_t y = 0; y <= FX_NV; ++y) (void)gs_db_distance(d, x, y);
        missed += gs_db_verify(d, &err) == GS_OK;
        d->storage = NULL;
        gs_db_free(d);
    }
    CHECK_MSG(undetected == 0 && missed == 0, "flips: %d undetected, %d missed by verify", undetected, missed);
    /* cut inside the section */
    memcpy(b, db->bytes, n);
    uint64_t off = gs__get64(table_entry(b, GS__SEC_NEAR) + 8);
    gs_error err;
    gs_db *d = NULL;
    for (uint64_t len = off; len < n; len += 4) CHECK(gs_db_open_memory(db->bytes, (size_t)len, &d, &err) == GS_EPARSE);
    free(b);
    free(copy);
    gs_db_free(db);
}

/* ---- what the build stores ------------------------------------------------ */

static void test_build(const char *spec, gs_mesh *m)
{
    gs_error err = {0};
    if (!m) return;
    uint32_t n = gs_mesh_num_vertices(m);
    gs_build_options o;
    gs_build_options_default(&o);
    CHECK(o.near_radius == 5);
    gs_db *db = NULL, *db0 = NULL;
    gs_build_stats st;
    CHECK_MSG(gs_db_build(m, &o, &db, &st, &err) == GS_OK, "%s: %s", spec, err.message);
    o.near_radius = 0;
    CHECK_MSG(gs_db_build(m, &o, &db0, NULL, &err) == GS_OK, "%s: %s", spec, err.message);
    double *exact = malloc((size_t)n * sizeof *exact);
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    CHECK(exact && gs_patch_create(m, NULL, 0, &p, &err) == GS_OK &&
          gs_solver_create(p, GS_METHOD_EXACT, &s, &err) == GS_OK);
    gs_db_info info;
    CHECK(db && db0 && gs_db_get_info(db, &info, &err) == GS_OK);
    if (!db || !db0 || !s) goto done;
    gs_db_info i0;
    gs_db_get_info(db0, &i0, &err);
    CHECK(i0.near_radius == 0 && i0.n_near_pairs == 0 && info.n_near_pairs == st.n_near_pairs);
    CHECK(info.file_bytes == i0.file_bytes + GS__DB_ENTRY_BYTES + info.near_bytes);
    gs_mesh_report rep;
    CHECK(gs_mesh_get_report(m, &rep, &err) == GS_OK);
    double R = info.near_radius, R0 = 5 * rep.mean_edge;
    CHECK(R >= R0 * (1 - 1e-12));
    uint64_t found = 0, wide = 0;
    double dmin = INFINITY;
    for (uint32_t x = 0; x < n; ++x) {
        gs_source src = gs_source_vertex(x);
        CHECK(gs_solver_solve(s, &src, 1, 0, exact, &err) == GS_OK);
        for (uint32_t y = x + 1; y < n; ++y) {
            double d = exact[y], a = gs_db_distance(db, x, y), a0 = gs_db_distance(db0, x, y), q;
            int in = gs__db_near_find(&db->near, x, y, &q);
            int cross = db->leaf[x] != db->leaf[y];
            if (in) {
                found++;
                wide += d >= R0; /* beyond the base radius: a widened vertex */
                CHECK_MSG(cross && d < R && fabs(a0 - d) > 0.02 * d, "%s: (%u, %u) stored: d %g, R %g, without %g",
                          spec, x, y, d, R, a0);
                /* 16 significant bits, however much nearer than R */
                CHECK_MSG(fabs(a - d) <= 0x1p-16 * d + 1e-12 * d, "%s: (%u, %u): %.17g, exact %.17g", spec, x, y, a, d);
                dmin = d < dmin ? d : dmin;
            } else {
                CHECK_MSG(memcmp(&a, &a0, sizeof a) == 0, "%s: (%u, %u) not stored, answers differ", spec, x, y);
                /* all within the base radius that needed it are stored */
                CHECK_MSG(!cross || d >= R0 || fabs(a0 - d) <= 0.02 * d, "%s: (%u, %u) d %g < %g off by %.2f%%",
                          spec, x, y, d, R0, 100 * fabs(a0 - d) / d);
            }
        }
    }
    CHECK(found == info.n_near_pairs);
    printf("%s: %llu near pairs stored (%llu beyond the base radius, the nearest %.3g: radius / %.3g), %.2f "
           "bytes/vertex\n",
           spec, (unsigned long long)found, (unsigned long long)wide, dmin, R / dmin, (double)info.near_bytes / n);
    CHECK(found > 0);
done:
    gs_solver_free(s);
    gs_patch_free(p);
    free(exact);
    gs_db_free(db);
    gs_db_free(db0);
    gs_mesh_free(m);
}

/* A height field on the grid x = (i/(n-1))^p, y = (j/(n-1))^p: cells from
 * (1/(n-1))^p to ~p/(n-1) wide (a boundary layer's grading), so that near
 * pairs at the origin are 10^4 to 10^6 times nearer than the radius. */
static gs_mesh *graded(uint32_t n, double p)
{
    double *xyz = malloc(3 * (size_t)n * n * sizeof *xyz);
    uint32_t *tri = malloc(6 * (size_t)(n - 1) * (n - 1) * sizeof *tri), t = 0;
    gs_mesh *m = NULL;
    gs_error err = {0};
    if (!xyz || !tri) goto done;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            double x = pow((double)i / (n - 1), p), y = pow((double)j / (n - 1), p);
            double *v = xyz + 3 * ((size_t)j * n + i);
            v[0] = x, v[1] = y, v[2] = 0.25 * sin(5 * x) * sin(5 * y);
        }
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i) {
            uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(tri + t, q, sizeof q), t += 6;
        }
    CHECK_MSG(gs_mesh_create(xyz, n * n, tri, t / 3, &m, &err) == GS_OK, "graded: %s", err.message);
done:
    free(xyz);
    free(tri);
    return m;
}

int main(void)
{
    test_fixture();
    test_corruptions();
    gs_mesh *m = NULL;
    gs_error err = {0};
    CHECK_MSG(gs_mesh_generate("knot:120,12", &m, &err) == GS_OK, "knot: %s", err.message);
    test_build("knot:120,12", m);
    test_build("graded 24 x 24, p = 5", graded(24, 5.0));
    return gs__test_finish("test_near");
}
