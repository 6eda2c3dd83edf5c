/* db_near.h - section 'near_pairs' (doc/database-format.md): the exact
 * distances of the near cross-leaf pairs whose separator answer is off by
 * more than the build's near tolerance (issue 17: the pairs a few edges
 * apart on either side of a separator curve). Its writer, its checks (the
 * structure at open, every value by verify) and the query's lookup, kept
 * apart from the rest of the format. Internal.
 *
 * Layout (little-endian, 8-byte aligned, inside the section):
 *   0   f64 radius   the build looked at every pair with exact d < radius;
 *                    a stored pair has d < radius, so Euclidean >= radius
 *                    means "not stored" (the query's early-out)
 *   8   f64 step     a stored distance is q * step * 2^-shift (q: u16;
 *                    shift: u8, format 6; 0 in format 5, whose steps were
 *                    too coarse for pairs far nearer than the radius)
 *   16  u64 n        entries
 *   24  u32 bits     log2 of the vertices per bucket (GS__NEAR_BUCKET_BITS)
 *   28  u32 0
 *   32  u32 start[nb + 1], nb = ceil(nv / 2^bits): bucket b's entries are
 *       [start[b], start[b+1]); start[0] = 0, start[nb] = n; zero padding
 *       to 8 bytes
 *   then n entries of 8 bytes: u32 y, u16 q, u8 xlow, u8 shift - the pair
 *       (x, y), x = b 2^bits + xlow < y, sorted by (xlow, y) in a bucket,
 *       each pair once (at its smaller vertex). */
#ifndef GS_DB_NEAR_H
#define GS_DB_NEAR_H

#include "format.h"

#define GS__NEAR_BUCKET_BITS 4u
#define GS__NEAR_HEAD 32u
#define GS__NEAR_QMAX 65535u
#define GS__NEAR_SHIFT_MAX 64u /* format 6: q's relative step <= 2^-15 for d >= radius 2^-64 */

/* The section as the query reads it (in place; start NULL: no section). */
typedef struct gs__db_near {
    double radius, step;
    double radius2;            /* radius^2 (0 without the section)        */
    uint64_t n;
    uint32_t nb;
    const uint32_t *start;
    const unsigned char *ent;
} gs__db_near;

/* A pair the builder hands to the writer: x < y, exact distance d < radius. */
typedef struct gs__near_pair {
    uint32_t x, y;
    double d;
} gs__near_pair;

/* The section's size in bytes for nv vertices and n entries (0 if absurd). */
uint64_t gs__db_near_bytes(uint32_t nv, uint64_t n);

/* Write the section for p[0..n) (sorted by x, then y; x < y < nv,
 * 0 <= d < radius) into sec (gs__db_near_bytes(nv, n) zeroed bytes), in
 * format GS__DB_VERSION: each distance to 16 significant bits (relative
 * error <= 2^-16) down to radius 2^-64. */
void gs__db_near_write(unsigned char *sec, uint32_t nv, double radius, const gs__near_pair *p, uint64_t n);

/* Structure at open, O(nv / 16): the head, the size, the bucket starts
 * (what keeps every lookup inside the section). Fills *out. */
int gs__db_near_attach(const unsigned char *sec, uint64_t size, uint32_t nv, const char *name, gs__db_near *out,
                       gs_error *err);

/* Every entry (gs_db_verify): x < y < nv, sorted in its bucket, shift at
 * most GS__NEAR_SHIFT_MAX (0 in format 5); any q: q * step <= radius by
 * the head's check. version: the file's format version. */
int gs__db_near_verify(const gs__db_near *nr, uint32_t nv, uint32_t version, const char *name, gs_error *err);

/* The stored distance of the pair (x, y), x < y, if stored: 1 and *d. */
static inline int gs__db_near_find(const gs__db_near *nr, uint32_t x, uint32_t y, double *d)
{
    uint32_t b = x >> GS__NEAR_BUCKET_BITS;
    uint32_t lo = nr->start[b], hi = nr->start[b + 1];
    uint64_t key = ((uint64_t)(x & ((1u << GS__NEAR_BUCKET_BITS) - 1)) << 32) | y;
    while (lo < hi) { /* the first entry >= key */
        uint32_t mid = lo + (hi - lo) / 2;
        const unsigned char *e = nr->ent + 8 * (size_t)mid;
        uint64_t k = ((uint64_t)e[6] << 32) | gs__get32(e);
        if (k < key) lo = mid + 1;
        else hi = mid;
    }
    if (lo == nr->start[b + 1]) return 0;
    const unsigned char *e = nr->ent + 8 * (size_t)lo;
    if (gs__get32(e) != y || e[6] != (x & ((1u << GS__NEAR_BUCKET_BITS) - 1))) return 0;
    uint16_t q;
    memcpy(&q, e + 4, 2);
    /* 2^-shift as a double's bits: exact for any byte (2^-255 is normal) */
    uint64_t bits = (uint64_t)(1023u - e[7]) << 52;
    double scale;
    memcpy(&scale, &bits, 8);
    *d = q * nr->step * scale;
    return 1;
}

#endif
