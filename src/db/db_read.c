/* db_read.c - the database reader (doc/database-format.md, version 6): map
 * the file and validate its structure (header, section table, counts,
 * offsets, the tree and the record index: what makes every read of a
 * query land inside the file); the full check (checksums, every record and
 * value) on demand: gs_db_verify, gs_db_open_ex(GS_DB_OPEN_VERIFY). */
#include "db_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct reader {
    gs_db *db;
    const char *name;
    gs_error *err;
    const unsigned char *sec[GS__SEC_MAX + 1];
    uint64_t sec_size[GS__SEC_MAX + 1];
    uint32_t n_sec, ids[GS__SEC_MAX]; /* the sections present, in order */
} reader;

#define BAD(r, ...) gs__fail((r)->err, GS_EPARSE, __VA_ARGS__)
#define SEC(s) gs__db_section_name[s]

/* ---- header and section table ------------------------------------------ */

static int check_ident(reader *r, const unsigned char *b, uint64_t size)
{
    if (size < GS__DB_HEADER_BYTES)
        return BAD(r, "%s: header: file has %llu bytes, a database has at least %u", r->name,
                   (unsigned long long)size, GS__DB_HEADER_BYTES);
    if (memcmp(b, GS__DB_MAGIC, 8) != 0) return BAD(r, "%s: header: bad magic (not a geosep database)", r->name);
    uint32_t v = gs__get32(b + GS__H_VERSION);
    if (v < GS__DB_VERSION_MIN || v > GS__DB_VERSION)
        return gs__fail(r->err, GS_EFORMAT,
                        "%s: header: format_version %u; this geosep reads versions %u to %u%s", r->name, v,
                        GS__DB_VERSION_MIN, GS__DB_VERSION,
                        v < GS__DB_VERSION ? " (an older file: rebuild it with geosep build)" : " (a newer geosep wrote it)");
    if (gs__get32(b + GS__H_ENDIAN) != GS__DB_ENDIAN_TAG)
        return gs__fail(r->err, GS_EFORMAT, "%s: header: endian_tag 0x%08X (expected 0x%08X)", r->name,
                        gs__get32(b + GS__H_ENDIAN), GS__DB_ENDIAN_TAG);
    return GS_OK;
}

static void read_header(gs_db *db, const unsigned char *b)
{
    db->version = gs__get32(b + GS__H_VERSION);
    db->flags = gs__get32(b + GS__H_FLAGS);
    db->nv = gs__get32(b + GS__H_NV);
    db->n_nodes = gs__get32(b + GS__H_NODES);
    db->n_curves = gs__get32(b + GS__H_CURVES);
    db->n_leaves = gs__get32(b + GS__H_LEAVES);
    db->n_functions = gs__get64(b + GS__H_FUNCTIONS);
    db->records_bytes = gs__get64(b + GS__H_RECORDS_BYTES);
    db->max_depth = gs__get32(b + GS__H_MAX_DEPTH);
    db->avg_depth = gs__getf64(b + GS__H_AVG_DEPTH);
    db->method = gs__get32(b + GS__H_METHOD);
    db->vmax = gs__get32(b + GS__H_VMAX);
    db->mmax = gs__get32(b + GS__H_MMAX);
    db->build_flags = gs__get32(b + GS__H_BUILD_FLAGS);
    db->tol = gs__getf64(b + GS__H_TOL);
    db->leaf_entries = gs__get64(b + GS__H_LEAF_ENTRIES);
    db->cost = gs__getf64(b + GS__H_COST);
    db->sample_spacing = gs__getf64(b + GS__H_SPACING);
    db->seed = gs__get32(b + GS__H_SEED);
    db->max_samples = gs__get32(b + GS__H_MAX_SAMPLES);
    db->heat_time = gs__getf64(b + GS__H_HEAT_TIME);
    db->fmm_exact_start = gs__getf64(b + GS__H_FMM_START);
    db->dgg_eps = gs__getf64(b + GS__H_DGG_EPS);
    db->n_input = gs__get32(b + GS__H_N_INPUT);
    db->alias_exceptions = gs__get32(b + GS__H_ALIAS_EXCEPTIONS);
    db->alias_entries = gs__get64(b + GS__H_ALIAS_ENTRIES);
}

static int check_header(reader *r, const unsigned char *b, uint64_t size)
{
    gs_db *db = r->db;
    if (db->flags & ~GS__DB_FLAGS_KNOWN)
        return BAD(r, "%s: header: flags 0x%X has unknown bits", r->name, db->flags);
    if ((db->flags & GS__DB_FLAG_LEAF_LOCAL16) && !(db->flags & GS__DB_FLAG_LEAF_EXACT))
        return BAD(r, "%s: header: flags 0x%X: 16-bit leaf numbers without leaf tables", r->name, db->flags);
    uint32_t want = gs__db_section_ids(db->flags, r->ids);
    r->n_sec = gs__get32(b + GS__H_SECTIONS);
    if (r->n_sec != want) return BAD(r, "%s: header: n_sections %u (flags require %u)", r->name, r->n_sec, want);
    if (gs__get32(b + GS__H_HEADER_BYTES) != GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * want)
        return BAD(r, "%s: header: header_bytes %u (expected %u)", r->name, gs__get32(b + GS__H_HEADER_BYTES),
                   GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * want);
    if (gs__get64(b + GS__H_FILE_BYTES) != size)
        return BAD(r, "%s: header: file_bytes %llu but the file has %llu bytes (truncated or extended)", r->name,
                   (unsigned long long)gs__get64(b + GS__H_FILE_BYTES), (unsigned long long)size);
    uint64_t tab = GS__DB_ENTRY_BYTES * (uint64_t)want;
    if (size < GS__DB_HEADER_BYTES + tab) return BAD(r, "%s: section table: file ends inside the table", r->name);
    /* always: the header and the table are a few hundred bytes */
    if (gs__db_checksum(b, GS__DB_CHECKSUM_AT, b + GS__DB_HEADER_BYTES, (size_t)tab) !=
        gs__get64(b + GS__DB_CHECKSUM_AT))
        return BAD(r, "%s: header: header_checksum mismatch (corrupt header or section table)", r->name);
    return GS_OK;
}

static int check_counts(reader *r)
{
    gs_db *db = r->db;
    if (db->nv == 0 || db->nv == GS_NONE) return BAD(r, "%s: header: n_vertices %u out of range", r->name, db->nv);
    if (db->n_nodes == 0 || db->n_nodes == GS_NONE)
        return BAD(r, "%s: header: n_nodes %u out of range", r->name, db->n_nodes);
    if (db->build_flags & ~(GS__DB_BUILD_VERTEX_SOURCES | GS__DB_BUILD_SAMPLED | GS__DB_BUILD_HEAT_REFINE_MASK))
        return BAD(r, "%s: header: build_flags 0x%X has unknown bits", r->name, db->build_flags);
    if (db->max_depth > db->n_nodes)
        return BAD(r, "%s: header: max_depth %u > n_nodes %u", r->name, db->max_depth, db->n_nodes);
    if (!(db->avg_depth >= 0 && db->avg_depth <= db->max_depth))
        return BAD(r, "%s: header: avg_depth %g not in [0, max_depth %u]", r->name, db->avg_depth, db->max_depth);
    if (!(db->tol >= 0 && isfinite(db->tol))) return BAD(r, "%s: header: tol %g not finite and >= 0", r->name, db->tol);
    if (!(db->cost >= 0 && isfinite(db->cost)))
        return BAD(r, "%s: header: cost %g not finite and >= 0", r->name, db->cost);
    if (!gs_method_name((gs_method)db->method)) return BAD(r, "%s: header: method %u unknown", r->name, db->method);
    if (!(db->sample_spacing > 0 && isfinite(db->sample_spacing)))
        return BAD(r, "%s: header: sample_spacing %g not finite and > 0", r->name, db->sample_spacing);
    if (!(db->heat_time >= GS_HEAT_TIME_MIN && db->heat_time <= GS_HEAT_TIME_MAX))
        return BAD(r, "%s: header: heat_time %g not in [%g, %g]", r->name, db->heat_time, GS_HEAT_TIME_MIN,
                   GS_HEAT_TIME_MAX);
    if (!(db->fmm_exact_start >= 0 && isfinite(db->fmm_exact_start)))
        return BAD(r, "%s: header: fmm_exact_start %g not finite and >= 0", r->name, db->fmm_exact_start);
    if (db->method == GS_METHOD_DGG ? !(db->dgg_eps >= GS_DGG_EPS_MIN && db->dgg_eps <= GS_DGG_EPS_MAX)
                                    : db->dgg_eps != 0)
        return BAD(r, "%s: header: dgg_eps %g (method %s: %s)", r->name, db->dgg_eps,
                   gs_method_name((gs_method)db->method),
                   db->method == GS_METHOD_DGG ? "must be in [1e-05, 0.5]" : "must be 0");
    if (db->flags & GS__DB_FLAG_ALIASES) {
        if (db->n_input == 0 || db->n_input > db->nv || db->alias_entries < db->alias_exceptions ||
            db->alias_entries > UINT32_MAX)
            return BAD(r, "%s: header: n_input %u, alias_exceptions %u, alias_entries %llu (need 1 <= n_input <= "
                          "n_vertices %u, exceptions <= entries < 2^32)",
                       r->name, db->n_input, db->alias_exceptions, (unsigned long long)db->alias_entries, db->nv);
    } else if (db->n_input || db->alias_exceptions || db->alias_entries) {
        return BAD(r, "%s: header: n_input %u, alias_exceptions %u, alias_entries %llu without aliases (flags bit 2)",
                   r->name, db->n_input, db->alias_exceptions, (unsigned long long)db->alias_entries);
    }
    if (!(db->flags & GS__DB_FLAG_LEAF_EXACT) && db->leaf_entries)
        return BAD(r, "%s: header: leaf_entries %llu without leaf tables", r->name,
                   (unsigned long long)db->leaf_entries);
    if (db->records_bytes % 8 || db->records_bytes > GS__DB_MAX_RECORDS_BYTES)
        return BAD(r, "%s: header: records_bytes %llu (a multiple of 8, at most %llu)", r->name,
                   (unsigned long long)db->records_bytes, (unsigned long long)GS__DB_MAX_RECORDS_BYTES);
    return GS_OK;
}

/* Offsets and sizes; the sections' checksums when verify. */
static int check_table(reader *r, const unsigned char *b, uint64_t size, int verify)
{
    gs_db *db = r->db;
    uint64_t want[GS__SEC_MAX + 1];
    gs__db_counts cn = {db->flags, db->nv, db->n_nodes, db->n_curves, db->records_bytes, db->leaf_entries,
                        db->alias_exceptions, db->alias_entries};
    if (!gs__db_layout(&cn, want))
        return BAD(r, "%s: header: records_bytes, leaf_entries or alias_entries absurdly large", r->name);
    uint64_t off = GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * (uint64_t)r->n_sec;
    for (uint32_t e = 0; e < r->n_sec; ++e) {
        uint32_t s = r->ids[e];
        const unsigned char *t = b + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * e;
        uint64_t o = gs__get64(t + 8), sz = gs__get64(t + 16);
        if (gs__get32(t) != s || gs__get32(t + 4) != 0)
            return BAD(r, "%s: section table: entry %u has id %u, reserved %u (expected id %u, 0)", r->name, e,
                       gs__get32(t), gs__get32(t + 4), s);
        if (o != off)
            return BAD(r, "%s: section '%s': offset %llu (expected %llu)", r->name, SEC(s), (unsigned long long)o,
                       (unsigned long long)off);
        if (s == GS__SEC_NEAR) { /* sized by its own head (db_near.c checks it) */
            if (sz % 8 || sz > size - off)
                return BAD(r, "%s: section '%s': size %llu (a multiple of 8 within the file's %llu bytes)", r->name,
                           SEC(s), (unsigned long long)sz, (unsigned long long)size);
        } else if (sz != want[s])
            return BAD(r, "%s: section '%s': size %llu disagrees with the header counts (expected %llu)", r->name,
                       SEC(s), (unsigned long long)sz, (unsigned long long)want[s]);
        if (sz > size - off)
            return BAD(r, "%s: section '%s': [%llu, +%llu) runs past the end of the file (%llu bytes)", r->name,
                       SEC(s), (unsigned long long)off, (unsigned long long)sz, (unsigned long long)size);
        if (verify && gs__db_checksum(b + off, (size_t)sz, NULL, 0) != gs__get64(t + 24))
            return BAD(r, "%s: section '%s': checksum mismatch (corrupt data)", r->name, SEC(s));
        r->sec[s] = b + off;
        r->sec_size[s] = sz;
        off += sz;
    }
    if (off != size)
        return BAD(r, "%s: section table: sections end at %llu, file has %llu bytes", r->name,
                   (unsigned long long)off, (unsigned long long)size);
    return GS_OK;
}

static int check_padding(reader *r, uint32_t s, uint64_t used)
{
    for (uint64_t i = used; i < r->sec_size[s]; ++i)
        if (r->sec[s][i])
            return BAD(r, "%s: section '%s': padding byte %llu is not zero", r->name, SEC(s), (unsigned long long)i);
    return GS_OK;
}

/* ---- tree: nodes, curves, leaves ---------------------------------------- */

static int check_node(reader *r, uint32_t i, const gs__db_node *n, const uint32_t *n_children)
{
    gs_db *db = r->db;
    if (i == 0) {
        if (n->parent != GS_NONE || n->depth != 0 || n->curve_prefix != 0)
            return BAD(r, "%s: section 'nodes': root has parent %u, depth %u, curve_prefix %u (expected none, 0, 0)",
                       r->name, n->parent, n->depth, n->curve_prefix);
    } else {
        if (n->parent >= i)
            return BAD(r, "%s: section 'nodes': node %u has parent %u (must be < its own index)", r->name, i,
                       n->parent);
        const gs__db_node *p = &db->nodes[n->parent];
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
    int rc = check_padding(r, GS__SEC_NODES, 20 * (uint64_t)db->n_nodes);
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
        const gs__db_disk_curve *c = &db->curves[j];
        if (c->node >= db->n_nodes)
            return BAD(r, "%s: section 'curves': curve %u has node %u (n_nodes %u)", r->name, j, c->node, db->n_nodes);
        const gs__db_node *n = &db->nodes[c->node];
        if (j < n->curve_start || j - n->curve_start >= n->n_curves)
            return BAD(r, "%s: section 'curves': curve %u names node %u whose curves are [%u, +%u)", r->name, j,
                       c->node, n->curve_start, n->n_curves);
        if (c->closed > 1 || c->n_samples < 2 || c->degree1 > GS_FUN_MAX_DEGREE + 1 ||
            !(c->length >= 0 && isfinite(c->length)))
            return BAD(r, "%s: section 'curves': curve %u has closed %u, n_samples %u, degree1 %u, length %g", r->name,
                       j, c->closed, c->n_samples, c->degree1, c->length);
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
    return check_padding(r, GS__SEC_LEAVES, 4 * (uint64_t)db->nv);
}

/* The record index: starts at 0, never decreases, ends at records_bytes,
 * and every record holds at least its nf minima. */
static int check_index(reader *r)
{
    gs_db *db = r->db;
    const uint32_t *ix = db->index;
    if (ix[0] != 0) return BAD(r, "%s: section 'vertex_index': entry 0 is %u (must be 0)", r->name, ix[0]);
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x];
        uint64_t nf = l == GS_NONE ? 0 : db->nodes[l].curve_prefix;
        if (ix[x + 1] < ix[x] || GS__DB_RECORD_UNIT * ((uint64_t)ix[x + 1] - ix[x]) < GS__DB_MIN_BYTES * nf)
            return BAD(r, "%s: section 'vertex_index': vertex %u's record [%u, %u) (2-byte units) cannot hold its %llu "
                          "minima",
                       r->name, x, ix[x], ix[x + 1], (unsigned long long)nf);
    }
    uint64_t used = GS__DB_RECORD_UNIT * (uint64_t)ix[db->nv];
    if (gs__pad8(used) != db->records_bytes)
        return BAD(r, "%s: section 'vertex_index': last entry %u (x 2, rounded up to 8) disagrees with records_bytes %llu",
                   r->name, ix[db->nv], (unsigned long long)db->records_bytes);
    int rc = check_padding(r, GS__SEC_RECORDS, used); /* at most 6 bytes */
    return rc ? rc : check_padding(r, GS__SEC_INDEX, 4 * ((uint64_t)db->nv + 1));
}

/* ---- leaf tables: the structure at open, the values by verify ---------- */

/* Every vertex's number is below its leaf's n (0 for unreferenced
 * vertices). wide: u16 numbers (a constant where it is called: one loop
 * per width, the open's longest one). */
static inline int check_local_bounds(reader *r, int wide)
{
    const gs_db *db = r->db;
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x], k = wide ? db->leaf_local16[x] : db->leaf_local8[x];
        if (l == GS_NONE ? k != 0 : k >= db->leaf_nodes[l].n)
            return l == GS_NONE
                       ? BAD(r, "%s: section 'leaf_local': unreferenced vertex %u has number %u (must be 0)", r->name,
                             x, k)
                       : BAD(r, "%s: section 'leaf_local': vertex %u has number %u in leaf %u (%u vertices)", r->name,
                             x, k, l, db->leaf_nodes[l].n);
    }
    return GS_OK;
}

/* At open, what keeps every same-leaf read in bounds: each node's n at
 * most 256 (65,536 with 16-bit numbers), the tables contiguous from 0 to
 * leaf_entries, every vertex's number below its leaf's n; padding zero.
 * O(nodes + vertices), no allocation. That each n is its leaf's vertex
 * count and no two vertices share a number: verify
 * (check_leaf_numbering). */
static int check_leaf_structure(reader *r)
{
    gs_db *db = r->db;
    if (!db->leaf_nodes) return GS_OK;
    const uint64_t wl = db->leaf_local8 ? 1 : 2;
    int rc = check_padding(r, GS__SEC_LEAF_LOCAL, wl * db->nv);
    if (!rc) rc = check_padding(r, GS__SEC_LEAF_Q, 2 * db->leaf_entries);
    if (rc) return rc;
    uint64_t q = 0;
    const uint64_t nmax = db->leaf_local8 ? 256 : 65536;
    for (uint32_t l = 0; l < db->n_nodes; ++l) {
        const gs__db_leaf_node *t = &db->leaf_nodes[l];
        if (t->n > nmax)
            return BAD(r, "%s: section 'leaf_nodes': node %u has a table of %u vertices (at most %llu)", r->name, l,
                       t->n, (unsigned long long)nmax);
        if (t->qstart != q)
            return BAD(r, "%s: section 'leaf_nodes': node %u's table starts at entry %llu (expected %llu)", r->name, l,
                       (unsigned long long)t->qstart, (unsigned long long)q);
        q += gs__db_leaf_tri(t->n);
    }
    if (q != db->leaf_entries)
        return BAD(r, "%s: section 'leaf_nodes': the tables hold %llu entries, header leaf_entries %llu", r->name,
                   (unsigned long long)q, (unsigned long long)db->leaf_entries);
    return db->leaf_local8 ? check_local_bounds(r, 0) : check_local_bounds(r, 1);
}

/* Verify: each node's n is the number of vertices in it, and the vertices
 * of a leaf have distinct numbers (so the table has a row per vertex). */
static int check_leaf_numbering(reader *r)
{
    gs_db *db = r->db;
    uint32_t *count = gs__calloc(db->n_nodes, sizeof *count);
    uint64_t *first = gs__calloc((size_t)db->n_nodes + 1, sizeof *first); /* seen[] offset of each node */
    unsigned char *seen = gs__calloc((size_t)db->nv + 1, 1);
    int rc = count && first && seen ? GS_OK : gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    for (uint32_t x = 0; x < db->nv && !rc; ++x)
        if (db->leaf[x] != GS_NONE) count[db->leaf[x]]++;
    for (uint32_t l = 0; l < db->n_nodes && !rc; ++l) {
        if (db->leaf_nodes[l].n != count[l])
            rc = BAD(r, "%s: section 'leaf_nodes': node %u has a table of %u vertices, %u vertices are in it", r->name,
                     l, db->leaf_nodes[l].n, count[l]);
        first[l + 1] = first[l] + count[l];
    }
    for (uint32_t x = 0; x < db->nv && !rc; ++x) {
        uint32_t l = db->leaf[x], k = gs__db_leaf_local(db, x);
        if (l == GS_NONE) continue;
        if (seen[first[l] + k]) /* k < n = count[l]: checked */
            rc = BAD(r, "%s: section 'leaf_local': vertex %u has number %u in leaf %u, taken by another vertex",
                     r->name, x, k, l);
        seen[first[l] + k] = 1;
    }
    free(count);
    free(first);
    free(seen);
    return rc;
}

/* The scales (finite, in [0, 1e30], 0 for internal nodes) and that each
 * scale is its table's largest finite excess over the straight segment
 * (its largest finite entry is GS__DB_LEAF_QMAX, or 0 when the scale is
 * 0). */
static int check_leaf_values(reader *r)
{
    gs_db *db = r->db;
    if (!db->leaf_nodes) return GS_OK;
    int rc = check_leaf_numbering(r);
    if (rc) return rc;
    for (uint32_t l = 0; l < db->n_nodes; ++l) {
        const gs__db_leaf_node *t = &db->leaf_nodes[l];
        if (!(t->scale >= 0 && t->scale <= GS__DB_LEAF_MAX_SCALE) || (t->n == 0 && t->scale != 0))
            return BAD(r, "%s: section 'leaf_nodes': node %u (%u vertices) has scale %g (must be in [0, 1e30], 0 "
                          "without vertices)",
                       r->name, l, t->n, (double)t->scale);
        uint32_t top = 0;
        int finite = 0;
        for (uint64_t i = 0; i < gs__db_leaf_tri(t->n); ++i) {
            uint32_t v = db->leaf_q[t->qstart + i];
            if (v == GS__DB_LEAF_QINF) continue;
            finite = 1;
            top = v > top ? v : top;
        }
        if (finite && top != (t->scale > 0 ? GS__DB_LEAF_QMAX : 0u))
            return BAD(r, "%s: section 'leaf_q': node %u's largest finite entry is %u (its scale %g: expected %u)",
                       r->name, l, top, (double)t->scale, t->scale > 0 ? GS__DB_LEAF_QMAX : 0u);
    }
    return GS_OK;
}

/* ---- input-id aliases: the whole section at open (a few bytes per
 * repaired vertex) --------------------------------------------------------- */

/* Exceptions sorted by input vertex (each < n_input), lists non-empty and
 * contiguous from 0 to alias_entries (the sentinel: {n_input,
 * alias_entries}), every alias < n_vertices; padding zero. */
static int check_aliases(reader *r)
{
    gs_db *db = r->db;
    if (!db->alias_index) return GS_OK;
    const gs__db_alias_head *h = db->alias_index;
    uint32_t ne = db->alias_exceptions;
    if (h[0].start != 0) return BAD(r, "%s: section 'alias_index': entry 0 starts at %u (must be 0)", r->name, h[0].start);
    for (uint32_t k = 0; k < ne; ++k) {
        if (h[k].v >= db->n_input || (k && h[k].v <= h[k - 1].v))
            return BAD(r, "%s: section 'alias_index': entry %u names input vertex %u (increasing, below n_input %u)",
                       r->name, k, h[k].v, db->n_input);
        if (h[k + 1].start <= h[k].start)
            return BAD(r, "%s: section 'alias_index': input vertex %u's list [%u, %u) is empty or reversed", r->name,
                       h[k].v, h[k].start, h[k + 1].start);
    }
    if (h[ne].v != db->n_input || h[ne].start != db->alias_entries)
        return BAD(r, "%s: section 'alias_index': sentinel {%u, %u}, expected {n_input %u, alias_entries %llu}",
                   r->name, h[ne].v, h[ne].start, db->n_input, (unsigned long long)db->alias_entries);
    for (uint64_t i = 0; i < db->alias_entries; ++i)
        if (db->alias_list[i] >= db->nv)
            return BAD(r, "%s: section 'alias_list': entry %llu is vertex %u (n_vertices %u)", r->name,
                       (unsigned long long)i, db->alias_list[i], db->nv);
    return check_padding(r, GS__SEC_ALIAS_LIST, 4 * db->alias_entries);
}

/* ---- records: every block and value (verify) --------------------------- */

/* Vertex x's record: its minima, then one well-formed block per reachable
 * function (closed as its curve, sampled as the build, coefficients in
 * range, dip values finite, the minimum at most the stored function's
 * values on the curve's grid), then zero padding below 8 bytes. */
static int check_record(reader *r, uint32_t x, uint32_t *path)
{
    gs_db *db = r->db;
    const unsigned char *end, *p = gs__db_record(db, x, &end);
    uint32_t l = db->leaf[x], n = 0;
    if (l == GS_NONE) {
        if (p != end) return BAD(r, "%s: section 'records': unreferenced vertex %u has a record", r->name, x);
        return GS_OK;
    }
    uint64_t nf = db->nodes[l].curve_prefix, k = 0;
    const unsigned char *q = p + GS__DB_MIN_BYTES * nf;
    for (uint32_t a = db->nodes[l].parent; a != GS_NONE; a = db->nodes[a].parent) path[n++] = a;
    while (n--) {
        const gs__db_node *a = &db->nodes[path[n]];
        for (uint32_t j = 0; j < a->n_curves; ++j, ++k) {
            const gs__db_disk_curve *cv = &db->curves[a->curve_start + j];
            float mv = gs__db_min_get(p, k);
            if (mv != mv)
                return BAD(r, "%s: section 'records': vertex %u, function %llu: minimum %g", r->name, x,
                           (unsigned long long)k, mv);
            if (mv == INFINITY) continue;
            gs__db_fblock b;
            if (!gs__db_fblock_parse(q, (uint64_t)(end - q), &b))
                return BAD(r, "%s: section 'records': vertex %u, function %llu: malformed block at byte %llu", r->name,
                           x, (unsigned long long)k, (unsigned long long)(q - db->records));
            int sampled = (db->build_flags & GS__DB_BUILD_SAMPLED) != 0;
            if (b.closed != cv->closed || (int)b.sampled != sampled || (b.sampled && b.has_dip) ||
                (!b.sampled && !b.f32 && (b.e < GS__FB_EXP_MIN || b.e > GS__FB_EXP_MAX)))
                return BAD(r, "%s: section 'records': vertex %u, function %llu: closed %u (curve %u), sampled %u "
                              "(build %d), exponent %d",
                           r->name, x, (unsigned long long)k, b.closed, cv->closed, b.sampled, sampled, b.e);
            for (int i = 0; i < 4 && b.has_dip; ++i)
                if (!isfinite(b.dip[i]))
                    return BAD(r, "%s: section 'records': vertex %u, function %llu: dip value %g", r->name, x,
                               (unsigned long long)k, b.dip[i]);
            for (uint32_t i = 0; b.f32 && i <= b.degree; ++i) {
                float v = gs__ldf(b.coef + 4 * (size_t)i);
                if (!(fabsf(v) <= 1e30f))
                    return BAD(r, "%s: section 'records': vertex %u, function %llu: coefficient %u is %g", r->name, x,
                               (unsigned long long)k, i, v);
            }
            if (!b.sampled && b.degree >= cv->degree1)
                return BAD(r, "%s: section 'records': vertex %u, function %llu: degree %u, its curve's degree1 %u",
                           r->name, x, (unsigned long long)k, b.degree, cv->degree1);
            if (!b.sampled) { /* the quick reject's bound is one (on the query's grid) */
                double c[GS_FUN_MAX_DEGREE + 1];
                gs__db_fblock_coef(&b, c);
                gs__fun f = {GS_FUN_CHEBYSHEV, b.degree, b.squared, b.closed, b.shift, mv, c};
                const uint32_t g = gs__fun_grid_points(cv->degree1 - 1);
                for (uint32_t i = 0; i < g; ++i) {
                    double u = b.closed ? -1.0 + 2.0 * i / g : -1.0 + 2.0 * i / (g - 1);
                    double v = gs__fun_value(&f, u);
                    if (!(mv <= v * (1.0 + 1e-9) + 1e-300))
                        return BAD(r, "%s: section 'records': vertex %u, function %llu: minimum %.9g is above the "
                                      "function's value %.9g at u = %.6f (the quick reject would skip it)",
                                   r->name, x, (unsigned long long)k, mv, v, u);
                }
            }
            q += b.bytes;
        }
    }
    if (end - q >= GS__DB_RECORD_UNIT)
        return BAD(r, "%s: section 'records': vertex %u's record has %lld bytes after its blocks", r->name, x,
                   (long long)(end - q));
    for (; q < end; ++q)
        if (*q) return BAD(r, "%s: section 'records': vertex %u's padding is not zero", r->name, x);
    return GS_OK;
}

static int check_values(reader *r)
{
    gs_db *db = r->db;
    for (uint32_t x = 0; x < db->nv; ++x)
        for (int i = 0; i < 3; ++i)
            if (!isfinite(db->xyz[3 * (size_t)x + i]))
                return BAD(r, "%s: section 'positions': vertex %u has a non-finite coordinate", r->name, x);
    uint32_t *path = gs__malloc((size_t)db->max_depth + 1, sizeof *path);
    if (!path) return gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    int rc = GS_OK;
    uint64_t nfun = 0;
    for (uint32_t x = 0; x < db->nv; ++x)
        if (db->leaf[x] != GS_NONE) {
            if (db->nodes[db->leaf[x]].depth > db->max_depth) {
                rc = BAD(r, "%s: header: max_depth %u but vertex %u's leaf has depth %u", r->name, db->max_depth, x,
                         db->nodes[db->leaf[x]].depth);
                break;
            }
            nfun += db->nodes[db->leaf[x]].curve_prefix;
        }
    if (!rc && nfun != db->n_functions)
        rc = BAD(r, "%s: header: n_functions %llu but the vertices have %llu", r->name,
                 (unsigned long long)db->n_functions, (unsigned long long)nfun);
    for (uint32_t x = 0; x < db->nv && !rc; ++x) rc = check_record(r, x, path);
    free(path);
    if (!rc) rc = check_leaf_values(r);
    if (!rc) rc = gs__db_near_verify(&db->near, db->nv, db->version, r->name, r->err);
    return rc;
}

/* ---- attach ------------------------------------------------------------- */

static void set_pointers(reader *r)
{
    gs_db *db = r->db;
    db->xyz = (const double *)r->sec[GS__SEC_POSITIONS];
    db->leaf = (const uint32_t *)r->sec[GS__SEC_LEAVES];
    db->nodes = (const gs__db_node *)r->sec[GS__SEC_NODES];
    db->curves = (const gs__db_disk_curve *)r->sec[GS__SEC_CURVES];
    db->index = (const uint32_t *)r->sec[GS__SEC_INDEX];
    db->records = r->sec[GS__SEC_RECORDS];
    if (db->flags & GS__DB_FLAG_LEAF_EXACT) {
        db->leaf_nodes = (const gs__db_leaf_node *)r->sec[GS__SEC_LEAF_NODES];
        if (db->flags & GS__DB_FLAG_LEAF_LOCAL16) db->leaf_local16 = (const uint16_t *)r->sec[GS__SEC_LEAF_LOCAL];
        else db->leaf_local8 = r->sec[GS__SEC_LEAF_LOCAL];
        db->leaf_q = (const uint16_t *)r->sec[GS__SEC_LEAF_Q];
    }
    if (db->flags & GS__DB_FLAG_ALIASES) {
        db->alias_index = (const gs__db_alias_head *)r->sec[GS__SEC_ALIAS_INDEX];
        db->alias_list = (const uint32_t *)r->sec[GS__SEC_ALIAS_LIST];
    } else {
        db->n_input = db->nv;
    }
}

/* In the order of doc/database-format.md "Validation": the structure
 * always (O(sections + nodes + curves + vertices), no checksum but the
 * header's), the checksums and every value with verify. */
static int validate(reader *r, const unsigned char *b, uint64_t size, int verify)
{
    int rc = check_ident(r, b, size);
    if (!rc) read_header(r->db, b), rc = check_header(r, b, size);
    if (!rc) rc = check_counts(r);
    if (!rc) rc = check_table(r, b, size, verify);
    if (rc) return rc;
    set_pointers(r);
    uint32_t *n_children = gs__calloc(r->db->n_nodes, sizeof *n_children);
    if (!n_children) return gs__fail(r->err, GS_ENOMEM, "%s: out of memory", r->name);
    rc = check_nodes(r, n_children);
    if (!rc) rc = check_curves(r);
    if (!rc) rc = check_leaves(r, n_children);
    free(n_children);
    if (!rc) rc = check_index(r);
    if (!rc) rc = check_leaf_structure(r);
    if (!rc) rc = check_aliases(r);
    if (!rc && r->sec[GS__SEC_NEAR])
        rc = gs__db_near_attach(r->sec[GS__SEC_NEAR], r->sec_size[GS__SEC_NEAR], r->db->nv, r->name, &r->db->near,
                                r->err);
    if (!rc && verify) rc = check_values(r);
    return rc;
}

int gs__db_attach(void *storage, size_t size, int mapped, const char *name, int verify, gs_db **out,
                  gs_error *err)
{
    *out = NULL;
    if (!gs__db_host_little_endian())
        return gs__fail(err, GS_EFORMAT, "%s: big-endian hosts cannot read geosep databases", name);
    if (((uintptr_t)storage & 7u) != 0) return gs__fail(err, GS_EINTERNAL, "%s: buffer not 8-byte aligned", name);
    gs_db *db = gs__calloc(1, sizeof *db);
    if (!db) return gs__fail(err, GS_ENOMEM, "%s: out of memory", name);
    reader r = {.db = db, .name = name, .err = err};
    int rc = validate(&r, storage, size, verify);
    if (rc) {
        free(db);
        return rc;
    }
    db->storage = storage;
    db->storage_size = size;
    db->mapped = mapped;
    db->bytes = storage;
    db->size = size;
    *out = db;
    return GS_OK;
}

/* ---- public entry points ------------------------------------------------- */

int gs_db_open_ex(const char *path, unsigned flags, gs_db **out, gs_error *err)
{
    if (!path || !out) return gs__fail(err, GS_EARG, "gs_db_open: NULL argument");
    *out = NULL;
    if (flags & ~(unsigned)GS_DB_OPEN_VERIFY) return gs__fail(err, GS_EARG, "gs_db_open_ex: unknown flags 0x%X", flags);
    int fd = open(path, O_RDONLY);
    if (fd < 0) return gs__fail(err, GS_EIO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return gs__fail(err, GS_EIO, "%s: not a regular file", path);
    }
    if ((uint64_t)st.st_size < GS__DB_HEADER_BYTES) {
        close(fd);
        return gs__fail(err, GS_EPARSE, "%s: header: file has %llu bytes, a database has at least %u", path,
                        (unsigned long long)st.st_size, GS__DB_HEADER_BYTES);
    }
    size_t size = (size_t)st.st_size;
    void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (map == MAP_FAILED) return gs__fail(err, GS_EIO, "%s: cannot map: %s", path, strerror(errno));
    int rc = gs__db_attach(map, size, 1, path, (flags & GS_DB_OPEN_VERIFY) != 0, out, err);
    if (rc) munmap(map, size);
    return rc;
}

int gs_db_open(const char *path, gs_db **out, gs_error *err)
{
    return gs_db_open_ex(path, 0, out, err);
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

int gs_db_verify(const gs_db *db, gs_error *err)
{
    if (!db) return gs__fail(err, GS_EARG, "gs_db_verify: NULL argument");
    gs_db tmp;
    memset(&tmp, 0, sizeof tmp);
    reader r = {.db = &tmp, .name = "database", .err = err};
    return validate(&r, db->bytes, db->size, 1);
}

void gs_db_free(gs_db *db)
{
    if (!db) return;
    if (db->derived) db->derived->free(db->derived);
    if (db->mapped) munmap(db->storage, db->storage_size);
    else free(db->storage);
    free(db);
}

int gs_db_get_info(const gs_db *db, gs_db_info *info, gs_error *err)
{
    if (!db || !info) return gs__fail(err, GS_EARG, "gs_db_get_info: NULL argument");
    memset(info, 0, sizeof *info);
    info->format_version = db->version;
    info->n_vertices = db->nv;
    info->n_nodes = db->n_nodes;
    info->n_leaves = db->n_leaves;
    info->n_curves = db->n_curves;
    info->n_functions = db->n_functions;
    info->avg_depth = db->avg_depth;
    info->max_depth = db->max_depth;
    info->cost = db->cost;
    info->file_bytes = db->size;
    info->bytes_per_vertex = (double)db->size / db->nv;
    info->records_bytes = db->records_bytes;
    info->method = (gs_method)db->method;
    info->vmax = db->vmax;
    info->mmax = db->mmax;
    info->tol = db->tol;
    info->vertex_sources = (db->build_flags & GS__DB_BUILD_VERTEX_SOURCES) != 0;
    info->sampled = (db->build_flags & GS__DB_BUILD_SAMPLED) != 0;
    info->leaf_exact = db->leaf_nodes != NULL;
    info->near_radius = db->near.start ? db->near.radius : 0.0;
    info->n_near_pairs = db->near.n;
    info->near_bytes = db->near.start ? gs__db_near_bytes(db->nv, db->near.n) : 0;
    info->sample_spacing = db->sample_spacing;
    info->seed = db->seed;
    info->max_samples = db->max_samples;
    info->solver.heat_time = db->heat_time;
    info->solver.fmm_exact_start = db->fmm_exact_start;
    info->solver.dgg_eps = db->dgg_eps;
    info->solver.heat_refine = (db->build_flags & GS__DB_BUILD_HEAT_REFINE_MASK) >> GS__DB_BUILD_HEAT_REFINE_SHIFT;
    return GS_OK;
}
