/* test_db.c - the database file (doc/database-format.md, version 6): a
 * hand-made tree and functions packed, saved, re-opened bit-exact; every
 * corruption (flips, truncation, absurd fields with valid checksums)
 * rejected cleanly, by the structural validation at open or by
 * gs_db_verify; an unverified corrupt file is queried without a crash.
 * The fixture (make_fixture) is in tests/util/db_fixture.c, shared with
 * test_query.c. */
#include "check.h"
#include "db/db_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <dirent.h>
#include <unistd.h>

#include "db_fixture.h"


static char tmpdir[1024];

static const char *tmp_path(const char *name)
{
    static char buf[2048];
    snprintf(buf, sizeof buf, "%s/%s", tmpdir, name);
    return buf;
}

static int write_file(const char *path, const void *data, size_t n)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    size_t w = n ? fwrite(data, 1, n, fp) : 0;
    fclose(fp);
    return w == n ? 0 : -1;
}

static unsigned char *read_file(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    fseek(fp, 0, SEEK_END);
    long sz = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *b = malloc(sz > 0 ? (size_t)sz : 1);
    *n = fread(b, 1, (size_t)sz, fp);
    fclose(fp);
    return b;
}

/* Opening must fail with a message; returns the status. */
static int open_bad(const unsigned char *b, size_t n, gs_error *err)
{
    gs_db *db = NULL;
    memset(err, 0, sizeof *err);
    int rc = gs_db_open_memory(b, n, &db, err);
    CHECK(db == NULL || rc == GS_OK);
    if (rc == GS_OK) gs_db_free(db);
    else CHECK(err->message[0] != '\0');
    return rc;
}

static void all_distances(const gs_db *db, double *out)
{
    for (uint32_t x = 0; x < FX_NV; ++x)
        for (uint32_t y = 0; y < FX_NV; ++y) out[x * FX_NV + y] = gs_db_distance(db, x, y);
}

static void test_round_trip(int leaf_exact)
{
    fixture f;
    gs_db *db = fixture_db(&f, leaf_exact);
    if (!db) return;
    gs_error err = {0};
    const char *path = tmp_path("fixture.gsdb");
    CHECK(gs_db_save(db, path, &err) == GS_OK);
    size_t n = 0;
    unsigned char *bytes = read_file(path, &n);
    CHECK(bytes && n == db->size && memcmp(bytes, db->bytes, n) == 0);
    {   /* the file image without a file: what gs_db_save wrote */
        size_t m = 0;
        const void *img = gs_db_file_bytes(db, &m);
        CHECK(img && bytes && m == n && memcmp(img, bytes, n) == 0);
        CHECK(gs_db_file_bytes(db, NULL) == img);
        CHECK(gs_db_file_bytes(NULL, &m) == NULL && m == 0);
    }
    gs_db *db2 = NULL, *db3 = NULL;
    CHECK_MSG(gs_db_open(path, &db2, &err) == GS_OK, "%s", err.message);
    CHECK(gs_db_open_memory(bytes, n, &db3, &err) == GS_OK);
    if (db2 && db3) {
        CHECK(db2->mapped && !db3->mapped);
        double a[FX_NV * FX_NV], b[FX_NV * FX_NV], c[FX_NV * FX_NV];
        all_distances(db, a);
        all_distances(db2, b);
        all_distances(db3, c);
        CHECK(memcmp(a, b, sizeof a) == 0 && memcmp(a, c, sizeof a) == 0);
        gs_db_info i1, i2;
        CHECK(gs_db_get_info(db, &i1, NULL) == GS_OK && gs_db_get_info(db2, &i2, NULL) == GS_OK);
        CHECK(memcmp(&i1, &i2, sizeof i1) == 0);
        CHECK(i1.n_vertices == FX_NV && i1.n_nodes == 5 && i1.n_leaves == 3 && i1.n_curves == 3);
        CHECK(i1.max_depth == 2 && i1.vmax == 2 && i1.mmax == 12 && i1.tol == 0.005 && i1.vertex_sources == 1);
        CHECK(i1.leaf_exact == leaf_exact && i1.sampled == 0 && i1.file_bytes == n && i1.format_version == 6);
        CHECK(i1.n_functions == 14 && i1.records_bytes > 0 && i1.records_bytes < n);
        CHECK(i1.sample_spacing == 0.25 && i1.seed == 7 && i1.max_samples == 64 && i1.solver.heat_time == 0.5 &&
              i1.solver.fmm_exact_start == 3 && i1.solver.heat_refine == 2 && i1.solver.dgg_eps == 0);
        /* 14 functions: 12 reachable with 3 coefficients, 4 of them loops */
        CHECK_NEAR(i1.cost, (12.0 * 3 + 4 /* loop shifts */) / FX_NV, 1e-12); /* Table 1: coefficients and shifts */
        /* saving a loaded database writes the same bytes */
        CHECK(gs_db_save(db2, tmp_path("again.gsdb"), &err) == GS_OK);
        size_t n2 = 0;
        unsigned char *b2 = read_file(tmp_path("again.gsdb"), &n2);
        CHECK(b2 && n2 == n && memcmp(b2, bytes, n) == 0);
        free(b2);
        /* verify: the function, the open flag */
        gs_db *db4 = NULL;
        CHECK(gs_db_verify(db2, &err) == GS_OK && gs_db_verify(db, &err) == GS_OK);
        CHECK(gs_db_open_ex(path, GS_DB_OPEN_VERIFY, &db4, &err) == GS_OK && db4);
        gs_db_free(db4);
        CHECK(gs_db_open_ex(path, 2, &db4, &err) == GS_EARG && db4 == NULL && strstr(err.message, "unknown flags"));
        CHECK(gs_db_verify(NULL, &err) == GS_EARG);
    }
    gs_db_free(db2);
    gs_db_free(db3);
    free(bytes);
    gs_db_free(db);
}

/* Every single-byte change of the file is detected (checksums cover every
 * byte); plus random flips of random bits. */
static void test_flips(void)
{
    fixture f;
    gs_db *db = fixture_db_full(&f);
    if (!db) return;
    size_t n = (size_t)db->size;
    unsigned char *b = malloc(n);
    gs_error err;
    int undetected = 0;
    for (size_t pos = 0; pos < n; ++pos) {
        memcpy(b, db->bytes, n);
        b[pos] ^= 0x01;
        if (open_bad(b, n, &err) == GS_OK) undetected++;
    }
    CHECK_MSG(undetected == 0, "%d of %zu single-bit flips undetected", undetected, n);
    /* the same flips through a file opened without verify: refused by the
     * structure, or accepted, then queried safely and caught by
     * gs_db_verify */
    int accepted = 0, missed = 0;
    for (size_t pos = 0; pos < n; pos += 3) {
        memcpy(b, db->bytes, n);
        b[pos] ^= 0x10;
        CHECK(write_file(tmp_path("flip.gsdb"), b, n) == 0);
        gs_db *d = NULL;
        if (gs_db_open(tmp_path("flip.gsdb"), &d, &err) != GS_OK) continue;
        accepted++;
        for (uint32_t x = 0; x < FX_NV; ++x)
            for (uint32_t y = 0; y < FX_NV; ++y) (void)gs_db_distance(d, x, y);
        missed += gs_db_verify(d, &err) != GS_EPARSE;
        gs_db_free(d);
    }
    CHECK_MSG(missed == 0, "%d of %d flips accepted at open missed by gs_db_verify", missed, accepted);
    printf("bit flips: %d of %zu accepted by the structural open, all caught by gs_db_verify\n", accepted, (n + 2) / 3);
    srand(12345);
    int bad_status = 0;
    for (int seed = 0; seed < 500; ++seed) {
        memcpy(b, db->bytes, n);
        size_t pos = (size_t)rand() % n;
        b[pos] ^= (unsigned char)(1 + rand() % 255);
        int rc = open_bad(b, n, &err);
        if (rc != GS_EPARSE && rc != GS_EFORMAT) bad_status++;
    }
    CHECK(bad_status == 0);
    free(b);
    gs_db_free(db);
}

static void test_truncation(void)
{
    fixture f;
    gs_db *db = fixture_db_full(&f);
    if (!db) return;
    size_t n = (size_t)db->size;
    gs_error err;
    int accepted = 0;
    for (size_t len = 0; len < n; ++len) /* every length, in memory */
        if (open_bad(db->bytes, len, &err) != GS_EPARSE) accepted++;
    CHECK(accepted == 0);
    unsigned char *ext = calloc(n + 8, 1); /* an extended file too */
    memcpy(ext, db->bytes, n);
    CHECK(open_bad(ext, n + 8, &err) == GS_EPARSE && strstr(err.message, "file_bytes"));
    free(ext);
    /* files cut at every section boundary (and inside each section) */
    const unsigned char *t = db->bytes + GS__DB_HEADER_BYTES;
    uint32_t n_sec;
    memcpy(&n_sec, db->bytes + 64, 4);
    CHECK(n_sec == GS__SEC_MAX - 1); /* every section but near pairs (test_near.c): leaf tables and aliases */
    for (uint32_t s = 0; s < n_sec; ++s, t += GS__DB_ENTRY_BYTES) {
        uint64_t off, size;
        memcpy(&off, t + 8, 8);
        memcpy(&size, t + 16, 8);
        uint64_t cuts[2] = {off, off + size / 2};
        for (int j = 0; j < 2; ++j) {
            CHECK(write_file(tmp_path("cut.gsdb"), db->bytes, (size_t)cuts[j]) == 0);
            gs_db *d = NULL;
            CHECK(gs_db_open(tmp_path("cut.gsdb"), &d, &err) == GS_EPARSE && d == NULL);
        }
    }
    CHECK(write_file(tmp_path("empty.gsdb"), "", 0) == 0);
    gs_db *d = NULL;
    CHECK(gs_db_open(tmp_path("empty.gsdb"), &d, &err) == GS_EPARSE && strstr(err.message, "0 bytes"));
    gs_db_free(db);
}

/* Recompute every checksum, so that only structural validation can object. */
static void reseal(unsigned char *b, size_t n)
{
    uint32_t n_sec;
    memcpy(&n_sec, b + 64, 4);
    if (n_sec > GS__SEC_MAX) return; /* a mutated count: leave it */
    for (uint32_t s = 0; s < n_sec; ++s) {
        unsigned char *t = b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * s;
        uint64_t off, size;
        memcpy(&off, t + 8, 8);
        memcpy(&size, t + 16, 8);
        if (off > n || size > n - off) continue; /* a mutated table */
        uint64_t h = gs__db_checksum(b + off, (size_t)size, NULL, 0);
        memcpy(t + 24, &h, 8);
    }
    uint64_t h = gs__db_checksum(b, GS__DB_CHECKSUM_AT, b + GS__DB_HEADER_BYTES, GS__DB_ENTRY_BYTES * n_sec);
    memcpy(b + GS__DB_CHECKSUM_AT, &h, 8);
}

/* Section `id` (looked up in the table: the optional ones may be absent). */
static unsigned char *section(unsigned char *b, uint32_t id)
{
    uint32_t n_sec;
    memcpy(&n_sec, b + 64, 4);
    for (uint32_t e = 0; e < n_sec && e < GS__SEC_MAX; ++e) {
        uint32_t sid;
        uint64_t off;
        memcpy(&sid, b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * e, 4);
        memcpy(&off, b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * e + 8, 8);
        if (sid == id) return b + off;
    }
    return NULL;
}

/* Vertex x's record (its minima first), and its first block. */
static unsigned char *record(unsigned char *b, uint32_t x)
{
    uint32_t ix;
    memcpy(&ix, section(b, GS__SEC_INDEX) + 4 * x, 4);
    return section(b, GS__SEC_RECORDS) + GS__DB_RECORD_UNIT * (uint64_t)ix;
}
static unsigned char *first_block(unsigned char *b, uint32_t x, uint32_t nf)
{
    return record(b, x) + GS__DB_MIN_BYTES * nf;
}

typedef void (*mutation)(unsigned char *b);

static void m_parent_self(unsigned char *b) { uint32_t v = 2; memcpy(section(b, GS__SEC_NODES) + 20 * 2, &v, 4); }
static void m_depth(unsigned char *b) { uint32_t v = 7; memcpy(section(b, GS__SEC_NODES) + 20 * 3 + 4, &v, 4); }
static void m_prefix(unsigned char *b) { uint32_t v = 2; memcpy(section(b, GS__SEC_NODES) + 20 * 2 + 16, &v, 4); }
static void m_curve_range(unsigned char *b) { uint32_t v = 1000; memcpy(section(b, GS__SEC_NODES) + 20 * 2 + 12, &v, 4); }
static void m_curve_node(unsigned char *b) { uint32_t v = 0; memcpy(section(b, GS__SEC_CURVES) + 24 * 2, &v, 4); }
static void m_curve_closed(unsigned char *b) { uint32_t v = 1; memcpy(section(b, GS__SEC_CURVES) + 24 * 2 + 4, &v, 4); }
static void m_grid(unsigned char *b) { uint32_t v = 26; memcpy(section(b, GS__SEC_CURVES) + 12, &v, 4); }
static void m_degree1(unsigned char *b) { uint32_t v = 2; memcpy(section(b, GS__SEC_CURVES) + 12, &v, 4); }
static void m_leaf_internal(unsigned char *b) { uint32_t v = 2; memcpy(section(b, GS__SEC_LEAVES) + 4 * 4, &v, 4); }
static void m_leaf_range(unsigned char *b) { uint32_t v = 99; memcpy(section(b, GS__SEC_LEAVES) + 4 * 0, &v, 4); }
/* vertex 1 moves to leaf 3: it would need 3 minima, its record holds 1 */
static void m_leaf_count(unsigned char *b) { uint32_t v = 3; memcpy(section(b, GS__SEC_LEAVES) + 4 * 1, &v, 4); }
/* vertex 2 moves from leaf 3 to leaf 4 (the same ancestors: its record fits) */
static void m_leaf_moved(unsigned char *b) { uint32_t v = 4; memcpy(section(b, GS__SEC_LEAVES) + 4 * 2, &v, 4); }
/* vertex 2 (leaf 3: 3 functions, curves 0, 1 loop, 2) */
static void m_degree(unsigned char *b) { first_block(b, 2, 3)[0] = (first_block(b, 2, 3)[0] & ~0x1Fu) | 27u; }
static void m_exponent(unsigned char *b) { first_block(b, 2, 3)[1] = 125; }
static void m_closed_bit(unsigned char *b) { first_block(b, 2, 3)[0] |= GS__FB_CLOSED; }
static void m_minval_nan(unsigned char *b) { uint16_t v = 0xFFFF; memcpy(record(b, 2) + 2, &v, 2); }
static void m_minval_above(unsigned char *b) { uint16_t v = gs__db_min_encode(50.0); memcpy(record(b, 0), &v, 2); }
static void m_index_past(unsigned char *b) { uint32_t v = 1u << 30; memcpy(section(b, GS__SEC_INDEX) + 4 * 3, &v, 4); }
static void m_index_first(unsigned char *b) { uint32_t v = 1; memcpy(section(b, GS__SEC_INDEX), &v, 4); }
/* the first padding byte after a record's blocks (a record of odd length) */
static void m_record_pad(unsigned char *b)
{
    for (uint32_t x = 0; x < FX_NV; ++x) {
        uint32_t l, nf, i0, i1;
        memcpy(&l, section(b, GS__SEC_LEAVES) + 4 * x, 4);
        if (l == GS_NONE) continue;
        memcpy(&nf, section(b, GS__SEC_NODES) + 20 * (uint64_t)l + 16, 4);
        memcpy(&i0, section(b, GS__SEC_INDEX) + 4 * x, 4);
        memcpy(&i1, section(b, GS__SEC_INDEX) + 4 * (x + 1), 4);
        unsigned char *q = first_block(b, x, nf), *end = section(b, GS__SEC_RECORDS) + GS__DB_RECORD_UNIT * (uint64_t)i1;
        for (uint32_t k = 0; k < nf; ++k) {
            gs__db_fblock bl;
            if (gs__db_min_get(record(b, x), k) == INFINITY) continue;
            if (!gs__db_fblock_parse(q, (uint64_t)(end - q), &bl)) return;
            q += bl.bytes;
        }
        if (q < end) {
            *q = 7;
            return;
        }
        (void)i0;
    }
}
static void m_nv(unsigned char *b) { uint32_t v = 0x7FFFFFFF; memcpy(b + 32, &v, 4); }
static void m_nfun(unsigned char *b) { uint64_t v = 5; memcpy(b + 48, &v, 8); }
static void m_records_bytes(unsigned char *b) { uint64_t v = (uint64_t)1 << 61; memcpy(b + 56, &v, 8); }
static void m_offset(unsigned char *b) { uint64_t v = 1u << 20; memcpy(b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * 6 + 8, &v, 8); }
static void m_size(unsigned char *b) { uint64_t v = 8; memcpy(b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * 0 + 16, &v, 8); }
static void m_n_leaves(unsigned char *b) { uint32_t v = 4; memcpy(b + 44, &v, 4); }
static void m_flags(unsigned char *b) { uint32_t v = 16 | 7; memcpy(b + 16, &v, 4); }
static void m_flags16(unsigned char *b) { uint32_t v = 2 | 4; memcpy(b + 16, &v, 4); }
static void m_dgg_eps(unsigned char *b) { double v = 0.1; memcpy(b + 152, &v, 8); }
static void m_dgg_eps_dgg(unsigned char *b) { uint32_t m = GS_METHOD_DGG; memcpy(b + 80, &m, 4); }
static void m_n_input(unsigned char *b) { uint32_t v = 8; memcpy(b + 160, &v, 4); }
static void m_alias_order(unsigned char *b) { uint32_t v = 1; memcpy(section(b, GS__SEC_ALIAS_INDEX) + 8, &v, 4); }
static void m_alias_empty(unsigned char *b) { uint32_t v = 0; memcpy(section(b, GS__SEC_ALIAS_INDEX) + 12, &v, 4); }
static void m_alias_range(unsigned char *b) { uint32_t v = 99; memcpy(section(b, GS__SEC_ALIAS_LIST) + 4, &v, 4); }
static void m_alias_sentinel(unsigned char *b) { uint32_t v = 6; memcpy(section(b, GS__SEC_ALIAS_INDEX) + 8 * 3, &v, 4); }
static void m_alias_pad(unsigned char *b) { section(b, GS__SEC_ALIAS_LIST)[20] = 1; }
static void m_avg_depth(unsigned char *b) { double v = NAN; memcpy(b + 72, &v, 8); }
static void m_method(unsigned char *b) { uint32_t v = 9; memcpy(b + 80, &v, 4); }
static void m_spacing(unsigned char *b) { double v = 0; memcpy(b + 120, &v, 8); }
static void m_heat_time(unsigned char *b) { double v = -1; memcpy(b + 136, &v, 8); }
static void m_heat_time_big(unsigned char *b) { double v = 1e9; memcpy(b + 136, &v, 8); }
static void m_build_flags(unsigned char *b) { uint32_t v = 1 | 2u << 2 | 1u << 4; memcpy(b + 92, &v, 4); }
static void m_fmm_start(unsigned char *b) { double v = INFINITY; memcpy(b + 144, &v, 8); }
static void m_pos_nan(unsigned char *b) { double v = NAN; memcpy(section(b, GS__SEC_POSITIONS) + 8, &v, 8); }
/* leaf tables (fixture: nodes 1, 3, 4 hold 2 vertices, one entry each) */
static unsigned char *leaf_node(unsigned char *b, uint32_t l) { return section(b, GS__SEC_LEAF_NODES) + 16 * l; }
static void m_leaf_scale(unsigned char *b) { float v = 1e31f; memcpy(leaf_node(b, 1) + 12, &v, 4); }
static void m_leaf_scale_nan(unsigned char *b) { float v = NAN; memcpy(leaf_node(b, 3) + 12, &v, 4); }
static void m_leaf_internal_scale(unsigned char *b) { float v = 1; memcpy(leaf_node(b, 0) + 12, &v, 4); }
static void m_leaf_local(unsigned char *b) { section(b, GS__SEC_LEAF_LOCAL)[1] = 0; }
static void m_leaf_local_range(unsigned char *b) { section(b, GS__SEC_LEAF_LOCAL)[4] = 2; }
static void m_leaf_unref(unsigned char *b) { section(b, GS__SEC_LEAF_LOCAL)[6] = 1; }
static void m_leaf_qstart(unsigned char *b) { uint64_t v = 5; memcpy(leaf_node(b, 3), &v, 8); }
static void m_leaf_n(unsigned char *b) { uint32_t v = 3; memcpy(leaf_node(b, 4) + 8, &v, 4); }
static void m_leaf_n_big(unsigned char *b) { uint32_t v = 257; memcpy(leaf_node(b, 4) + 8, &v, 4); }
static void m_leaf_q_top(unsigned char *b) { uint16_t v = 100; memcpy(section(b, GS__SEC_LEAF_Q), &v, 2); }
static void m_leaf_q_pad(unsigned char *b) { section(b, GS__SEC_LEAF_Q)[6] = 1; }
static void m_padding(unsigned char *b) { section(b, GS__SEC_LEAVES)[4 * FX_NV] = 1; }

static void test_structure(void)
{
    /* open: 1 when the structural validation at open refuses it, 0 when
     * only gs_db_verify does (a value) */
    static const struct {
        mutation fn;
        int open;
        const char *expect;
    } cases[] = {
        {m_parent_self, 1, "node 2 has parent 2 (must be < its own index)"},
        {m_depth, 1, "node 3 has depth 7"},
        {m_prefix, 1, "node 2 has curve_prefix 2"},
        {m_curve_range, 1, "past n_curves"},
        {m_curve_node, 1, "curve 2 is in node 2's range but names node 0"},
        {m_curve_closed, 0, "vertex 2, function 2: closed 0 (curve 1)"},
        {m_grid, 1, "curve 0 has closed 0, n_samples 50, degree1 26"},
        {m_degree1, 0, "vertex 0, function 0: degree 2, its curve's degree1 2"},
        {m_leaf_internal, 1, "vertex 4 has leaf 2, which is not a leaf node"},
        {m_leaf_range, 1, "vertex 0 has leaf 99"},
        {m_leaf_count, 0, "n_functions 14 but the vertices have 16"},
        {m_leaf_moved, 0, "section 'leaf_nodes': node 3 has a table of 2 vertices, 1 vertices are in it"},
        {m_degree, 0, "vertex 2, function 0: malformed block"},
        {m_exponent, 0, "vertex 2, function 0: closed 0 (curve 0), sampled 0 (build 0), exponent 125"},
        {m_closed_bit, 0, "vertex 2, function 0: malformed block"},
        {m_minval_nan, 0, "vertex 2, function 1: minimum nan"},
        {m_minval_above, 0, "vertex 0, function 0: minimum 50 is above the function's value"},
        {m_index_past, 1, "section 'vertex_index': vertex 3's record"},
        {m_index_first, 1, "section 'vertex_index': entry 0 is 1"},
        {m_record_pad, 0, "padding is not zero"},
        {m_nv, 1, "section 'positions': size"},
        {m_nfun, 0, "n_functions 5 but the vertices have 14"},
        {m_records_bytes, 1, "records_bytes 2305843009213693952"},
        {m_offset, 1, "section 'leaf_nodes': offset"},
        {m_size, 1, "section 'positions': size 8"},
        {m_n_leaves, 1, "n_leaves 4 but the tree has 3"},
        {m_flags, 1, "flags 0x17 has unknown bits"},
        {m_flags16, 1, "flags 0x6: 16-bit leaf numbers without leaf tables"},
        {m_dgg_eps, 1, "dgg_eps 0.1 (method exact: must be 0)"},
        {m_dgg_eps_dgg, 1, "dgg_eps 0 (method dgg: must be in [1e-05, 0.5])"},
        {m_n_input, 1, "header: n_input 8, alias_exceptions 3, alias_entries 5"},
        {m_alias_order, 1, "section 'alias_index': entry 1 names input vertex 1 (increasing"},
        {m_alias_empty, 1, "section 'alias_index': input vertex 1's list [0, 0) is empty"},
        {m_alias_range, 1, "section 'alias_list': entry 1 is vertex 99 (n_vertices 7)"},
        {m_alias_sentinel, 1, "section 'alias_index': sentinel {6, 5}"},
        {m_alias_pad, 1, "section 'alias_list': padding byte 20"},
        {m_avg_depth, 1, "avg_depth"},
        {m_method, 1, "method 9 unknown"},
        {m_spacing, 1, "sample_spacing 0"},
        {m_heat_time, 1, "heat_time -1 not in [1e-08, 1e+08]"},
        {m_heat_time_big, 1, "heat_time 1e+09 not in [1e-08, 1e+08]"},
        {m_fmm_start, 1, "fmm_exact_start inf"},
        {m_build_flags, 1, "build_flags 0x19 has unknown bits"},
        {m_pos_nan, 0, "vertex 0 has a non-finite coordinate"},
        {m_leaf_scale, 0, "section 'leaf_nodes': node 1 (2 vertices) has scale 1e+31"},
        {m_leaf_scale_nan, 0, "section 'leaf_nodes': node 3 (2 vertices) has scale nan"},
        {m_leaf_internal_scale, 0, "section 'leaf_nodes': node 0 (0 vertices) has scale 1"},
        {m_leaf_local, 0, "vertex 1 has number 0 in leaf 1, taken by another vertex"},
        {m_leaf_local_range, 1, "vertex 4 has number 2 in leaf 4 (2 vertices)"},
        {m_leaf_unref, 1, "unreferenced vertex 6 has number 1"},
        {m_leaf_qstart, 1, "section 'leaf_nodes': node 3's table starts at entry 5 (expected 1)"},
        {m_leaf_n, 1, "section 'leaf_nodes': the tables hold 5 entries, header leaf_entries 3"},
        {m_leaf_n_big, 1, "section 'leaf_nodes': node 4 has a table of 257 vertices (at most 256)"},
        {m_leaf_q_top, 0, "section 'leaf_q': node 1's largest finite entry is 100"},
        {m_leaf_q_pad, 1, "section 'leaf_q': padding byte 6"},
        {m_padding, 1, "padding byte"},
    };
    fixture f;
    gs_db *db = fixture_db_full(&f);
    if (!db) return;
    size_t n = (size_t)db->size;
    unsigned char *b = malloc(n);
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        memcpy(b, db->bytes, n);
        cases[i].fn(b);
        reseal(b, n);
        gs_error err;
        int rc = open_bad(b, n, &err);
        CHECK_MSG(rc == GS_EPARSE && strstr(err.message, cases[i].expect), "case %zu: rc %d, message '%s', expected '%s'",
                  i, rc, err.message, cases[i].expect);
        /* the structural open alone (no checksums, no values) */
        unsigned char *copy = malloc(n);
        memcpy(copy, b, n);
        gs_db *d = NULL;
        rc = gs__db_attach(copy, n, 0, "case", 0, &d, &err);
        CHECK_MSG((rc != GS_OK) == cases[i].open, "case %zu: structural open rc %d (%s)", i, rc, rc ? err.message : "");
        if (rc) {
            free(copy);
            continue;
        }
        for (uint32_t x = 0; x <= FX_NV; ++x) /* answers: any number (or NaN), never a crash */
            for (uint32_t y = 0; y <= FX_NV; ++y) (void)gs_db_distance(d, x, y);
        CHECK(gs_db_verify(d, &err) == GS_EPARSE && strstr(err.message, cases[i].expect));
        gs_db_free(d);
    }
    /* magic and version */
    gs_error err;
    memcpy(b, db->bytes, n);
    b[0] = 'X';
    CHECK(open_bad(b, n, &err) == GS_EPARSE && strstr(err.message, "bad magic"));
    memcpy(b, db->bytes, n);
    b[8] = 3; /* version 3 (f64 leaf tables, no aliases) is not read */
    reseal(b, n);
    CHECK(open_bad(b, n, &err) == GS_EFORMAT &&
          strstr(err.message, "format_version 3; this geosep reads versions 5 to 6") &&
          strstr(err.message, "rebuild it with geosep build"));
    memcpy(b, db->bytes, n);
    b[8] = 4; /* version 4 (float minima, 16-bit coefficients, records in 8-byte units) is not read */
    reseal(b, n);
    CHECK(open_bad(b, n, &err) == GS_EFORMAT &&
          strstr(err.message, "format_version 4; this geosep reads versions 5 to 6") &&
          strstr(err.message, "rebuild it with geosep build"));
    memcpy(b, db->bytes, n);
    b[8] = 2;
    CHECK(open_bad(b, n, &err) == GS_EFORMAT && strstr(err.message, "format_version 2") && strstr(err.message, "rebuild"));
    memcpy(b, db->bytes, n);
    b[8] = 7;
    reseal(b, n);
    CHECK(open_bad(b, n, &err) == GS_EFORMAT && strstr(err.message, "format_version 7") && strstr(err.message, "newer"));
    /* files written before heat_refine have bits 2-3 of build_flags 0: read
     * as heat_refine 0 */
    memcpy(b, db->bytes, n);
    uint32_t bf = 1;
    memcpy(b + 92, &bf, 4);
    reseal(b, n);
    gs_db *old = NULL;
    gs_db_info info;
    CHECK(gs_db_open_memory(b, n, &old, &err) == GS_OK);
    CHECK(old && gs_db_get_info(old, &info, &err) == GS_OK && info.solver.heat_refine == 0 &&
          info.vertex_sources == 1 && info.sampled == 0);
    gs_db_free(old);
    /* a value that does not fit the two bits is refused by the writer */
    f.c.heat_refine = 4;
    CHECK(gs__db_pack(&f.c, &old, &err) == GS_EARG && old == NULL && strstr(err.message, "heat_refine 4"));
    f.c.heat_refine = 2;
    free(b);
    gs_db_free(db);
}

/* Coefficients as large as 1e25 (float32 blocks) are stored
 * and answered with distances (>= 0 or +inf), symmetric; coefficients that
 * need float32 blocks beyond 1e30 (minimum 0: a 16-bit block would lose
 * the function near it) are refused by the writer. */
static void test_huge_coefficients(void)
{
    static const double mags[2] = {1e25, 1e31};
    for (int t = 0; t < 2; ++t) {
        fixture f;
        make_fixture(&f, 0);
        double big[3][GS_FUN_MAX_DEGREE + 1];
        for (uint32_t i = 0; i < 3; ++i) { /* vertex 2's functions (curves 0, 1, 2), degree 24 */
            gs__fun *g = &f.funs[f.fun_start[2] + i];
            for (uint32_t k = 0; k <= GS_FUN_MAX_DEGREE; ++k) big[i][k] = (k % 3 == 0 ? 1 : -1) * mags[t];
            big[i][0] = 30 * mags[t];
            g->degree = GS_FUN_MAX_DEGREE;
            g->coef = big[i];
            g->squared = i == 2;
            g->minval = t ? 0.0 : mags[t];
        }
        gs_db *db = NULL;
        gs_error err = {0};
        int rc = gs__db_pack(&f.c, &db, &err);
        if (t == 1) {
            CHECK_MSG(rc == GS_ELIMIT && db == NULL && strstr(err.message, "exceed 1e30"), "rc %d: %s", rc, err.message);
            continue;
        }
        CHECK_MSG(rc == GS_OK, "%s", err.message);
        if (!db) continue;
        CHECK(gs_db_verify(db, &err) == GS_OK);
        int bad = 0;
        for (uint32_t x = 0; x < FX_NV; ++x)
            for (uint32_t y = 0; y < FX_NV; ++y) {
                double d = gs_db_distance(db, x, y);
                bad += !(d >= 0) || d != gs_db_distance(db, y, x);
            }
        CHECK_MSG(bad == 0, "%d pairs answered NaN, negative or asymmetric", bad);
        gs_db_free(db);
    }
}

/* Random bytes changed anywhere with the checksums recomputed: whatever the
 * reader accepts must be safe to query (the sanitizers watch). */
static void test_random_structural(void)
{
    fixture f;
    gs_db *db = fixture_db_full(&f);
    if (!db) return;
    size_t n = (size_t)db->size;
    unsigned char *b = malloc(n);
    double field[FX_NV];
    int accepted = 0;
    srand(777);
    for (int seed = 0; seed < 3000; ++seed) {
        memcpy(b, db->bytes, n);
        for (int k = 1 + rand() % 4; k > 0; --k) b[(size_t)rand() % n] = (unsigned char)rand();
        reseal(b, n);
        gs_db *d = NULL;
        gs_error err;
        unsigned char *copy = malloc(n);
        memcpy(copy, b, n);
        if (gs__db_attach(copy, n, 0, "random", 0, &d, &err) == GS_OK) { /* structure only: any answer, no crash */
            for (uint32_t x = 0; x <= FX_NV; ++x) {
                for (uint32_t y = 0; y <= FX_NV; ++y) (void)gs_db_distance(d, x, y);
                (void)gs_db_field(d, x, field, NULL);
            }
            gs_db_free(d);
        } else {
            free(copy);
        }
        d = NULL;
        if (gs_db_open_memory(b, n, &d, &err) != GS_OK) continue;
        accepted++;
        for (uint32_t x = 0; x <= FX_NV; ++x) {
            for (uint32_t y = 0; y <= FX_NV; ++y) {
                double v = gs_db_distance(d, x, y);
                CHECK((x < FX_NV && y < FX_NV) ? !isnan(v) && v >= 0 : isnan(v));
            }
            CHECK(gs_db_field(d, x, field, NULL) == (x < FX_NV ? GS_OK : GS_EARG));
        }
        gs_db_free(d);
    }
    printf("random structural mutations: %d of 3000 accepted (harmless values) and queried\n", accepted);
    free(b);
    gs_db_free(db);
}

/* A leaf table may hold any symmetric non-negative values (the reader
 * cannot know the geodesics): a same-leaf answer is still never below the
 * straight segment, like a cross-leaf one (0 between two distinct points
 * would be a lie). */
static void test_leaf_floor(void)
{
    fixture f;
    make_fixture(&f, 1);
    f.leaf_dist[4 + 1] = f.leaf_dist[4 + 2] = 0.0; /* leaf 1: vertices 2 and 3 */
    gs_db *db = NULL;
    gs_error err = {0};
    CHECK_MSG(gs__db_pack(&f.c, &db, &err) == GS_OK, "pack: %s", err.message);
    if (!db) return;
    double dx = f.xyz[6] - f.xyz[9], dy = f.xyz[7] - f.xyz[10], dz = f.xyz[8] - f.xyz[11];
    double e = sqrt(dx * dx + dy * dy + dz * dz), d = gs_db_distance(db, 2, 3), out[FX_NV];
    CHECK_MSG(e > 0 && d == e && gs_db_distance(db, 3, 2) == e, "d(2,3) %g, Euclidean %g", d, e);
    CHECK(gs_db_field(db, 2, out, &err) == GS_OK && out[3] == e && out[2] == 0.0);
    /* leaf 0 unchanged: 1.25 x Euclidean (its largest: the float scale) */
    CHECK(fabs(gs_db_distance(db, 0, 1) - f.leaf_dist[1]) <= 1e-7 * f.leaf_dist[1]);
    gs_db_free(db);
}

/* A minimum above the function's own values would make the quick reject
 * skip that curve and lengthen answers silently: the writer stores the
 * lower of the given minimum and the stored function's own, so a minval
 * given too high is lowered (verify agrees); one raised in the file is
 * refused by gs_db_verify (test_structure, m_minval_above). */
static void test_minval_above(void)
{
    fixture f;
    make_fixture(&f, 0);
    uint32_t x = 0;
    while (x < FX_NV && f.fun_start[x + 1] == f.fun_start[x]) ++x;
    if (x == FX_NV) return;
    uint64_t i = f.fun_start[x];
    gs_db *db = NULL;
    gs_error err = {0};
    double truth = f.funs[i].minval;
    f.funs[i].minval = 1.0 + 2.0 * gs__fun_value(&f.funs[i], 0.0);
    CHECK_MSG(gs__db_pack(&f.c, &db, &err) == GS_OK, "pack: %s", err.message);
    if (!db) return;
    CHECK(gs_db_verify(db, &err) == GS_OK);
    const unsigned char *end, *r = gs__db_record(db, x, &end);
    float stored = gs__db_min_get(r, 0); /* 8 mantissa bits, rounded down */
    CHECK_MSG(stored <= truth && stored > truth * (1 - 1.0 / 128), "stored minimum %.9g, the function's %.9g", stored,
              truth);
    gs_db_free(db);
}

static void test_files(void)
{
    gs_db *db = NULL;
    gs_error err;
    CHECK(gs_db_open(tmpdir, &db, &err) == GS_EIO && db == NULL && strstr(err.message, "not a regular file"));
    CHECK(gs_db_open(tmp_path("missing.gsdb"), &db, &err) == GS_EIO && strstr(err.message, "cannot open"));
    CHECK(gs_db_open(NULL, &db, &err) == GS_EARG);
    CHECK(gs_db_open_memory(NULL, 0, &db, &err) == GS_EARG);
    fixture f;
    gs_db *good = fixture_db(&f, 0);
    if (!good) return;
    /* a failed save leaves nothing: a missing folder, a path that is a folder */
    CHECK(gs_db_save(good, tmp_path("no/such/dir/x.gsdb"), &err) == GS_EIO);
    const char *sub = tmp_path("sub");
    char subdir[2048];
    snprintf(subdir, sizeof subdir, "%s", sub);
    mkdir(subdir, 0755);
    char target[2100];
    snprintf(target, sizeof target, "%s/isdir", subdir);
    mkdir(target, 0755);
    CHECK(gs_db_save(good, target, &err) == GS_EIO && strstr(err.message, "not a regular file"));
    /* a device or a pipe is never replaced by the rename (as root, saving
     * to /dev/full once turned it into a regular file) */
    char fifo[2100];
    snprintf(fifo, sizeof fifo, "%s/pipe", subdir);
    struct stat st;
    if (mkfifo(fifo, 0644) == 0) {
        CHECK(gs_db_save(good, fifo, &err) == GS_EIO && strstr(err.message, "not a regular file"));
        CHECK(stat(fifo, &st) == 0 && S_ISFIFO(st.st_mode));
        unlink(fifo);
    }

    if (geteuid() != 0) { /* root ignores permissions */
        char ro[2100];
        snprintf(ro, sizeof ro, "%s/ro", subdir);
        mkdir(ro, 0555);
        char p[2200];
        snprintf(p, sizeof p, "%s/x.gsdb", ro);
        CHECK(gs_db_save(good, p, &err) == GS_EIO);
        CHECK(access(p, F_OK) != 0);
        rmdir(ro);
    }
    int entries = 0;
    DIR *d = opendir(subdir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (e->d_name[0] != '.') entries++;
    if (d) closedir(d);
    CHECK_MSG(entries == 1, "%d entries left in %s (expected only 'isdir')", entries, subdir);
    rmdir(target);
    rmdir(subdir);
    gs_db_free(good);
}

static void test_checksum_speed(void)
{
    size_t n = 100u << 20;
    unsigned char *b = malloc(n);
    if (!b) return;
    for (size_t i = 0; i < n; ++i) b[i] = (unsigned char)(i * 131u);
    double t = gs__now();
    uint64_t h = gs__db_checksum(b, n, NULL, 0);
    t = gs__now() - t;
    printf("checksum of 100 MB: %.3f s (%016llx)\n", t, (unsigned long long)h);
    /* split input hashes like one piece */
    CHECK(gs__db_checksum(b, 1000, b + 1000, 3333) == gs__db_checksum(b, 4333, NULL, 0));
    CHECK(gs__db_checksum(b, 1003, b + 1003, 3330) == gs__db_checksum(b, 4333, NULL, 0));
    free(b);
}

/* Queries by input id: the least distance over both sides' aliases
 * (brute force over the fixture's lists), 0 for the same input vertex,
 * NaN / GS_EARG out of range; the field agrees with the pairs bit for bit;
 * saved and re-opened, the same answers. Without aliases, input ids are
 * vertex ids. The writer refuses lists that are empty or name a vertex
 * beyond n_vertices. */
static void test_aliases(void)
{
    fixture f;
    gs_db *db = fixture_db_full(&f);
    if (!db) return;
    gs_error err = {0};
    CHECK(gs_db_num_input_vertices(db) == 5 && gs_db_num_input_vertices(NULL) == 0);
    uint32_t got[4];
    CHECK(gs_db_input_aliases(db, 1, got, 4) == 2 && got[0] == 1 && got[1] == 5);
    CHECK(gs_db_input_aliases(db, 4, got, 4) == 1 && got[0] == 2);
    CHECK(gs_db_input_aliases(db, 3, got, 4) == 1 && got[0] == 3);
    CHECK(gs_db_input_aliases(db, 2, NULL, 0) == 2 && gs_db_input_aliases(db, 5, got, 4) == 0);
    CHECK(gs_db_save(db, tmp_path("aliases.gsdb"), &err) == GS_OK);
    gs_db *re = NULL;
    CHECK_MSG(gs_db_open(tmp_path("aliases.gsdb"), &re, &err) == GS_OK, "%s", err.message);
    double field[5], fre[5];
    uint32_t pairs[2 * 25];
    double batch[25];
    int bad = 0;
    for (uint32_t x = 0; x < 5; ++x) {
        CHECK(gs_db_input_field(db, x, field, &err) == GS_OK);
        if (re) CHECK(gs_db_input_field(re, x, fre, &err) == GS_OK && memcmp(field, fre, sizeof field) == 0);
        for (uint32_t y = 0; y < 5; ++y) {
            double want = INFINITY;
            for (uint32_t i = f.alias_start[x]; i < f.alias_start[x + 1]; ++i)
                for (uint32_t j = f.alias_start[y]; j < f.alias_start[y + 1]; ++j)
                    want = fmin(want, gs_db_distance(db, f.alias[i], f.alias[j]));
            if (x == y) want = 0.0;
            double d = gs_db_input_distance(db, x, y);
            bad += d != want || field[y] != want || gs_db_input_distance(db, y, x) != want;
            if (re) bad += gs_db_input_distance(re, x, y) != want;
            pairs[2 * (5 * x + y)] = x, pairs[2 * (5 * x + y) + 1] = y;
        }
    }
    CHECK_MSG(bad == 0, "%d input-id answers differ from the minimum over the aliases", bad);
    /* 4 was welded into 2: the same vertex; 1 and 4 through 1's copy 5 or itself */
    CHECK(gs_db_input_distance(db, 2, 4) == 0.0);
    CHECK(gs_db_input_distance(db, 1, 4) == fmin(fmin(gs_db_distance(db, 1, 2), gs_db_distance(db, 5, 2)), INFINITY));
    CHECK(gs_db_input_distances(db, pairs, 25, batch, &err) == GS_OK);
    for (uint32_t k = 0; k < 25; ++k) bad += batch[k] != gs_db_input_distance(db, pairs[2 * k], pairs[2 * k + 1]);
    CHECK(bad == 0);
    pairs[3] = 5;
    CHECK(gs_db_input_distances(db, pairs, 2, batch, &err) == GS_EARG && strstr(err.message, "pair 1 (0, 5)") &&
          isnan(batch[1]) && !isnan(batch[0]));
    CHECK(isnan(gs_db_input_distance(db, 5, 0)) && isnan(gs_db_input_distance(NULL, 0, 0)));
    CHECK(gs_db_input_field(db, 5, field, &err) == GS_EARG && strstr(err.message, "input vertex 5 >= n_input_vertices 5"));
    CHECK(gs_db_input_field(db, 0, NULL, &err) == GS_EARG);
    gs_db_free(re);
    gs_db_free(db);

    /* no aliases: input ids are vertex ids */
    db = fixture_db(&f, 1);
    if (!db) return;
    double a[FX_NV], b[FX_NV];
    CHECK(gs_db_num_input_vertices(db) == FX_NV && gs_db_input_aliases(db, 6, got, 4) == 1 && got[0] == 6);
    for (uint32_t x = 0; x < FX_NV; ++x) {
        CHECK(gs_db_input_field(db, x, a, &err) == GS_OK && gs_db_field(db, x, b, &err) == GS_OK);
        CHECK(memcmp(a, b, sizeof a) == 0);
        for (uint32_t y = 0; y < FX_NV; ++y) {
            double p = gs_db_input_distance(db, x, y), q = gs_db_distance(db, x, y);
            CHECK(memcmp(&p, &q, sizeof p) == 0);
        }
    }
    gs_db_free(db);

    /* the writer checks the lists */
    make_fixture(&f, 0);
    fixture_add_aliases(&f);
    f.alias[2] = FX_NV;
    CHECK(gs__db_pack(&f.c, &db, &err) == GS_EARG && db == NULL && strstr(err.message, "input vertex 1's alias 7"));
    make_fixture(&f, 0);
    fixture_add_aliases(&f);
    f.alias_start[2] = 3, f.alias_start[1] = 3;
    CHECK(gs__db_pack(&f.c, &db, &err) == GS_EARG && db == NULL && strstr(err.message, "has no alias"));
    make_fixture(&f, 0);
    fixture_add_aliases(&f);
    f.c.n_input = FX_NV + 1;
    CHECK(gs__db_pack(&f.c, &db, &err) == GS_EARG && db == NULL);
    /* aliases without leaf tables: sections 10-11 follow 6 */
    make_fixture(&f, 0);
    fixture_add_aliases(&f);
    CHECK(gs__db_pack(&f.c, &db, &err) == GS_OK && db && gs_db_verify(db, &err) == GS_OK);
    if (db) CHECK(gs_db_input_distance(db, 1, 3) == fmin(gs_db_distance(db, 1, 3), gs_db_distance(db, 5, 3)));
    gs_db_free(db);
}

/* dgg_eps is recorded for dgg builds, returned by gs_db_get_info, and
 * survives save and open; other methods record 0. */
static void test_dgg_eps(void)
{
    fixture f;
    make_fixture(&f, 0);
    f.c.method = GS_METHOD_DGG;
    f.c.dgg_eps = 0.02;
    gs_db *db = NULL, *re = NULL;
    gs_error err = {0};
    gs_db_info info;
    CHECK_MSG(gs__db_pack(&f.c, &db, &err) == GS_OK, "%s", err.message);
    if (!db) return;
    CHECK(gs_db_save(db, tmp_path("dgg.gsdb"), &err) == GS_OK);
    CHECK(gs_db_open(tmp_path("dgg.gsdb"), &re, &err) == GS_OK);
    CHECK(re && gs_db_get_info(re, &info, &err) == GS_OK && info.method == GS_METHOD_DGG &&
          info.solver.dgg_eps == 0.02);
    gs_db_free(re);
    gs_db_free(db);
    f.c.method = GS_METHOD_HEAT; /* recorded as 0 whatever the option */
    CHECK(gs__db_pack(&f.c, &db, &err) == GS_OK && gs_db_get_info(db, &info, &err) == GS_OK &&
          info.solver.dgg_eps == 0);
    gs_db_free(db);
}

/* The 16-bit minima: every code's value is at most what was encoded (a
 * lower bound for the quick reject) and within 2^-8 of it for normal
 * floats; 0 and below give 0, +inf its own code, beyond FLT_MAX the
 * largest finite code. */
static void test_min16(void)
{
    long bad = 0;
    double v = 1e-45;
    for (int i = 0; i < 200000; ++i, v *= 1.00107) {
        uint16_t q = gs__db_min_encode(v);
        double w = gs__db_min_value(q);
        bad += !(w <= v) || (v >= 1.2e-38 && v <= 3.4e38 && !(w >= v * (1 - 1.0 / 128))) || q >= GS__DB_MIN_INF;
    }
    CHECK_MSG(bad == 0, "%ld minima not stored as a close lower bound", bad);
    CHECK(gs__db_min_encode(0.0) == 0 && gs__db_min_encode(-1.0) == 0 && gs__db_min_encode(NAN) == 0);
    CHECK(gs__db_min_encode(INFINITY) == GS__DB_MIN_INF && gs__db_min_value(GS__DB_MIN_INF) == INFINITY);
    CHECK(gs__db_min_value(gs__db_min_encode(3.4028234663852886e38)) <= 3.4028234663852886e38);
    CHECK(gs__db_min_value(gs__db_min_encode(1e300)) <= 3.4028234663852886e38);
    CHECK(gs__db_min_value(0xFFFF) != gs__db_min_value(0xFFFF)); /* codes above +inf: NaN (refused by verify) */
}

int main(void)
{
    snprintf(tmpdir, sizeof tmpdir, "%s/test_db_tmp", GEOSEP_BINARY_DIR);
    mkdir(tmpdir, 0755);
    test_round_trip(0);
    test_round_trip(1);
    test_flips();
    test_truncation();
    test_structure();
    test_random_structural();
    test_huge_coefficients();
    test_leaf_floor();
    test_minval_above();
    test_min16();
    test_aliases();
    test_dgg_eps();
    test_files();
    test_checksum_speed();
    return gs__test_finish("test_db");
}

