/* db_write.c - the database writer: the format's checksum and layout, the
 * packer that serialises a gs_db_content (paper sec. 3.1) into the on-disk
 * bytes of doc/database-format.md, and the atomic save. */
#include "db_internal.h"
#include "../io/atomic_file.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define HASH_P 0x9E3779B97F4A7C15ull

/* ---- checksum ----------------------------------------------------------- */

static uint64_t load_le64(const unsigned char *p)
{
    uint64_t w;
    memcpy(&w, p, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    w = __builtin_bswap64(w);
#endif
    return w;
}

typedef struct hash_state {
    uint64_t lane[4];
    unsigned j;             /* lane of the next word                  */
    unsigned char part[8];  /* pending partial word                   */
    unsigned n_part;
    uint64_t length;
} hash_state;

static void hash_init(hash_state *h)
{
    memset(h, 0, sizeof *h);
    for (unsigned j = 0; j < 4; ++j) h->lane[j] = 0x243F6A8885A308D3ull + j * 0x13198A2E03707344ull;
}

static void hash_word(hash_state *h, uint64_t w)
{
    h->lane[h->j] = (h->lane[h->j] ^ w) * HASH_P;
    h->j = (h->j + 1) & 3u;
}

static void hash_bytes(hash_state *h, const unsigned char *p, size_t n)
{
    h->length += n;
    while (n && h->n_part) { /* finish a partial word first */
        h->part[h->n_part++] = *p++;
        --n;
        if (h->n_part == 8) {
            hash_word(h, load_le64(h->part));
            h->n_part = 0;
        }
    }
    if (h->j == 0) { /* fast path: four lanes in step */
        uint64_t a = h->lane[0], b = h->lane[1], c = h->lane[2], d = h->lane[3];
        for (; n >= 32; n -= 32, p += 32) {
            a = (a ^ load_le64(p)) * HASH_P;
            b = (b ^ load_le64(p + 8)) * HASH_P;
            c = (c ^ load_le64(p + 16)) * HASH_P;
            d = (d ^ load_le64(p + 24)) * HASH_P;
        }
        h->lane[0] = a, h->lane[1] = b, h->lane[2] = c, h->lane[3] = d;
    }
    for (; n >= 8; n -= 8, p += 8) hash_word(h, load_le64(p));
    while (n--) h->part[h->n_part++] = *p++;
}

static uint64_t hash_final(hash_state *h)
{
    if (h->n_part) {
        memset(h->part + h->n_part, 0, 8 - h->n_part);
        hash_word(h, load_le64(h->part));
    }
    uint64_t r = h->length * HASH_P;
    for (unsigned j = 0; j < 4; ++j) {
        r = (r ^ h->lane[j]) * HASH_P;
        r ^= r >> 29;
    }
    return r;
}

uint64_t gs__db_checksum(const void *a, size_t na, const void *b, size_t nb)
{
    hash_state h;
    hash_init(&h);
    hash_bytes(&h, a, na);
    if (b && nb) hash_bytes(&h, b, nb);
    return hash_final(&h);
}

/* ---- layout ------------------------------------------------------------- */

int gs__db_host_little_endian(void)
{
    const uint32_t one = 1;
    unsigned char c;
    memcpy(&c, &one, 1);
    return c == 1;
}

static uint64_t pad8(uint64_t b) { return (b + 7) & ~(uint64_t)7; }

int gs__db_layout(uint32_t nv, uint32_t n_nodes, uint32_t n_curves, uint64_t n_functions,
                  uint64_t n_words, uint64_t leaf_entries, int tables, uint64_t size[12])
{
    const uint64_t lim = (uint64_t)1 << 58; /* counts * 16 stay below 2^62 */
    if (n_functions > lim || n_words > lim || leaf_entries > lim) return 0;
    memset(size, 0, 12 * sizeof *size);
    size[GS_SEC_POSITIONS] = 24 * (uint64_t)nv;
    size[GS_SEC_LEAVES] = pad8(4 * (uint64_t)nv);
    size[GS_SEC_NODES] = pad8(20 * (uint64_t)n_nodes);
    size[GS_SEC_CURVES] = 24 * (uint64_t)n_curves;
    size[GS_SEC_VERTEX_DIR] = 16 * ((uint64_t)nv + 1);
    size[GS_SEC_FUNCTIONS] = 16 * n_functions;
    size[GS_SEC_WORDS] = 8 * n_words;
    if (tables) {
        size[GS_SEC_LEAF_VSTART] = pad8(4 * ((uint64_t)n_nodes + 1));
        size[GS_SEC_LEAF_LOCAL] = pad8(4 * (uint64_t)nv);
        size[GS_SEC_LEAF_DSTART] = 8 * ((uint64_t)n_nodes + 1);
        size[GS_SEC_LEAF_DIST] = 8 * leaf_entries;
    }
    return 1;
}

/* ---- packing ------------------------------------------------------------ */

static uint64_t record_words(const gs_fun *f)
{
    if (f->minval == INFINITY) return 0;
    return (uint64_t)f->closed + f->degree + 1;
}

static uint32_t record_meta(const gs_fun *f)
{
    uint32_t closed = f->closed ? 1u : 0u;
    if (f->minval == INFINITY) return closed << 19;
    return (f->degree & 0xFFFFu) | (f->kind & 3u) << 16 | (f->squared ? 1u : 0u) << 18 |
           closed << 19;
}

/* Words of all records; fails if a vertex's records exceed 2^32 words. */
static int count_words(const gs_db_content *c, uint64_t *n_words, gs_error *err)
{
    uint64_t total = 0;
    for (uint32_t x = 0; x < c->nv; ++x) {
        uint64_t w = 0;
        for (uint64_t k = c->fun_start[x]; k < c->fun_start[x + 1]; ++k) w += record_words(&c->funs[k]);
        if (w >= ((uint64_t)1 << 32))
            return gs__fail(err, GS_ELIMIT, "database: vertex %u has %llu words of functions (max 2^32)",
                            x, (unsigned long long)w);
        total += w;
    }
    *n_words = total;
    return GS_OK;
}

static void put32(unsigned char *p, uint32_t v) { memcpy(p, &v, 4); }
static void put64(unsigned char *p, uint64_t v) { memcpy(p, &v, 8); }
static void putf(unsigned char *p, double v) { memcpy(p, &v, 8); }

static void write_header(unsigned char *b, const gs_db_content *c, uint32_t n_sec, uint64_t file_bytes,
                         uint64_t n_words, uint64_t leaf_entries, int tables)
{
    uint64_t n_functions = c->fun_start[c->nv];
    memcpy(b, GS_DB_MAGIC, 8);
    put32(b + 8, GS_DB_VERSION);
    put32(b + 12, GS_DB_ENDIAN_TAG);
    put32(b + 16, tables ? GS_DB_FLAG_LEAF_EXACT : 0);
    put32(b + 20, GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * n_sec);
    put64(b + 24, file_bytes);
    put32(b + 32, c->nv);
    put32(b + 36, c->n_nodes);
    put32(b + 40, c->n_curves);
    put32(b + 44, c->n_leaves);
    put64(b + 48, n_functions);
    put64(b + 56, n_words);
    put32(b + 64, n_sec);
    put32(b + 68, c->max_depth);
    putf(b + 72, c->avg_depth);
    put32(b + 80, c->method);
    put32(b + 84, c->vmax);
    put32(b + 88, c->mmax);
    put32(b + 92, (c->vertex_sources ? GS_DB_BUILD_VERTEX_SOURCES : 0) |
                      (c->sampled ? GS_DB_BUILD_SAMPLED : 0) |
                      ((c->heat_refine << GS_DB_BUILD_HEAT_REFINE_SHIFT) & GS_DB_BUILD_HEAT_REFINE_MASK));
    putf(b + 96, c->tol);
    put64(b + 104, leaf_entries);
    /* Table 1 counts what describes the functions: coefficients and loop
     * shifts; minima and meta words are index overhead (bytes/vertex). */
    putf(b + 112, c->nv ? (double)n_words / c->nv : 0.0);
    putf(b + 120, c->sample_spacing);
    put32(b + 128, c->seed);
    put32(b + 132, c->max_samples);
    putf(b + 136, c->heat_time);
    putf(b + 144, c->fmm_exact_start);
}

static void write_functions(unsigned char *fsec, unsigned char *wsec, unsigned char *vsec,
                            const gs_db_content *c)
{
    uint64_t word = 0;
    for (uint32_t x = 0; x <= c->nv; ++x) {
        gs_db_vdir vd = {c->fun_start[x], word};
        memcpy(vsec + 16 * (uint64_t)x, &vd, 16);
        if (x == c->nv) break;
        uint64_t rel = 0;
        for (uint64_t k = c->fun_start[x]; k < c->fun_start[x + 1]; ++k) {
            const gs_fun *f = &c->funs[k];
            gs_db_fentry e = {f->minval, (uint32_t)rel, record_meta(f)};
            memcpy(fsec + 16 * k, &e, 16);
            uint64_t n = record_words(f);
            if (n) {
                unsigned char *r = wsec + 8 * (word + rel);
                if (f->closed) putf(r, f->shift), r += 8;
                memcpy(r, f->coef, 8 * ((size_t)f->degree + 1));
            }
            rel += n;
        }
        word += rel;
    }
}

static void write_nodes_curves(unsigned char *nsec, unsigned char *csec, const gs_db_content *c)
{
    for (uint32_t i = 0; i < c->n_nodes; ++i) {
        const gs_db_node *n = &c->nodes[i];
        uint32_t v[5] = {n->parent, n->depth, n->curve_start, n->n_curves, n->curve_prefix};
        memcpy(nsec + 20 * (uint64_t)i, v, 20);
    }
    for (uint32_t j = 0; j < c->n_curves; ++j) {
        gs_db_disk_curve d = {c->curves[j].node, c->curves[j].closed, c->curves[j].n_samples, 0,
                              c->curves[j].length};
        memcpy(csec + 24 * (uint64_t)j, &d, 24);
    }
}

static void write_leaf_tables(unsigned char *const sec[12], const gs_db_content *c)
{
    memcpy(sec[GS_SEC_LEAF_VSTART], c->leaf_vstart, 4 * ((size_t)c->n_nodes + 1));
    memcpy(sec[GS_SEC_LEAF_DSTART], c->leaf_dstart, 8 * ((size_t)c->n_nodes + 1));
    memcpy(sec[GS_SEC_LEAF_DIST], c->leaf_dist, 8 * (size_t)c->leaf_dstart[c->n_nodes]);
    unsigned char *loc = sec[GS_SEC_LEAF_LOCAL];
    for (uint32_t x = 0; x < c->nv; ++x) put32(loc + 4 * (uint64_t)x, GS_NONE);
    for (uint32_t l = 0; l < c->n_nodes; ++l)
        for (uint32_t k = c->leaf_vstart[l]; k < c->leaf_vstart[l + 1]; ++k)
            if (c->leaf_verts[k] < c->nv) put32(loc + 4 * (uint64_t)c->leaf_verts[k], k - c->leaf_vstart[l]);
}

static void write_sections(unsigned char *buf, const gs_db_content *c, const uint64_t size[12],
                           uint32_t n_sec)
{
    unsigned char *sec[12] = {0};
    uint64_t off = GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * n_sec;
    for (uint32_t s = 1; s <= n_sec; ++s) sec[s] = buf + off, off += size[s];
    memcpy(sec[GS_SEC_POSITIONS], c->xyz, 24 * (size_t)c->nv);
    memcpy(sec[GS_SEC_LEAVES], c->leaf, 4 * (size_t)c->nv);
    write_nodes_curves(sec[GS_SEC_NODES], sec[GS_SEC_CURVES], c);
    write_functions(sec[GS_SEC_FUNCTIONS], sec[GS_SEC_WORDS], sec[GS_SEC_VERTEX_DIR], c);
    if (n_sec == GS_SEC_COUNT_FULL) write_leaf_tables(sec, c);
    unsigned char *t = buf + GS_DB_HEADER_BYTES;
    for (uint32_t s = 1; s <= n_sec; ++s, t += GS_DB_ENTRY_BYTES) {
        put32(t, s);
        put32(t + 4, 0);
        put64(t + 8, (uint64_t)(sec[s] - buf));
        put64(t + 16, size[s]);
        put64(t + 24, gs__db_checksum(sec[s], size[s], NULL, 0));
    }
    put64(buf + GS_DB_CHECKSUM_AT,
          gs__db_checksum(buf, GS_DB_CHECKSUM_AT, buf + GS_DB_HEADER_BYTES, GS_DB_ENTRY_BYTES * n_sec));
}

int gs_db_pack(const gs_db_content *c, gs_db **out, gs_error *err)
{
    if (!c || !out || !c->fun_start || (c->nv && (!c->xyz || !c->leaf)) || !c->nodes)
        return gs__fail(err, GS_EARG, "gs_db_pack: missing content");
    *out = NULL;
    if (c->heat_refine > GS_DB_BUILD_HEAT_REFINE_MASK >> GS_DB_BUILD_HEAT_REFINE_SHIFT)
        return gs__fail(err, GS_EARG, "gs_db_pack: heat_refine %u does not fit the header", c->heat_refine);
    if (!gs__db_host_little_endian())
        return gs__fail(err, GS_EFORMAT, "database: big-endian hosts are not supported");
    int tables = c->leaf_dist && c->leaf_vstart && c->leaf_verts && c->leaf_dstart;
    uint64_t n_words = 0, size[12];
    int rc = count_words(c, &n_words, err);
    if (rc) return rc;
    uint64_t leaf_entries = tables ? c->leaf_dstart[c->n_nodes] : 0;
    uint32_t n_sec = tables ? GS_SEC_COUNT_FULL : GS_SEC_COUNT_BASE;
    if (!gs__db_layout(c->nv, c->n_nodes, c->n_curves, c->fun_start[c->nv], n_words, leaf_entries,
                       tables, size))
        return gs__fail(err, GS_ELIMIT, "database: too many functions or words");
    uint64_t total = GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * n_sec;
    for (uint32_t s = 1; s <= n_sec; ++s) total += size[s];
    if (total > SIZE_MAX) return gs__fail(err, GS_ELIMIT, "database: %llu bytes", (unsigned long long)total);
    unsigned char *buf = gs__calloc((size_t)total, 1);
    if (!buf) return gs__fail(err, GS_ENOMEM, "database: out of memory (%llu bytes)", (unsigned long long)total);
    write_header(buf, c, n_sec, total, n_words, leaf_entries, tables);
    write_sections(buf, c, size, n_sec);
    rc = gs__db_attach(buf, (size_t)total, 0, "built database", !c->no_query_cache, out, err);
    if (rc) free(buf);
    return rc;
}

int gs_db_save(const gs_db *db, const char *path, gs_error *err)
{
    if (!db || !path) return gs__fail(err, GS_EARG, "gs_db_save: NULL argument");
    gs_atomic_file af;
    int rc = gs_atomic_open(&af, path, err);
    if (rc) return rc;
    if (fwrite(db->bytes, 1, (size_t)db->size, af.fp) != (size_t)db->size) {
        gs_atomic_abort(&af);
        return gs__fail(err, GS_EIO, "%s: cannot write the database", path);
    }
    return gs_atomic_commit(&af, err);
}
