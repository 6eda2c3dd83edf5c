/* db_read.c - the validating database reader (doc/database-format.md): mmap
 * or copy the bytes, check every field, checksum, count and index before the
 * first query (paper sec. 3.1 data, sec. 3.2 queries rely on it). */
#include "db_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const sec_name[12] = {"?",         "positions",  "leaves",      "nodes",
                                         "curves",    "vertex_dir", "functions",   "words",
                                         "leaf_vstart", "leaf_local", "leaf_dstart", "leaf_dist"};

typedef struct reader {
    gs_db *db;
    const char *name;
    gs_error *err;
    const unsigned char *sec[12];
} reader;

#define BAD(r, ...) gs__fail((r)->err, GS_EPARSE, __VA_ARGS__)

static uint32_t get32(const unsigned char *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}
static uint64_t get64(const unsigned char *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}
static double getf(const unsigned char *p)
{
    double v;
    memcpy(&v, p, 8);
    return v;
}

/* ---- header and section table ------------------------------------------ */

static int check_ident(reader *r, const unsigned char *b, uint64_t size)
{
    if (size < GS_DB_HEADER_BYTES)
        return BAD(r, "%s: header: file has %llu bytes, a database has at least %u", r->name,
                   (unsigned long long)size, GS_DB_HEADER_BYTES);
    if (memcmp(b, GS_DB_MAGIC, 8) != 0) return BAD(r, "%s: header: bad magic (not a geosep database)", r->name);
    if (get32(b + 8) != GS_DB_VERSION)
        return gs__fail(r->err, GS_EFORMAT, "%s: header: format_version %u (this reader knows %u)", r->name,
                        get32(b + 8), GS_DB_VERSION);
    if (get32(b + 12) != GS_DB_ENDIAN_TAG)
        return gs__fail(r->err, GS_EFORMAT, "%s: header: endian_tag 0x%08X (expected 0x%08X)", r->name,
                        get32(b + 12), GS_DB_ENDIAN_TAG);
    return GS_OK;
}

static void read_header(gs_db *db, const unsigned char *b)
{
    db->flags = get32(b + 16);
    db->nv = get32(b + 32);
    db->n_nodes = get32(b + 36);
    db->n_curves = get32(b + 40);
    db->n_leaves = get32(b + 44);
    db->n_functions = get64(b + 48);
    db->n_words = get64(b + 56);
    db->max_depth = get32(b + 68);
    db->avg_depth = getf(b + 72);
    db->method = get32(b + 80);
    db->vmax = get32(b + 84);
    db->mmax = get32(b + 88);
    db->build_flags = get32(b + 92);
    db->tol = getf(b + 96);
    db->leaf_entries = get64(b + 104);
    db->cost = getf(b + 112);
    db->sample_spacing = getf(b + 120);
    db->seed = get32(b + 128);
    db->max_samples = get32(b + 132);
    db->heat_time = getf(b + 136);
    db->fmm_exact_start = getf(b + 144);
}

static int check_header(reader *r, const unsigned char *b, uint64_t size, uint32_t *n_sec)
{
    gs_db *db = r->db;
    if (db->flags & ~GS_DB_FLAG_LEAF_EXACT) return BAD(r, "%s: header: flags 0x%X has unknown bits", r->name, db->flags);
    uint32_t want = (db->flags & GS_DB_FLAG_LEAF_EXACT) ? GS_SEC_COUNT_FULL : GS_SEC_COUNT_BASE;
    *n_sec = get32(b + 64);
    if (*n_sec != want) return BAD(r, "%s: header: n_sections %u (flags require %u)", r->name, *n_sec, want);
    if (get32(b + 20) != GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * want)
        return BAD(r, "%s: header: header_bytes %u (expected %u)", r->name, get32(b + 20),
                   GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * want);
    if (get64(b + 24) != size)
        return BAD(r, "%s: header: file_bytes %llu but the file has %llu bytes (truncated or extended)", r->name,
                   (unsigned long long)get64(b + 24), (unsigned long long)size);
    uint64_t tab = GS_DB_ENTRY_BYTES * (uint64_t)want;
    if (size < GS_DB_HEADER_BYTES + tab)
        return BAD(r, "%s: section table: file ends inside the table", r->name);
    if (gs__db_checksum(b, GS_DB_CHECKSUM_AT, b + GS_DB_HEADER_BYTES, (size_t)tab) != get64(b + GS_DB_CHECKSUM_AT))
        return BAD(r, "%s: header: header_checksum mismatch (corrupt header or section table)", r->name);
    return GS_OK;
}

static int check_counts(reader *r)
{
    gs_db *db = r->db;
    if (db->nv == 0 || db->nv == GS_NONE) return BAD(r, "%s: header: n_vertices %u out of range", r->name, db->nv);
    if (db->n_nodes == 0 || db->n_nodes == GS_NONE)
        return BAD(r, "%s: header: n_nodes %u out of range", r->name, db->n_nodes);
    if (db->build_flags & ~(GS_DB_BUILD_VERTEX_SOURCES | GS_DB_BUILD_SAMPLED | GS_DB_BUILD_HEAT_REFINE_MASK))
        return BAD(r, "%s: header: build_flags 0x%X has unknown bits", r->name, db->build_flags);
    if (db->max_depth > db->n_nodes) return BAD(r, "%s: header: max_depth %u > n_nodes %u", r->name, db->max_depth, db->n_nodes);
    if (!(db->avg_depth >= 0 && db->avg_depth <= db->max_depth))
        return BAD(r, "%s: header: avg_depth %g not in [0, max_depth %u]", r->name, db->avg_depth, db->max_depth);
    if (!(db->tol >= 0 && isfinite(db->tol))) return BAD(r, "%s: header: tol %g not finite and >= 0", r->name, db->tol);
    if (!(db->cost >= 0 && isfinite(db->cost))) return BAD(r, "%s: header: cost %g not finite and >= 0", r->name, db->cost);
    if (!gs_method_name((gs_method)db->method)) return BAD(r, "%s: header: method %u unknown", r->name, db->method);
    if (!(db->sample_spacing > 0 && isfinite(db->sample_spacing)))
        return BAD(r, "%s: header: sample_spacing %g not finite and > 0", r->name, db->sample_spacing);
    if (!(db->heat_time >= GS_HEAT_TIME_MIN && db->heat_time <= GS_HEAT_TIME_MAX)) /* as the builder accepts */
        return BAD(r, "%s: header: heat_time %g not in [%g, %g]", r->name, db->heat_time, GS_HEAT_TIME_MIN,
                   GS_HEAT_TIME_MAX);
    if (!(db->fmm_exact_start >= 0 && isfinite(db->fmm_exact_start)))
        return BAD(r, "%s: header: fmm_exact_start %g not finite and >= 0", r->name, db->fmm_exact_start);
    if (!(db->flags & GS_DB_FLAG_LEAF_EXACT) && db->leaf_entries)
        return BAD(r, "%s: header: leaf_entries %llu without leaf tables", r->name, (unsigned long long)db->leaf_entries);
    return GS_OK;
}

static int check_table(reader *r, const unsigned char *b, uint64_t size, uint32_t n_sec)
{
    gs_db *db = r->db;
    uint64_t want[12];
    if (!gs__db_layout(db->nv, db->n_nodes, db->n_curves, db->n_functions, db->n_words, db->leaf_entries,
                       n_sec == GS_SEC_COUNT_FULL, want))
        return BAD(r, "%s: header: n_functions, n_words or leaf_entries absurdly large", r->name);
    uint64_t off = GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * (uint64_t)n_sec;
    for (uint32_t s = 1; s <= n_sec; ++s) {
        const unsigned char *t = b + GS_DB_HEADER_BYTES + GS_DB_ENTRY_BYTES * (s - 1);
        uint64_t o = get64(t + 8), sz = get64(t + 16);
        if (get32(t) != s || get32(t + 4) != 0)
            return BAD(r, "%s: section table: entry %u has id %u, reserved %u (expected id %u, 0)", r->name, s - 1,
                       get32(t), get32(t + 4), s);
        if (o != off) return BAD(r, "%s: section '%s': offset %llu (expected %llu)", r->name, sec_name[s],
                                 (unsigned long long)o, (unsigned long long)off);
        if (sz != want[s])
            return BAD(r, "%s: section '%s': size %llu disagrees with the header counts (expected %llu)", r->name,
                       sec_name[s], (unsigned long long)sz, (unsigned long long)want[s]);
        if (sz > size - off)
            return BAD(r, "%s: section '%s': [%llu, +%llu) runs past the end of the file (%llu bytes)", r->name,
                       sec_name[s], (unsigned long long)off, (unsigned long long)sz, (unsigned long long)size);
        if (gs__db_checksum(b + off, (size_t)sz, NULL, 0) != get64(t + 24))
            return BAD(r, "%s: section '%s': checksum mismatch (corrupt data)", r->name, sec_name[s]);
        r->sec[s] = b + off;
        off += sz;
    }
    if (off != size) return BAD(r, "%s: section table: sections end at %llu, file has %llu bytes", r->name,
                                (unsigned long long)off, (unsigned long long)size);
    return GS_OK;
}

static int check_padding(reader *r, uint32_t s, uint64_t used, uint64_t size)
{
    for (uint64_t i = used; i < size; ++i)
        if (r->sec[s][i]) return BAD(r, "%s: section '%s': padding byte %llu is not zero", r->name, sec_name[s],
                                     (unsigned long long)i);
    return GS_OK;
}

/* ---- tree: nodes, curves, leaves ---------------------------------------- */

static int check_node(reader *r, uint32_t i, const gs_db_node *n, const uint32_t *n_children)
{
    gs_db *db = r->db;
    if (i == 0) {
        if (n->parent != GS_NONE || n->depth != 0 || n->curve_prefix != 0)
            return BAD(r, "%s: section 'nodes': root has parent %u, depth %u, curve_prefix %u (expected none, 0, 0)",
                       r->name, n->parent, n->depth, n->curve_prefix);
    } else {
        if (n->parent >= i)
            return BAD(r, "%s: section 'nodes': node %u has parent %u (must be < its own index)", r->name, i, n->parent);
        const gs_db_node *p = &db->nodes[n->parent];
        if (n->depth != p->depth + 1)
            return BAD(r, "%s: section 'nodes': node %u has depth %u, its parent %u depth %u", r->name, i, n->depth,
                       n->parent, p->depth);
        if ((uint64_t)n->curve_prefix != (uint64_t)p->curve_prefix + p->n_curves)
            return BAD(r, "%s: section 'nodes': node %u has curve_prefix %u (parent's %u + %u curves)", r->name, i,
                       n->curve_prefix, p->curve_prefix, p->n_curves);
    }
    if ((uint64_t)n->curve_start + n->n_curves > db->n_curves)
        return BAD(r, "%s: section 'nodes': node %u curves [%u, +%u) past n_curves %u", r->name, i, n->curve_start,
                   n->n_curves, db->n_curves);
    if (n_children && n_children[i] == 0 && n->n_curves)
        return BAD(r, "%s: section 'nodes': leaf node %u has %u curves (a leaf has no separator)", r->name, i,
                   n->n_curves);
    for (uint32_t j = n->curve_start; j < n->curve_start + n->n_curves; ++j)
        if (db->curves[j].node != i)
            return BAD(r, "%s: section 'curves': curve %u is in node %u's range but names node %u", r->name, j, i,
                       db->curves[j].node);
    return GS_OK;
}

static int check_nodes(reader *r, uint32_t *n_children)
{
    gs_db *db = r->db;
    int rc = check_padding(r, GS_SEC_NODES, 20 * (uint64_t)db->n_nodes, ((20 * (uint64_t)db->n_nodes) + 7) & ~7ull);
    for (uint32_t i = 0; i < db->n_nodes && !rc; ++i) rc = check_node(r, i, &db->nodes[i], NULL);
    if (rc) return rc;
    for (uint32_t i = 1; i < db->n_nodes; ++i) n_children[db->nodes[i].parent]++;
    uint32_t leaves = 0;
    for (uint32_t i = 0; i < db->n_nodes && !rc; ++i) {
        leaves += n_children[i] == 0;
        if (n_children[i] > 2)
            return BAD(r, "%s: section 'nodes': node %u has %u children (a bisection tree has <= 2)", r->name, i,
                       n_children[i]);
        rc = check_node(r, i, &db->nodes[i], n_children);
    }
    if (!rc && leaves != db->n_leaves)
        return BAD(r, "%s: header: n_leaves %u but the tree has %u leaves", r->name, db->n_leaves, leaves);
    return rc;
}

static int check_curves(reader *r)
{
    gs_db *db = r->db;
    for (uint32_t j = 0; j < db->n_curves; ++j) {
        const gs_db_disk_curve *c = &db->curves[j];
        if (c->node >= db->n_nodes)
            return BAD(r, "%s: section 'curves': curve %u has node %u (n_nodes %u)", r->name, j, c->node, db->n_nodes);
        const gs_db_node *n = &db->nodes[c->node];
        if (j < n->curve_start || j - n->curve_start >= n->n_curves)
            return BAD(r, "%s: section 'curves': curve %u names node %u whose curves are [%u, +%u)", r->name, j,
                       c->node, n->curve_start, n->n_curves);
        if (c->closed > 1 || c->n_samples < 2 || c->reserved || !(c->length >= 0 && isfinite(c->length)))
            return BAD(r, "%s: section 'curves': curve %u has closed %u, n_samples %u, reserved %u, length %g", r->name,
                       j, c->closed, c->n_samples, c->reserved, c->length);
    }
    return GS_OK;
}

static int check_leaves(reader *r, const uint32_t *n_children)
{
    gs_db *db = r->db;
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x];
        if (l == GS_NONE) continue;
        if (l >= db->n_nodes)
            return BAD(r, "%s: section 'leaves': vertex %u has leaf %u (n_nodes %u)", r->name, x, l, db->n_nodes);
        if (n_children[l])
            return BAD(r, "%s: section 'leaves': vertex %u has leaf %u, which is not a leaf node", r->name, x, l);
    }
    for (uint32_t x = 0; x < db->nv; ++x)
        if (!isfinite(db->xyz[3 * (size_t)x]) || !isfinite(db->xyz[3 * (size_t)x + 1]) ||
            !isfinite(db->xyz[3 * (size_t)x + 2]))
            return BAD(r, "%s: section 'positions': vertex %u has a non-finite coordinate", r->name, x);
    return check_padding(r, GS_SEC_LEAVES, 4 * (uint64_t)db->nv, (4 * (uint64_t)db->nv + 7) & ~7ull);
}

/* ---- functions ---------------------------------------------------------- */

static int check_record(reader *r, uint32_t x, uint64_t k, const gs_db_fentry *e, uint32_t curve_closed,
                        uint64_t *words)
{
    gs_db *db = r->db;
    uint32_t m = e->meta, deg = GS_META_DEGREE(m), kind = GS_META_KIND(m);
    const char *nm = r->name;
    if (isnan(e->minval) || e->minval == -INFINITY)
        return BAD(r, "%s: section 'functions': record %llu of vertex %u has minval %g", nm, (unsigned long long)k, x, e->minval);
    if ((m & GS_META_UNKNOWN_BITS) || kind > 1)
        return BAD(r, "%s: section 'functions': record %llu of vertex %u has meta 0x%08X (unknown kind or bits)", nm,
                   (unsigned long long)k, x, m);
    if (GS_META_CLOSED(m) != curve_closed)
        return BAD(r, "%s: section 'functions': record %llu of vertex %u has closed %u, its curve %u", nm,
                   (unsigned long long)k, x, GS_META_CLOSED(m), curve_closed);
    if (e->word_offset != *words)
        return BAD(r, "%s: section 'functions': record %llu of vertex %u has word_offset %u (expected %llu)", nm,
                   (unsigned long long)k, x, e->word_offset, (unsigned long long)*words);
    if (e->minval == INFINITY) {
        if (deg || kind || GS_META_SQUARED(m))
            return BAD(r, "%s: section 'functions': record %llu of vertex %u is unreachable but has degree %u", nm,
                       (unsigned long long)k, x, deg);
        return GS_OK;
    }
    uint32_t max = kind == GS_FUN_SAMPLED ? GS_DB_MAX_SAMPLED : GS_FUN_MAX_DEGREE;
    if (deg > max || (kind == GS_FUN_SAMPLED && deg < 1))
        return BAD(r, "%s: section 'functions': record %llu of vertex %u has degree %u (max %u)", nm,
                   (unsigned long long)k, x, deg, max);
    uint64_t n = (uint64_t)curve_closed + deg + 1, base = db->vdir[x].first_word + *words;
    if (n > db->vdir[x + 1].first_word - db->vdir[x].first_word - *words)
        return BAD(r, "%s: section 'functions': record %llu of vertex %u (%llu words at %llu) runs past the vertex's words",
                   nm, (unsigned long long)k, x, (unsigned long long)n, (unsigned long long)*words);
    const double *w = db->words + base;
    if (curve_closed && !(fabs(w[0]) <= GS_DB_MAX_SHIFT))
        return BAD(r, "%s: section 'words': record %llu of vertex %u has shift %g (|shift| <= 2)", nm,
                   (unsigned long long)k, x, w[0]);
    for (uint64_t i = curve_closed; i < n; ++i) {
        if (!isfinite(w[i]))
            return BAD(r, "%s: section 'words': record %llu of vertex %u has a non-finite coefficient %llu", nm,
                       (unsigned long long)k, x, (unsigned long long)(i - curve_closed));
        if (fabs(w[i]) > GS_DB_MAX_COEF)
            return BAD(r, "%s: section 'words': record %llu of vertex %u has coefficient %llu = %g (|c| <= %g)", nm,
                       (unsigned long long)k, x, (unsigned long long)(i - curve_closed), w[i], GS_DB_MAX_COEF);
    }
    *words += n;
    return GS_OK;
}

/* The functions of vertex x in index order: the proper ancestors of its leaf
 * from the root down (path: scratch for n_nodes ids), each node's curves in
 * order, so that each function's curve is known. */
static int check_vertex_functions(reader *r, uint32_t x, uint32_t *path)
{
    gs_db *db = r->db;
    const gs_db_vdir *v = &db->vdir[x];
    uint64_t nf = v[1].first_function - v->first_function, words = 0;
    uint32_t l = db->leaf[x], len = 0;
    uint64_t want = l == GS_NONE ? 0 : db->nodes[l].curve_prefix;
    if (nf != want)
        return BAD(r, "%s: section 'vertex_dir': vertex %u has %llu functions, its leaf %u needs %llu", r->name, x,
                   (unsigned long long)nf, l, (unsigned long long)want);
    for (uint32_t a = l == GS_NONE ? GS_NONE : db->nodes[l].parent; a != GS_NONE; a = db->nodes[a].parent)
        path[len++] = a;
    while (len--) {
        const gs_db_node *n = &db->nodes[path[len]];
        for (uint32_t j = 0; j < n->n_curves; ++j) {
            uint64_t k = n->curve_prefix + (uint64_t)j;
            int rc = check_record(r, x, k, &db->funs[v->first_function + k], db->curves[n->curve_start + j].closed,
                                  &words);
            if (rc) return rc;
        }
    }
    if (words != v[1].first_word - v->first_word)
        return BAD(r, "%s: section 'vertex_dir': vertex %u has %llu words, its records use %llu", r->name, x,
                   (unsigned long long)(v[1].first_word - v->first_word), (unsigned long long)words);
    return GS_OK;
}

static int check_functions(reader *r)
{
    gs_db *db = r->db;
    const gs_db_vdir *v = db->vdir;
    if (v[0].first_function || v[0].first_word || v[db->nv].first_function != db->n_functions ||
        v[db->nv].first_word != db->n_words)
        return BAD(r, "%s: section 'vertex_dir': first entry (%llu, %llu) or sentinel (%llu, %llu) disagrees with "
                      "the header (n_functions %llu, n_words %llu)", r->name, (unsigned long long)v[0].first_function,
                   (unsigned long long)v[0].first_word, (unsigned long long)v[db->nv].first_function,
                   (unsigned long long)v[db->nv].first_word, (unsigned long long)db->n_functions,
                   (unsigned long long)db->n_words);
    for (uint32_t x = 0; x < db->nv; ++x) {
        if (v[x + 1].first_function < v[x].first_function || v[x + 1].first_function > db->n_functions ||
            v[x + 1].first_word < v[x].first_word || v[x + 1].first_word > db->n_words ||
            v[x + 1].first_word - v[x].first_word >= ((uint64_t)1 << 32))
            return BAD(r, "%s: section 'vertex_dir': entry %u (%llu, %llu) out of order or past the end", r->name,
                       x + 1, (unsigned long long)v[x + 1].first_function, (unsigned long long)v[x + 1].first_word);
    }
    uint32_t *path = gs__malloc(db->n_nodes, sizeof *path);
    if (!path) return gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    int rc = GS_OK;
    for (uint32_t x = 0; x < db->nv && !rc; ++x) rc = check_vertex_functions(r, x, path);
    free(path);
    return rc;
}

/* ---- leaf tables -------------------------------------------------------- */

static int check_leaf_ranges(reader *r, uint32_t *count)
{
    gs_db *db = r->db;
    for (uint32_t x = 0; x < db->nv; ++x)
        if (db->leaf[x] != GS_NONE) count[db->leaf[x]]++;
    if (db->leaf_vstart[0] || db->leaf_dstart[0])
        return BAD(r, "%s: section 'leaf_vstart': first entries must be 0", r->name);
    for (uint32_t l = 0; l < db->n_nodes; ++l) {
        uint64_t nl = (uint64_t)db->leaf_vstart[l + 1] - db->leaf_vstart[l];
        if (db->leaf_vstart[l + 1] < db->leaf_vstart[l] || nl != count[l])
            return BAD(r, "%s: section 'leaf_vstart': node %u has %lld table vertices, %u vertices are in it", r->name,
                       l, (long long)db->leaf_vstart[l + 1] - (long long)db->leaf_vstart[l], count[l]);
        if (db->leaf_dstart[l + 1] < db->leaf_dstart[l] || db->leaf_dstart[l + 1] - db->leaf_dstart[l] != nl * nl)
            return BAD(r, "%s: section 'leaf_dstart': node %u table size disagrees with its %llu vertices", r->name, l,
                       (unsigned long long)nl);
    }
    if (db->leaf_dstart[db->n_nodes] != db->leaf_entries)
        return BAD(r, "%s: section 'leaf_dstart': sentinel %llu but leaf_entries %llu", r->name,
                   (unsigned long long)db->leaf_dstart[db->n_nodes], (unsigned long long)db->leaf_entries);
    return GS_OK;
}

static int check_leaf_locals(reader *r, unsigned char *seen)
{
    gs_db *db = r->db;
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x], k = db->leaf_local[x];
        if (l == GS_NONE) {
            if (k != GS_NONE) return BAD(r, "%s: section 'leaf_local': unreferenced vertex %u has %u", r->name, x, k);
            continue;
        }
        uint32_t nl = db->leaf_vstart[l + 1] - db->leaf_vstart[l];
        if (k >= nl || seen[db->leaf_vstart[l] + (uint64_t)k])
            return BAD(r, "%s: section 'leaf_local': vertex %u has number %u in leaf %u (%u vertices, or taken)",
                       r->name, x, k, l, nl);
        seen[db->leaf_vstart[l] + (uint64_t)k] = 1;
    }
    /* bounded like coefficients: surface points square them (1e300 gave
     * +inf, "not connected"); a leaf's geodesic distances on a mesh that
     * loads are below n_vertices x GS_MESH_MAX_EDGE < 1e60 */
    for (uint64_t i = 0; i < db->leaf_entries; ++i)
        if (!(db->leaf_dist[i] >= 0 && (db->leaf_dist[i] <= GS_DB_MAX_COEF || db->leaf_dist[i] == INFINITY)))
            return BAD(r, "%s: section 'leaf_dist': entry %llu is %g (must be in [0, %g] or inf)", r->name,
                       (unsigned long long)i, db->leaf_dist[i], GS_DB_MAX_COEF);
    /* d(x,y) == d(y,x) and d(x,x) == 0, as the cross-leaf answers are */
    for (uint32_t l = 0; l < db->n_nodes; ++l) {
        uint64_t nl = (uint64_t)db->leaf_vstart[l + 1] - db->leaf_vstart[l];
        const double *t = db->leaf_dist + db->leaf_dstart[l];
        for (uint64_t i = 0; i < nl; ++i) {
            if (t[i * nl + i] != 0)
                return BAD(r, "%s: section 'leaf_dist': leaf %u's diagonal entry %llu is %g (must be 0)", r->name, l,
                           (unsigned long long)i, t[i * nl + i]);
            for (uint64_t j = i + 1; j < nl; ++j)
                if (t[i * nl + j] != t[j * nl + i])
                    return BAD(r, "%s: section 'leaf_dist': leaf %u's table is not symmetric ([%llu][%llu] %.17g, "
                                  "[%llu][%llu] %.17g)", r->name, l, (unsigned long long)i, (unsigned long long)j,
                               t[i * nl + j], (unsigned long long)j, (unsigned long long)i, t[j * nl + i]);
        }
    }
    return GS_OK;
}

static int check_leaf_tables(reader *r)
{
    gs_db *db = r->db;
    if (!db->leaf_vstart) return GS_OK;
    int rc = check_padding(r, GS_SEC_LEAF_VSTART, 4 * ((uint64_t)db->n_nodes + 1), (4 * ((uint64_t)db->n_nodes + 1) + 7) & ~7ull);
    if (!rc) rc = check_padding(r, GS_SEC_LEAF_LOCAL, 4 * (uint64_t)db->nv, (4 * (uint64_t)db->nv + 7) & ~7ull);
    if (rc) return rc;
    uint32_t *count = gs__calloc(db->n_nodes, sizeof *count);
    unsigned char *seen = gs__calloc((size_t)db->nv + 1, 1);
    if (!count || !seen) rc = gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    if (!rc) rc = check_leaf_ranges(r, count);
    if (!rc && db->leaf_vstart[db->n_nodes] > db->nv)
        rc = BAD(r, "%s: section 'leaf_vstart': %u table vertices > n_vertices", r->name, db->leaf_vstart[db->n_nodes]);
    if (!rc) rc = check_leaf_locals(r, seen);
    free(count);
    free(seen);
    return rc;
}

/* ---- attach ------------------------------------------------------------- */

static void set_pointers(reader *r, uint32_t n_sec)
{
    gs_db *db = r->db;
    db->xyz = (const double *)r->sec[GS_SEC_POSITIONS];
    db->leaf = (const uint32_t *)r->sec[GS_SEC_LEAVES];
    db->nodes = (const gs_db_node *)r->sec[GS_SEC_NODES];
    db->curves = (const gs_db_disk_curve *)r->sec[GS_SEC_CURVES];
    db->vdir = (const gs_db_vdir *)r->sec[GS_SEC_VERTEX_DIR];
    db->funs = (const gs_db_fentry *)r->sec[GS_SEC_FUNCTIONS];
    db->words = (const double *)r->sec[GS_SEC_WORDS];
    if (n_sec == GS_SEC_COUNT_FULL) {
        db->leaf_vstart = (const uint32_t *)r->sec[GS_SEC_LEAF_VSTART];
        db->leaf_local = (const uint32_t *)r->sec[GS_SEC_LEAF_LOCAL];
        db->leaf_dstart = (const uint64_t *)r->sec[GS_SEC_LEAF_DSTART];
        db->leaf_dist = (const double *)r->sec[GS_SEC_LEAF_DIST];
    }
}

static int validate(reader *r, const unsigned char *b, uint64_t size)
{
    uint32_t n_sec = 0;
    int rc = check_ident(r, b, size);
    if (!rc) read_header(r->db, b), rc = check_header(r, b, size, &n_sec);
    if (!rc) rc = check_counts(r);
    if (!rc) rc = check_table(r, b, size, n_sec);
    if (rc) return rc;
    set_pointers(r, n_sec);
    uint32_t *n_children = gs__calloc(r->db->n_nodes, sizeof *n_children);
    if (!n_children) return gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    rc = check_nodes(r, n_children);
    if (!rc) rc = check_curves(r);
    if (!rc) rc = check_leaves(r, n_children);
    free(n_children);
    if (!rc) rc = check_functions(r);
    if (!rc) rc = check_leaf_tables(r);
    return rc;
}

int gs__db_attach(void *storage, size_t size, int mapped, const char *name, int cache, gs_db **out,
                  gs_error *err)
{
    *out = NULL;
    if (!gs__db_host_little_endian())
        return gs__fail(err, GS_EFORMAT, "%s: big-endian hosts cannot read geosep databases", name);
    if (((uintptr_t)storage & 7u) != 0) return gs__fail(err, GS_EINTERNAL, "%s: buffer not 8-byte aligned", name);
    gs_db *db = gs__calloc(1, sizeof *db);
    if (!db) return gs__fail(err, GS_ENOMEM, "%s: out of memory", name);
    reader r = {db, name, err, {0}};
    int rc = validate(&r, storage, size);
    if (rc) {
        free(db);
        return rc;
    }
    db->storage = storage;
    db->storage_size = size;
    db->mapped = mapped;
    db->bytes = storage;
    db->size = size;
    rc = cache ? gs__db_grid_build(db, name, err) : GS_OK;
    if (rc) {
        free(db);
        return rc;
    }
    *out = db;
    return GS_OK;
}

/* ---- public entry points ------------------------------------------------- */

int gs_db_open(const char *path, gs_db **out, gs_error *err)
{
    if (!path || !out) return gs__fail(err, GS_EARG, "gs_db_open: NULL argument");
    *out = NULL;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return gs__fail(err, GS_EIO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return gs__fail(err, GS_EIO, "%s: not a regular file", path);
    }
    if ((uint64_t)st.st_size < GS_DB_HEADER_BYTES) {
        close(fd);
        return gs__fail(err, GS_EPARSE, "%s: header: file has %llu bytes, a database has at least %u", path,
                        (unsigned long long)st.st_size, GS_DB_HEADER_BYTES);
    }
    size_t size = (size_t)st.st_size;
    void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (map == MAP_FAILED) return gs__fail(err, GS_EIO, "%s: cannot map: %s", path, strerror(errno));
    int rc = gs__db_attach(map, size, 1, path, 1, out, err);
    if (rc) munmap(map, size);
    return rc;
}

int gs_db_open_memory(const void *data, size_t size, gs_db **out, gs_error *err)
{
    if (!data || !out) return gs__fail(err, GS_EARG, "gs_db_open_memory: NULL argument");
    *out = NULL;
    void *copy = gs__malloc(size ? size : 1, 1); /* malloc: aligned for doubles */
    if (!copy) return gs__fail(err, GS_ENOMEM, "database: out of memory (%zu bytes)", size);
    memcpy(copy, data, size);
    int rc = gs__db_attach(copy, size, 0, "database", 1, out, err);
    if (rc) free(copy);
    return rc;
}

void gs_db_free(gs_db *db)
{
    if (!db) return;
    gs__db_grid_free(db);
    if (db->mapped) munmap(db->storage, db->storage_size);
    else free(db->storage);
    free(db);
}

int gs_db_get_info(const gs_db *db, gs_db_info *info, gs_error *err)
{
    if (!db || !info) return gs__fail(err, GS_EARG, "gs_db_get_info: NULL argument");
    memset(info, 0, sizeof *info);
    info->format_version = GS_DB_VERSION;
    info->n_vertices = db->nv;
    info->n_nodes = db->n_nodes;
    info->n_leaves = db->n_leaves;
    info->n_curves = db->n_curves;
    info->avg_depth = db->avg_depth;
    info->max_depth = db->max_depth;
    info->cost = db->cost;
    info->file_bytes = db->size;
    info->bytes_per_vertex = (double)db->size / db->nv;
    info->method = (gs_method)db->method;
    info->vmax = db->vmax;
    info->mmax = db->mmax;
    info->tol = db->tol;
    info->vertex_sources = (db->build_flags & GS_DB_BUILD_VERTEX_SOURCES) != 0;
    info->sampled = (db->build_flags & GS_DB_BUILD_SAMPLED) != 0;
    info->leaf_exact = db->leaf_vstart != NULL;
    info->sample_spacing = db->sample_spacing;
    info->seed = db->seed;
    info->max_samples = db->max_samples;
    info->solver.heat_time = db->heat_time;
    info->solver.fmm_exact_start = db->fmm_exact_start;
    info->solver.heat_refine = (db->build_flags & GS_DB_BUILD_HEAT_REFINE_MASK) >> GS_DB_BUILD_HEAT_REFINE_SHIFT;
    return GS_OK;
}
