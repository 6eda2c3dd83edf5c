/* db_internal.h - the opened database (struct gs_db) and the on-disk layout
 * constants of doc/database-format.md; the packer the builder calls (paper
 * sec. 3.1: what is stored per vertex). Internal. */
#ifndef GS_DB_INTERNAL_H
#define GS_DB_INTERNAL_H

#include "db_content.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#define GS_DB_MAGIC "GSEPDB\0\0"
#define GS_DB_VERSION 2u
#define GS_DB_ENDIAN_TAG 0x0A0B0C0Du
#define GS_DB_HEADER_BYTES 160u
#define GS_DB_CHECKSUM_AT 152u /* header_checksum: the header's last field */
#define GS_DB_ENTRY_BYTES 32u
#define GS_DB_FLAG_LEAF_EXACT 1u
#define GS_DB_BUILD_VERTEX_SOURCES 1u
#define GS_DB_BUILD_SAMPLED 2u
/* bits 2-3: gs_solver_options.heat_refine (0 in files written before it) */
#define GS_DB_BUILD_HEAT_REFINE_SHIFT 2
#define GS_DB_BUILD_HEAT_REFINE_MASK (3u << GS_DB_BUILD_HEAT_REFINE_SHIFT)
_Static_assert(GS_HEAT_REFINE_MAX <= 3, "heat_refine must fit build_flags bits 2-3");
#define GS_DB_MAX_SAMPLED 65535u
#define GS_DB_MAX_SHIFT 2.0
/* |coefficient| and |sample| at most this: the query's minimiser then never
 * overflows (values, slopes and curvatures of a degree-24 series stay below
 * 1e108, their squares and products finite); larger finite values made it
 * compute inf - inf = NaN (and index outside its window on NaN slopes). */
#define GS_DB_MAX_COEF 1e100

enum {
    GS_SEC_POSITIONS = 1,
    GS_SEC_LEAVES,
    GS_SEC_NODES,
    GS_SEC_CURVES,
    GS_SEC_VERTEX_DIR,
    GS_SEC_FUNCTIONS,
    GS_SEC_WORDS,
    GS_SEC_LEAF_VSTART,
    GS_SEC_LEAF_LOCAL,
    GS_SEC_LEAF_DSTART,
    GS_SEC_LEAF_DIST,
    GS_SEC_COUNT_BASE = 7,
    GS_SEC_COUNT_FULL = 11
};

/* Function meta word (doc: "meta"). */
#define GS_META_DEGREE(m) ((m) & 0xFFFFu)
#define GS_META_KIND(m) (((m) >> 16) & 3u)
#define GS_META_SQUARED(m) (((m) >> 18) & 1u)
#define GS_META_CLOSED(m) (((m) >> 19) & 1u)
#define GS_META_UNKNOWN_BITS 0xFFF00000u

/* On-disk records, used in place (little-endian hosts only). */
typedef struct gs_db_disk_curve {
    uint32_t node, closed, n_samples, reserved;
    double length;
} gs_db_disk_curve;

typedef struct gs_db_vdir {
    uint64_t first_function;
    uint64_t first_word;
} gs_db_vdir;

typedef struct gs_db_fentry {
    double minval;
    uint32_t word_offset;
    uint32_t meta;
} gs_db_fentry;

struct gs_db {
    /* storage: either a mapping (munmap) or a malloc'ed buffer (free) */
    void *storage;
    size_t storage_size;
    int mapped;
    const unsigned char *bytes; /* the whole file                         */
    uint64_t size;
    /* header */
    uint32_t nv, n_nodes, n_curves, n_leaves, max_depth;
    uint64_t n_functions, n_words, leaf_entries;
    uint32_t flags, build_flags, method, vmax, mmax;
    double avg_depth, tol, cost;
    double sample_spacing, heat_time, fmm_exact_start;
    uint32_t seed, max_samples;
    /* sections, in place */
    const double *xyz;
    const uint32_t *leaf;
    const gs_db_node *nodes;
    const gs_db_disk_curve *curves;
    const gs_db_vdir *vdir;
    const gs_db_fentry *funs;
    const double *words;
    const uint32_t *leaf_vstart, *leaf_local; /* NULL without leaf tables */
    const uint64_t *leaf_dstart;
    const double *leaf_dist;
    /* Query cache (memory only, built at open, src/query/grid.c), so that
     * a query touches few cache lines and waits for memory at most twice:
     * - per vertex x a slot of qslot doubles at qroot + x qslot (an address
     *   known from x alone): its header (gs_qvert: where its block starts,
     *   its leaf, nf, ns, the leaf's ancestors), its coordinates (large
     *   caches, at GS_QSLOT_XYZ), the entries of its first ns
     *   functions, those of the curves of its ancestors shallower than
     *   qlev (from slot + GS_QSLOT_HEAD, room for qnroot), and their
     *   records (layout below; curve c's at slot + GS_QSLOT_HEAD +
     *   gs__qent_doubles(qnroot) + qcoff[c]). Pairs whose lowest common
     *   ancestor is that
     *   shallow (most random pairs) need nothing else. qlev is
     *   GS_QSLOT_LEVELS for caches over GS_QSLOT_MIN_BYTES (measured: the
     *   slots gain ~15% on homer-60k's 356 MB, lose ~10% on bunny-5k's 20
     *   MB), else 0 (a slot is then the header's first 16 bytes only:
     *   start, leaf, nf, which stay in cache for small meshes);
     * - its block at qbuf + start: all nf = nodes[leaf].curve_prefix entries
     *   (root's curves first, as in the file), then the records of the other
     *   curves, curve c's at block + gs__qent_doubles(nf) + qcoff[c], an
     *   offset that does not depend on x (records are sized per curve), so
     *   that a query can fetch the records it will likely need before it
     *   reads the entries.
     * An entry is a function's minval as a float, rounded down (FLT_MAX
     * for larger ones; +inf: unreachable): all the quick reject needs, in 4
     * bytes (the file's 16-byte entry costs a query 3 lines on bunny-5k, 1
     * this way). NULL when not built (queries then read the file's
     * sections). */
    double *qroot;            /* (nv + 1) slots; slot nv: the end, header  */
    double *qbuf;
    uint32_t qslot;           /* doubles per slot (a multiple of 8)        */
    uint32_t qslot0;          /* its head: header, entries and the root's  */
                              /*   records (doubles)                       */
    uint32_t qnroot;          /* room for entries in a slot (the most ns)  */
    uint32_t qlev;            /* the slots hold the curves of depth < qlev */
    uint32_t qhead;           /* qlev 0: the root's first record's size    */
    uint32_t *qcoff;          /* n_curves                                  */
    uint32_t *qclen;          /* n_curves: a record's size (doubles)       */
    uint32_t *qgrid;          /* n_curves: grid points (0: no grid)        */
    uint64_t qsize;           /* doubles in qbuf                           */
};

/* A slot's header (one 64-byte line): where the vertex's block starts,
 * its leaf (a copy of the file's), nf, and the leaf's ancestors by depth
 * down to depth GS_QANC - 1, so that the lowest common ancestor of two
 * vertices comes from their headers without walking the tree. */
#define GS_QANC 11
#define GS_QSLOT_XYZ 8   /* a large cache's slot: the vertex's coordinates */
                          /*   after the header (its second line), so     */
                          /*   that the Euclidean bound costs no miss     */
#define GS_QSLOT_HEAD 12 /* doubles before the entries: header, xyz, pad */
#define GS_QSLOT_LEVELS 2 /* a large cache's slots hold depths 0 and 1   */
#define GS_QSLOT_MIN_BYTES ((uint64_t)64 << 20) /* "large": blocks above   */
/* The threshold gs_db_open uses, GS_QSLOT_MIN_BYTES unless a test lowers it
 * (tests only, before opening, single-threaded: 0 gives every database the
 * large-cache slots so that small test databases exercise that layout). */
extern uint64_t gs__qslot_min_bytes;
typedef struct gs_qvert {
    uint64_t start;         /* in doubles from qbuf                         */
    uint32_t leaf;          /* leaf node, GS_NONE: no face                  */
    uint32_t nf;            /* functions: nodes[leaf].curve_prefix (0 for   */
                            /*   GS_NONE)                                   */
    uint32_t ns;            /* the first ns of them are in the slot         */
    uint32_t anc[GS_QANC];  /* anc[d]: the leaf's ancestor at depth d (the  */
                            /*   root at 0, the leaf at its own depth),     */
                            /*   GS_NONE deeper                             */
} gs_qvert;

/* Doubles of n entries (floats). */
static inline uint64_t gs__qent_doubles(uint64_t n)
{
    return (n + 1) / 2;
}

/* Where curve c's record starts, in doubles: from the slot for a curve of
 * depth < qlev, from the block of a vertex with nf functions otherwise. */
static inline size_t gs__qrec_in_slot(const gs_db *db, uint32_t c)
{
    return GS_QSLOT_HEAD + gs__qent_doubles(db->qnroot) + db->qcoff[c];
}

static inline size_t gs__qrec_in_block(const gs_db *db, uint64_t nf, uint32_t c)
{
    return gs__qent_doubles(nf) + db->qcoff[c];
}

/* The cache's copy of the meta word also holds, in bits the file leaves
 * zero, a loop's seam cell on its curve's grid (gs_fun_seam_cell; all
 * ones: none), so that queries need not find it again. */
#define GS_QREC_SEAM_SHIFT 20
#define GS_QREC_NO_CELL 0xFFu
#define GS_QREC_SEAM_CELL(m) (((m) >> GS_QREC_SEAM_SHIFT) & GS_QREC_NO_CELL)

/* A reachable function's record (none for unreachable ones), doubles:
 *   [0]    shift (loops; 0 for paths)
 *   [1]    float: the dip's u (gs_fun_dip; NaN: not sharp), then uint32:
 *          the meta word, as in the file (degree, kind, squared, closed),
 *          with the seam cell in bits 20-27 (GS_QREC_SEAM_CELL)
 *   [2]    two floats: the dip's lo - u and hi - u
 *   [3]    two floats: the dip's slope, and a loop's seam value rounded
 *          down (NaN for paths)
 *   [4]    two floats: the grid's base and step (gs_fun_grid)
 *   [5]    minval, as in the file
 *   [6..]  g uint16 (g = qgrid[curve]): the values on the curve's uniform grid in u (paths:
 *          u_j = -1 + 2j/(g-1); loops: u_j = -1 + 2j/g), quantised
 *          (gs_fun_grid_fill), padded to a multiple of 8
 *   then   the degree+1 coefficients (or samples)
 * Every record of a curve has the same size (room for its largest degree). */
#define GS_QREC_HEAD 6u

static inline uint32_t gs__qrec_meta(const double *rec)
{
    uint32_t m;
    __builtin_memcpy(&m, (const char *)(rec + 1) + 4, 4);
    return m;
}

static inline void gs__qrec_dip(const double *rec, gs_fun_dip *d)
{
    float f[5];
    __builtin_memcpy(f, rec + 1, 4);
    __builtin_memcpy(f + 1, rec + 2, 16);
    d->u = f[0];
    d->lo = d->u + f[1];
    d->hi = d->u + f[2];
    d->slope = f[3];
    d->seam = f[4];
    uint32_t c = GS_QREC_SEAM_CELL(gs__qrec_meta(rec));
    d->seam_cell = c == GS_QREC_NO_CELL ? GS_FUN_NO_CELL : c;
}

/* Doubles of a record's grid of g points. */
static inline uint32_t gs__qrec_grid_doubles(uint32_t g)
{
    return gs_fun_grid_padded(g) / 4u;
}

static inline gs_fun_grid gs__qrec_values(const double *rec)
{
    gs_fun_grid v;
    float bs[2];
    __builtin_memcpy(bs, rec + 4, 8);
    v.q = (const uint16_t *)(rec + GS_QREC_HEAD);
    v.base = bs[0], v.step = bs[1];
    return v;
}

static inline const double *gs__qrec_coef(const double *rec, uint32_t g)
{
    return rec + GS_QREC_HEAD + gs__qrec_grid_doubles(g);
}

/* Build the query cache (called once the database is validated); name
 * prefixes its messages. */
int gs__db_grid_build(gs_db *db, const char *name, gs_error *err);
void gs__db_grid_free(gs_db *db);

/* Serialise c into the on-disk layout and open the result through the
 * file reader's validation. *out: new database (gs_db_free). */
int gs_db_pack(const gs_db_content *c, gs_db **out, gs_error *err);

/* Validate `size` bytes and wrap them in a database, with the query cache
 * unless cache is 0 (queries then read the sections). On success the
 * database owns `storage` (munmap'ed if mapped, else freed); on failure the
 * caller keeps it. `name` prefixes messages ("db.gsdb: ..."). */
int gs__db_attach(void *storage, size_t size, int mapped, const char *name, int cache, gs_db **out,
                  gs_error *err);

/* The format's 64-bit checksum (doc/database-format.md "Checksum") of the
 * concatenation of a and b (b may be NULL with nb == 0). */
uint64_t gs__db_checksum(const void *a, size_t na, const void *b, size_t nb);

/* Sizes in bytes of sections 1..11 (size[0] unused) from the header counts;
 * tables: leaf exact tables present (else size[8..11] = 0). Returns 0 if a
 * size would exceed 2^62 (the caller reports it). */
int gs__db_layout(uint32_t nv, uint32_t n_nodes, uint32_t n_curves, uint64_t n_functions,
                  uint64_t n_words, uint64_t leaf_entries, int tables, uint64_t size[12]);

/* 1 on little-endian hosts (the only ones that can use the format in place). */
int gs__db_host_little_endian(void);

/* Decode function i (< the leaf's curve_prefix) of vertex x. */
static inline void gs__db_fun(const gs_db *db, uint32_t x, uint64_t i, gs_fun *f)
{
    const gs_db_vdir *vd = &db->vdir[x];
    const gs_db_fentry *e = &db->funs[vd->first_function + i];
    const double *rec = db->words + vd->first_word + e->word_offset;
    uint32_t m = e->meta;
    f->kind = GS_META_KIND(m);
    f->degree = GS_META_DEGREE(m);
    f->squared = GS_META_SQUARED(m);
    f->closed = GS_META_CLOSED(m);
    f->minval = e->minval;
    if (e->minval == (double)INFINITY) { /* unreachable: empty record */
        f->shift = 0.0;
        f->coef = NULL;
        return;
    }
    f->shift = f->closed ? rec[0] : 0.0;
    f->coef = rec + f->closed;
}

#endif
