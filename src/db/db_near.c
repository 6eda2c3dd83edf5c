/* db_near.c - section 'near_pairs' (db_near.h, doc/database-format.md):
 * writer and checks. */
#include "db_near.h"

#include <math.h>

#define BAD(...) gs__fail(err, GS_EPARSE, __VA_ARGS__)
#define BUCKET (1u << GS__NEAR_BUCKET_BITS)

static uint32_t n_buckets(uint32_t nv)
{
    return (uint32_t)(((uint64_t)nv + BUCKET - 1) / BUCKET);
}

uint64_t gs__db_near_bytes(uint32_t nv, uint64_t n)
{
    if (n > ((uint64_t)1 << 58) || n > UINT32_MAX) return 0;
    return GS__NEAR_HEAD + gs__pad8(4 * ((uint64_t)n_buckets(nv) + 1)) + 8 * n;
}

void gs__db_near_write(unsigned char *sec, uint32_t nv, double radius, const gs__near_pair *p, uint64_t n)
{
    uint32_t nb = n_buckets(nv);
    gs__putf64(sec, radius);
    gs__putf64(sec + 8, radius / GS__NEAR_QMAX);
    gs__put64(sec + 16, n);
    gs__put32(sec + 24, GS__NEAR_BUCKET_BITS);
    unsigned char *start = sec + GS__NEAR_HEAD, *ent = start + gs__pad8(4 * ((uint64_t)nb + 1));
    uint64_t k = 0;
    double step = radius / GS__NEAR_QMAX;
    for (uint32_t b = 0; b <= nb; ++b) {
        while (k < n && p[k].x >> GS__NEAR_BUCKET_BITS < b) ++k;
        gs__put32(start + 4 * (uint64_t)b, (uint32_t)k);
    }
    for (k = 0; k < n; ++k) {
        unsigned char *e = ent + 8 * k;
        /* the largest shift that keeps d 2^shift / step within 16 bits:
         * then q >= 2^15 (d >= radius 2^-64), 16 significant bits */
        double r = p[k].d / step;
        uint32_t shift = 0;
        while (r > 0 && shift < GS__NEAR_SHIFT_MAX && 2.0 * r <= GS__NEAR_QMAX) r *= 2.0, ++shift;
        double q = nearbyint(r);
        uint16_t qq = (uint16_t)(q > GS__NEAR_QMAX ? GS__NEAR_QMAX : (q < 0 ? 0 : q));
        gs__put32(e, p[k].y);
        memcpy(e + 4, &qq, 2);
        e[6] = (unsigned char)(p[k].x & (BUCKET - 1));
        e[7] = (unsigned char)shift;
    }
}

int gs__db_near_attach(const unsigned char *sec, uint64_t size, uint32_t nv, const char *name, gs__db_near *out,
                       gs_error *err)
{
    memset(out, 0, sizeof *out);
    if (size < GS__NEAR_HEAD)
        return BAD("%s: section 'near_pairs': %llu bytes, less than its %u-byte head", name, (unsigned long long)size,
                   GS__NEAR_HEAD);
    double radius = gs__getf64(sec), step = gs__getf64(sec + 8);
    uint64_t n = gs__get64(sec + 16);
    uint32_t bits = gs__get32(sec + 24), nb = n_buckets(nv);
    if (!(radius > 0 && radius <= 1e100) || !(step > 0 && step * GS__NEAR_QMAX <= radius * (1 + 1e-12)))
        return BAD("%s: section 'near_pairs': radius %g, step %g (radius in (0, 1e100], 0 < step <= radius / %u)",
                   name, radius, step, GS__NEAR_QMAX);
    if (bits != GS__NEAR_BUCKET_BITS || gs__get32(sec + 28) != 0)
        return BAD("%s: section 'near_pairs': bucket bits %u, reserved %u (expected %u, 0)", name, bits,
                   gs__get32(sec + 28), GS__NEAR_BUCKET_BITS);
    uint64_t want = gs__db_near_bytes(nv, n);
    if (!want || want != size)
        return BAD("%s: section 'near_pairs': %llu bytes, but %llu entries for %u vertices need %llu", name,
                   (unsigned long long)size, (unsigned long long)n, nv, (unsigned long long)want);
    const uint32_t *start = (const uint32_t *)(const void *)(sec + GS__NEAR_HEAD);
    if (start[0] != 0 || start[nb] != n)
        return BAD("%s: section 'near_pairs': bucket starts run from %u to %u (expected 0 to %llu)", name, start[0],
                   start[nb], (unsigned long long)n);
    for (uint32_t b = 0; b < nb; ++b)
        if (start[b + 1] < start[b])
            return BAD("%s: section 'near_pairs': bucket %u starts at %u, after bucket %u's %u", name, b + 1,
                       start[b + 1], b, start[b]);
    for (uint64_t i = 4 * ((uint64_t)nb + 1); i < gs__pad8(4 * ((uint64_t)nb + 1)); ++i)
        if (sec[GS__NEAR_HEAD + i]) return BAD("%s: section 'near_pairs': padding byte is not zero", name);
    out->radius = radius;
    out->radius2 = radius * radius;
    out->step = step;
    out->n = n;
    out->nb = nb;
    out->start = start;
    out->ent = sec + GS__NEAR_HEAD + gs__pad8(4 * ((uint64_t)nb + 1));
    return GS_OK;
}

int gs__db_near_verify(const gs__db_near *nr, uint32_t nv, uint32_t version, const char *name, gs_error *err)
{
    if (!nr->start) return GS_OK;
    for (uint32_t b = 0; b < nr->nb; ++b) {
        uint64_t prev = 0;
        for (uint32_t i = nr->start[b]; i < nr->start[b + 1]; ++i) {
            const unsigned char *e = nr->ent + 8 * (size_t)i;
            uint32_t y = gs__get32(e), xl = e[6];
            uint64_t x = (uint64_t)b * BUCKET + xl, key = ((uint64_t)xl << 32) | y;
            uint32_t shift_max = version >= 6 ? GS__NEAR_SHIFT_MAX : 0;
            if (xl >= BUCKET || e[7] > shift_max || x >= y || y >= nv)
                return BAD("%s: section 'near_pairs': entry %u is the pair (%llu, %u) with shift %u "
                           "(needs x < y < %u, shift <= %u in format %u)",
                           name, i, (unsigned long long)x, y, e[7], nv, shift_max, version);
            if (i > nr->start[b] && key <= prev)
                return BAD("%s: section 'near_pairs': entry %u (%llu, %u) is not after the entry before it", name, i,
                           (unsigned long long)x, y);
            prev = key;
        }
    }
    return GS_OK;
}
