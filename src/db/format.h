/* format.h - the on-disk layout of a geosep database, format version 6
 * (doc/database-format.md): constants, header offsets, section ids and
 * sizes, the checksum, and the encoding of a separator distance function's
 * block (paper sec. 3.1 items 2-3, stored compactly). Shared by the writer
 * (db_write.c), the reader (db_read.c) and the query (src/query/), which
 * decodes blocks in place. Internal. */
#ifndef GS_DB_FORMAT_H
#define GS_DB_FORMAT_H

#include "../core/internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define GS__DB_MAGIC "GSEPDB\0\0"
#define GS__DB_VERSION 6u
#define GS__DB_VERSION_MIN 5u /* the oldest version read (5: near pairs without shifts) */
#define GS__DB_ENDIAN_TAG 0x0A0B0C0Du
#define GS__DB_HEADER_BYTES 184u
#define GS__DB_CHECKSUM_AT 176u /* header_checksum: the header's last field */
#define GS__DB_ENTRY_BYTES 32u
#define GS__DB_FLAG_LEAF_EXACT 1u   /* leaf tables: sections 7-9            */
#define GS__DB_FLAG_LEAF_LOCAL16 2u /* leaf_local holds u16 (else u8)       */
#define GS__DB_FLAG_ALIASES 4u      /* input-id aliases: sections 10-11     */
#define GS__DB_FLAG_NEAR 8u         /* near pairs: section 12 (db_near.h)   */
#define GS__DB_FLAGS_KNOWN 15u
#define GS__DB_BUILD_VERTEX_SOURCES 1u
#define GS__DB_BUILD_SAMPLED 2u
/* bits 2-3: gs_solver_options.heat_refine */
#define GS__DB_BUILD_HEAT_REFINE_SHIFT 2
#define GS__DB_BUILD_HEAT_REFINE_MASK (3u << GS__DB_BUILD_HEAT_REFINE_SHIFT)
_Static_assert(GS_HEAT_REFINE_MAX <= 3, "heat_refine must fit build_flags bits 2-3");
#define GS__DB_MAX_SAMPLED 65535u
#define GS__DB_MAX_SHIFT 2.0
/* Records are addressed in 2-byte units by a u32 (a record starts 2-byte
 * aligned: its u16 minima first): at most 8 GiB of them. */
#define GS__DB_RECORD_UNIT 2u
#define GS__DB_MAX_RECORDS_BYTES ((uint64_t)UINT32_MAX * GS__DB_RECORD_UNIT)

/* Header field offsets (doc: "Header"). */
enum {
    GS__H_VERSION = 8,
    GS__H_ENDIAN = 12,
    GS__H_FLAGS = 16,
    GS__H_HEADER_BYTES = 20,
    GS__H_FILE_BYTES = 24,
    GS__H_NV = 32,
    GS__H_NODES = 36,
    GS__H_CURVES = 40,
    GS__H_LEAVES = 44,
    GS__H_FUNCTIONS = 48,
    GS__H_RECORDS_BYTES = 56,
    GS__H_SECTIONS = 64,
    GS__H_MAX_DEPTH = 68,
    GS__H_AVG_DEPTH = 72,
    GS__H_METHOD = 80,
    GS__H_VMAX = 84,
    GS__H_MMAX = 88,
    GS__H_BUILD_FLAGS = 92,
    GS__H_TOL = 96,
    GS__H_LEAF_ENTRIES = 104,
    GS__H_COST = 112,
    GS__H_SPACING = 120,
    GS__H_SEED = 128,
    GS__H_MAX_SAMPLES = 132,
    GS__H_HEAT_TIME = 136,
    GS__H_FMM_START = 144,
    GS__H_DGG_EPS = 152,
    GS__H_N_INPUT = 160,
    GS__H_ALIAS_EXCEPTIONS = 164,
    GS__H_ALIAS_ENTRIES = 168
};

enum {
    GS__SEC_POSITIONS = 1,
    GS__SEC_LEAVES,
    GS__SEC_NODES,
    GS__SEC_CURVES,
    GS__SEC_INDEX,
    GS__SEC_RECORDS,
    GS__SEC_LEAF_NODES, /* flags bit 0 */
    GS__SEC_LEAF_LOCAL,
    GS__SEC_LEAF_Q,
    GS__SEC_ALIAS_INDEX, /* flags bit 2 */
    GS__SEC_ALIAS_LIST,
    GS__SEC_NEAR,        /* flags bit 3: near pairs (db_near.h)          */
    GS__SEC_MAX = GS__SEC_NEAR
};

/* Section names for messages, by id (0 unused). */
extern const char *const gs__db_section_name[GS__SEC_MAX + 1];

/* The ids of the sections a file with these header flags holds, in file
 * order (the section table lists exactly these); returns their number. */
uint32_t gs__db_section_ids(uint32_t flags, uint32_t ids[GS__SEC_MAX]);

/* A node's leaf table (section 'leaf_nodes', 16 bytes, in place): the
 * upper triangle of the n x n exact distances of its vertices (n = 0 for
 * internal nodes), each as its excess over the straight segment,
 * d = e + q scale / GS__DB_LEAF_QMAX with e = gs__db_segment(x, y), stored
 * as u16 q = round(GS__DB_LEAF_QMAX (d - e) / scale) at entries [qstart,
 * qstart + n (n - 1) / 2) of leaf_q; q = GS__DB_LEAF_QINF: +inf. */
typedef struct gs__db_leaf_node {
    uint64_t qstart;
    uint32_t n;
    float scale; /* the largest finite excess in the leaf, rounded up */
} gs__db_leaf_node;

/* The straight distance between two stored positions, as the writer and
 * the query compute it (symmetric bit for bit). */
static inline double gs__db_segment(const double *p, const double *q)
{
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}
#define GS__DB_LEAF_QMAX 65534u
#define GS__DB_LEAF_QINF 65535u
#define GS__DB_LEAF_MAX_SCALE 1e30

/* Entries of a leaf table of n vertices (n (n - 1) / 2), and where the
 * pair of local numbers i < j < n is in it. */
static inline uint64_t gs__db_leaf_tri(uint64_t n)
{
    return n ? n * (n - 1) / 2 : 0;
}
static inline uint64_t gs__db_leaf_at(uint64_t n, uint64_t i, uint64_t j)
{
    return i * n - i * (i + 1) / 2 + (j - i - 1);
}

/* An input vertex with aliases other than itself (section 'alias_index',
 * 8 bytes): its list is alias_list[start, next entry's start). */
typedef struct gs__db_alias_head {
    uint32_t v, start;
} gs__db_alias_head;

/* A node of the bisection tree (section 'nodes', 20 bytes, in place). */
typedef struct gs__db_node {
    uint32_t parent;       /* GS_NONE for the root (node 0)                 */
    uint32_t depth;
    uint32_t curve_start;  /* its separator's curves: [start, start+n)      */
    uint32_t n_curves;
    uint32_t curve_prefix; /* curves of all proper ancestors                */
} gs__db_node;

/* A curve (section 'curves', 24 bytes, in place). */
typedef struct gs__db_disk_curve {
    uint32_t node, closed, n_samples;
    uint32_t degree1; /* 1 + the highest degree of its Chebyshev functions */
                      /*   (0: none reachable, or sampled): the query's    */
                      /*   grid for the curve (gs__fun_grid_points)         */
    double length;
} gs__db_disk_curve;

/* ---- a vertex's minima (doc: "Records") ---------------------------------
 * One u16 per function: the minimum's float32 bits 30..15 (exponent and
 * the top 8 mantissa bits; minima are >= 0), rounded down, so that it
 * stays a lower bound; 0xFF00 is +inf (unreachable); a code above it is a
 * NaN (rejected by verify). */
#define GS__DB_MIN_BYTES 2u
#define GS__DB_MIN_INF 0xFF00u

static inline float gs__db_min_value(uint16_t q)
{
    uint32_t u = (uint32_t)q << 15;
    float v;
    memcpy(&v, &u, 4);
    return v;
}

/* The minimum of function k from a record's minima at p. */
static inline float gs__db_min_get(const unsigned char *p, uint64_t k)
{
    uint16_t q;
    memcpy(&q, p + GS__DB_MIN_BYTES * k, 2);
    return gs__db_min_value(q);
}

/* The code of the largest representable value <= v (v >= 0 or +inf; a
 * value <= 0 or NaN gives 0, +inf GS__DB_MIN_INF). */
static inline uint16_t gs__db_min_encode(double v)
{
    if (!(v > 0.0)) return 0;
    if (v > 3.4028234663852886e38) /* beyond FLT_MAX: FLT_MAX's code (its value is below it) */
        return v == INFINITY ? (uint16_t)GS__DB_MIN_INF : (uint16_t)(GS__DB_MIN_INF - 1);
    float f = (float)v;
    if (f > v) f = nextafterf(f, 0.0f);
    uint32_t u;
    memcpy(&u, &f, 4);
    return (uint16_t)(u >> 15); /* truncation: toward zero, i.e. down */
}

/* ---- a function's block (doc: "Records") --------------------------------
 * byte 0   meta: bits 0-4 degree code (0..24 Chebyshev degree; 31 sampled),
 *          bit 5 squared, bit 6 closed, bit 7 dip
 * byte 1   e: integer coefficients c_k = q_k * 2^e (-126 <= e <= 120), or
 *          GS__FB_F32 (-128): float32 coefficients
 * byte 2   w (integer coefficients only): the first w coefficients are
 *          int16, the other m+1-w int8 (0 <= w <= m+1)
 * then     u16 m (sampled only: m+1 values, 1 <= m <= 65535)
 *          f32 shift (closed only; |shift| <= 2)
 *          4 x f32 dip: u, lo - u, hi - u, slope (bit 7 only)
 *          the m+1 coefficients (or values): int16 then int8, or float32
 * Blocks are packed byte after byte (no alignment). */
#define GS__FB_DEG_MASK 0x1Fu
#define GS__FB_SAMPLED 31u
#define GS__FB_SQUARED 0x20u
#define GS__FB_CLOSED 0x40u
#define GS__FB_DIP 0x80u
#define GS__FB_F32 (-128)
#define GS__FB_EXP_MIN (-126)
#define GS__FB_EXP_MAX 120

/* A decoded block: what the query needs of one function. */
typedef struct gs__db_fblock {
    uint32_t degree, sampled, squared, closed, f32;
    uint32_t wide;     /* integer coefficients: how many are int16        */
    int e;
    double shift;
    float dip[4];      /* valid when has_dip                              */
    int has_dip;
    const unsigned char *coef; /* the raw coefficients                   */
    uint32_t bytes;    /* the whole block's size                          */
} gs__db_fblock;

static inline float gs__ldf(const unsigned char *p)
{
    float v;
    memcpy(&v, p, 4);
    return v;
}

/* Decode the block at p with `avail` bytes left in its record. Returns 0
 * when the block is malformed or runs past the record (the caller then
 * answers NaN: never reads outside the record). Reads only the header
 * fields; the coefficients stay at b->coef. */
static inline int gs__db_fblock_parse(const unsigned char *p, uint64_t avail, gs__db_fblock *b)
{
    if (avail < 2) return 0;
    uint32_t meta = p[0];
    int e = (int)(signed char)p[1];
    uint32_t code = meta & GS__FB_DEG_MASK, n = 2;
    /* the common block first, an integer path's (the query's hot path):
     * the same checks and fields as the general case below */
    if (avail >= 3 && code <= 24 && !(meta & GS__FB_CLOSED) && e != GS__FB_F32 && p[2] <= code + 1) {
        uint32_t w = p[2], h = meta & GS__FB_DIP ? 19 : 3, cb = code + 1 + w;
        if (avail < h + cb) return 0;
        b->degree = code, b->sampled = 0, b->squared = (meta & GS__FB_SQUARED) != 0, b->closed = 0;
        b->f32 = 0, b->wide = w, b->e = e, b->shift = 0.0, b->has_dip = (meta & GS__FB_DIP) != 0;
        if (b->has_dip) memcpy(b->dip, p + 3, 16);
        b->coef = p + h, b->bytes = h + cb;
        return 1;
    }
    b->sampled = code == GS__FB_SAMPLED;
    b->squared = (meta & GS__FB_SQUARED) != 0;
    b->closed = (meta & GS__FB_CLOSED) != 0;
    b->has_dip = (meta & GS__FB_DIP) != 0;
    b->f32 = e == GS__FB_F32;
    b->e = e;
    b->wide = 0;
    if (b->sampled) {
        uint16_t m;
        if (avail < 4) return 0;
        memcpy(&m, p + 2, 2);
        if (m < 1 || !b->f32) return 0;
        b->degree = m;
        n = 4;
    } else {
        if (code > 24) return 0;
        b->degree = code;
        if (!b->f32) {
            if (avail < 3 || p[2] > code + 1) return 0;
            b->wide = p[2];
            n = 3;
        }
    }
    b->shift = 0.0;
    if (b->closed) {
        if (avail < n + 4) return 0;
        float s = gs__ldf(p + n);
        if (!(fabsf(s) <= (float)GS__DB_MAX_SHIFT)) return 0;
        b->shift = s;
        n += 4;
    }
    if (b->has_dip) {
        if (avail < n + 16) return 0;
        memcpy(b->dip, p + n, 16);
        n += 16;
    }
    uint64_t cb = b->f32 ? (uint64_t)(b->degree + 1) * 4u : (uint64_t)b->degree + 1 + b->wide;
    if (avail < n + cb) return 0;
    b->coef = p + n;
    b->bytes = (uint32_t)(n + cb);
    return 1;
}

/* The size of the block at p (what gs__db_fblock_parse gives as bytes), 0
 * when gs__db_fblock_parse would refuse it: the query's walk over the
 * blocks before the one it needs, without decoding them. */
static inline uint32_t gs__db_fblock_size(const unsigned char *p, uint64_t avail)
{
    if (avail < 3) return 0; /* no block is shorter than 4 bytes */
    uint32_t meta = p[0], code = meta & GS__FB_DEG_MASK, n, cb;
    int e = (int)(signed char)p[1];
    if (code == GS__FB_SAMPLED) {
        uint16_t m;
        if (avail < 4) return 0;
        memcpy(&m, p + 2, 2);
        if (m < 1 || e != GS__FB_F32) return 0;
        n = 4, cb = 4 * ((uint32_t)m + 1);
    } else if (code > 24) {
        return 0;
    } else if (e == GS__FB_F32) {
        n = 2, cb = 4 * (code + 1);
    } else {
        if (p[2] > code + 1) return 0;
        n = 3, cb = code + 1 + p[2];
    }
    if (meta & GS__FB_CLOSED) {
        if (avail < n + 4) return 0;
        float s = gs__ldf(p + n);
        if (!(fabsf(s) <= (float)GS__DB_MAX_SHIFT)) return 0;
        n += 4;
    }
    if (meta & GS__FB_DIP) n += 16;
    return avail >= (uint64_t)n + cb ? n + cb : 0;
}

/* The integer coefficient q_k of a parsed integer block (k <= degree). */
static inline int gs__db_fblock_q(const gs__db_fblock *b, uint32_t k)
{
    if (k < b->wide) {
        int16_t q;
        memcpy(&q, b->coef + 2 * (size_t)k, 2);
        return q;
    }
    return (signed char)b->coef[b->wide + k];
}

/* 2^e for -126 <= e <= 120, without a call to ldexp. */
static inline double gs__db_pow2(int e)
{
    uint64_t bits = (uint64_t)(1023 + e) << 52;
    double s;
    memcpy(&s, &bits, sizeof s);
    return s;
}

/* The m+1 coefficients of a parsed block as doubles; 0 if a float32 one
 * is not finite or beyond 1e30, or the exponent is out of range (a corrupt
 * file: the caller answers NaN). */
static inline int gs__db_fblock_coef(const gs__db_fblock *b, double *c)
{
    uint32_t n = b->degree + 1;
    if (b->f32) {
        for (uint32_t k = 0; k < n; ++k) {
            float v = gs__ldf(b->coef + 4 * (size_t)k);
            if (!(fabsf(v) <= 1e30f)) return 0;
            c[k] = v;
        }
        return 1;
    }
    if (b->e < GS__FB_EXP_MIN || b->e > GS__FB_EXP_MAX) return 0;
    double s = gs__db_pow2(b->e);
    for (uint32_t k = 0; k < n; ++k) c[k] = gs__db_fblock_q(b, k) * s;
    return 1;
}

/* The header counts that size the sections. */
typedef struct gs__db_counts {
    uint32_t flags, nv, n_nodes, n_curves;
    uint64_t records_bytes, leaf_entries;
    uint32_t alias_exceptions;
    uint64_t alias_entries;
} gs__db_counts;

/* Sizes in bytes of sections 1..GS__SEC_MAX (size[0] unused) from the
 * header counts; 0 for the sections the flags leave out, and for
 * 'near_pairs', which describes its own size (db_near.h). Returns 0 if a
 * size would exceed 2^62. */
int gs__db_layout(const gs__db_counts *c, uint64_t size[GS__SEC_MAX + 1]);

/* The format's 64-bit checksum (doc "Checksum") of a then b (b may be NULL
 * with nb == 0). */
uint64_t gs__db_checksum(const void *a, size_t na, const void *b, size_t nb);

/* 1 on little-endian hosts (the only ones that use the format in place). */
int gs__db_host_little_endian(void);

static inline uint64_t gs__pad8(uint64_t b)
{
    return (b + 7) & ~(uint64_t)7;
}

static inline uint32_t gs__get32(const unsigned char *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}
static inline uint64_t gs__get64(const unsigned char *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}
static inline double gs__getf64(const unsigned char *p)
{
    double v;
    memcpy(&v, p, 8);
    return v;
}
static inline void gs__put16(unsigned char *p, uint16_t v)
{
    memcpy(p, &v, 2);
}
static inline void gs__put32(unsigned char *p, uint32_t v)
{
    memcpy(p, &v, 4);
}
static inline void gs__put64(unsigned char *p, uint64_t v)
{
    memcpy(p, &v, 8);
}
static inline void gs__putf64(unsigned char *p, double v)
{
    memcpy(p, &v, 8);
}

#endif
