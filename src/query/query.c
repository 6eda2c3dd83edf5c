/* query.c - online point-to-point queries (paper sec. 3.2, eq. 4-5, Theorem
 * 2.1): same leaf -> Euclidean (or the stored exact table); otherwise the
 * minimum over the curves of the common ancestors, with the quick reject on
 * the stored minima. Reads the file's records in place (format version 6):
 * each vertex's minima, then its functions' blocks, decoded as needed; the
 * two functions of a curve are tabulated on the pair's grid (pair_grid)
 * and their sum minimised (pair_min.c gs__fun_pair_min_grid_sum, or
 * gs__fun_pair_min_grid for loops). Every read stays inside
 * the vertex's record (a malformed block gives NaN). The hot path: no
 * allocation, no locks. */
#include "../db/db_internal.h"
#include "../fit/fun_internal.h"
#include "pair_grid.h"
#include "query_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

static double euclidean2(const gs_db *db, uint32_t x, uint32_t y)
{
    const double *p = db->xyz + 3 * (size_t)x, *q = db->xyz + 3 * (size_t)y;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

/* as gs__db_segment, bit for bit (sqrt of euclidean2) */
static double euclidean(const gs_db *db, uint32_t x, uint32_t y)
{
    return gs__db_segment(db->xyz + 3 * (size_t)x, db->xyz + 3 * (size_t)y);
}

/* Same leaf: the straight segment plus the stored table's 16-bit excess
 * (format: "Leaf exact tables"); the Euclidean distance without tables. In
 * bounds: local numbers < the leaf's n and its table inside leaf_q
 * (validated at open); i == j only for x == y, which callers answer 0
 * before. */
static double same_leaf(const gs_db *db, uint32_t l, uint32_t x, uint32_t y)
{
    double e = euclidean(db, x, y);
    if (!db->leaf_nodes) return e;
    const gs__db_leaf_node *t = &db->leaf_nodes[l];
    uint32_t i = gs__db_leaf_local(db, x), j = gs__db_leaf_local(db, y);
    if (i == j) return e;
    if (i > j) {
        uint32_t s = i;
        i = j, j = s;
    }
    uint32_t q = db->leaf_q[t->qstart + gs__db_leaf_at(t->n, i, j)];
    if (q == GS__DB_LEAF_QINF) return INFINITY;
    double excess = q * ((double)t->scale / GS__DB_LEAF_QMAX);
    return excess > 0 ? e + excess : e; /* never below the segment (a corrupt scale: still not) */
}

/* Lowest common ancestor: parents have smaller depth (validated), so both
 * walks end at the root at the latest. */
static uint32_t lowest_common_ancestor(const gs__db_node *nodes, uint32_t a, uint32_t b)
{
    while (nodes[a].depth > nodes[b].depth) a = nodes[a].parent;
    while (nodes[b].depth > nodes[a].depth) b = nodes[b].parent;
    while (a != b) a = nodes[a].parent, b = nodes[b].parent;
    return a;
}

/* Candidate curves of a query: the lower bound minval_x + minval_y of each
 * common curve, and the curve's function index. */
typedef struct candidate {
    double bound;
    uint32_t k, curve;
} candidate;

#define MAX_CANDIDATES 64

/* ---- a vertex's record: minima, then blocks ---- */

#define CURSOR_MAX 64 /* block positions remembered (deeper: walked again) */

/* Finds function k's block by walking the blocks before it (their heads
 * only), remembering the positions it passes. */
typedef struct cursor {
    const uint16_t *ent;              /* the minima (gs__db_min_value)     */
    const unsigned char *first, *end; /* the first block, the record's end */
    const unsigned char *next;        /* the block of function n (walked)  */
    uint32_t n;
    const unsigned char *at[CURSOR_MAX];
} cursor;

static inline void cursor_init(const gs_db *db, uint32_t x, uint32_t nf, cursor *c)
{
    const unsigned char *p = gs__db_record(db, x, &c->end);
    c->ent = (const uint16_t *)(const void *)p; /* records start 2-aligned */
    c->first = c->next = p + GS__DB_MIN_BYTES * (size_t)nf;
    c->n = 0;
}

/* The size of the block at p (0: malformed, or past the record's end). */
static inline uint32_t block_bytes(const unsigned char *p, const unsigned char *end)
{
    return gs__db_fblock_size(p, (uint64_t)(end - p));
}

/* Function k's block (k reachable: its minimum finite), NULL if the walk
 * meets a malformed block. */
static const unsigned char *cursor_block(cursor *c, uint32_t k)
{
    if (k < c->n) return c->at[k];
    const unsigned char *p = c->next;
    uint32_t i = c->n;
    if (k >= CURSOR_MAX && c->n >= CURSOR_MAX) { /* deep: from the last remembered */
        p = c->at[CURSOR_MAX - 1], i = CURSOR_MAX - 1;
        if (c->ent[i] != GS__DB_MIN_INF) {
            uint32_t b = block_bytes(p, c->end);
            if (!b) return NULL;
            p += b;
        }
        ++i;
    }
    for (; i < k; ++i) {
        if (i < CURSOR_MAX) c->at[i] = p;
        if (c->ent[i] == GS__DB_MIN_INF) continue; /* unreachable: no block */
        uint32_t b = block_bytes(p, c->end);
        if (!b) return NULL;
        p += b;
    }
    if (k < CURSOR_MAX) {
        c->at[k] = p;
        if (k + 1 > c->n) {
            uint32_t b = c->ent[k] == GS__DB_MIN_INF ? 0 : block_bytes(p, c->end);
            if (!b && c->ent[k] != GS__DB_MIN_INF) return NULL;
            c->n = k + 1;
            c->next = p + b;
        }
    }
    return p;
}

/* A block as a function: coefficients decoded into coef (Chebyshev), the
 * dip (if stored), the minimum from the entry. Returns 0 if malformed. */
#define COEF_N (GS_FUN_MAX_DEGREE + 1 + 15) /* room for whole SIMD vectors */
typedef struct dfun {
    gs__fun f;
    gs__fun_dip dip;
    gs__db_fblock b;
    double coef[COEF_N];
    float cf[COEF_N]; /* coef as floats (exactly: integers times 2^e) */
} dfun;

#ifdef __SSE2__
/* Four int32 q's times the scale: as floats to cf (exact: |q| < 2^15 and
 * 2^e, e <= 100, stays in float range) and as doubles to c, from the
 * integers directly (the same values, bit for bit; a reload of cf as
 * doubles would wait for its stores to complete). */
static inline void int4_out(__m128i q, __m128 sf, __m128d sd, float *cf, double *c)
{
    _mm_storeu_ps(cf, _mm_mul_ps(_mm_cvtepi32_ps(q), sf));
    _mm_storeu_pd(c, _mm_mul_pd(_mm_cvtepi32_pd(q), sd));
    _mm_storeu_pd(c + 2, _mm_mul_pd(_mm_cvtepi32_pd(_mm_shuffle_epi32(q, 0xEE)), sd));
}

/* An integer block's coefficients q_k 2^e as floats and doubles, eight at
 * a time. The bytes are read in place when the record holds every byte the
 * vector loads touch, else copied first (never read beyond the record's
 * end); the lanes beyond the block are not used. */
static void decode_int(const gs__db_fblock *b, const unsigned char *end, double *c, float *cf)
{
    uint32_t n = b->degree + 1, w = b->wide;
    unsigned char buf[2 * COEF_N + 16];
    const unsigned char *raw = b->coef; /* w int16, then n - w int8 */
    /* the loads' last byte: int16 vectors of 16 bytes from 2k (k < w, step
     * 8), int8 ones of 8 bytes from w + k (w <= k < n, step 8) */
    uint32_t reach = 2 * ((w + 7) & ~7u), r8 = n > w ? 2 * w + 8 * ((n - 1 - w) / 8) + 8 : 0;
    reach = r8 > reach ? r8 : reach;
    if (end - raw < (ptrdiff_t)reach) { /* the record's last bytes: not read beyond its end */
        memset(buf, 0, sizeof buf);
        memcpy(buf, raw, n + w);
        raw = buf;
    }
    uint32_t bits = (uint32_t)(127 + b->e) << 23;
    float sf;
    memcpy(&sf, &bits, 4);
    const __m128 sc = _mm_set1_ps(sf);
    const __m128d sd = _mm_set1_pd(gs__db_pow2(b->e));
    for (uint32_t k = 0; k < w; k += 8) {
        __m128i q = _mm_loadu_si128((const __m128i *)(const void *)(raw + 2 * k));
        int4_out(_mm_srai_epi32(_mm_unpacklo_epi16(q, q), 16), sc, sd, cf + k, c + k);
        int4_out(_mm_srai_epi32(_mm_unpackhi_epi16(q, q), 16), sc, sd, cf + k + 4, c + k + 4);
    }
    for (uint32_t k = w; k < n; k += 8) {
        __m128i q = _mm_loadl_epi64((const __m128i *)(const void *)(raw + w + k));
        q = _mm_srai_epi16(_mm_unpacklo_epi8(q, q), 8);
        int4_out(_mm_srai_epi32(_mm_unpacklo_epi16(q, q), 16), sc, sd, cf + k, c + k);
        int4_out(_mm_srai_epi32(_mm_unpackhi_epi16(q, q), 16), sc, sd, cf + k + 4, c + k + 4);
    }
}
#endif

/* The coefficients of a parsed Chebyshev block as doubles and floats
 * (gs__db_fblock_coef, without a call to ldexp); 0 if malformed. */
static int decode_coef(const gs__db_fblock *b, const unsigned char *end, double *c, float *cf)
{
    uint32_t n = b->degree + 1;
    if (b->f32) {
        for (uint32_t k = 0; k < n; ++k) {
            float v = gs__ldf(b->coef + 4 * (size_t)k);
            if (!(fabsf(v) <= 1e30f)) return 0;
            c[k] = v, cf[k] = v;
        }
        return 1;
    }
    if (b->e < GS__FB_EXP_MIN || b->e > GS__FB_EXP_MAX) return 0;
#ifdef __SSE2__
    if (b->e <= 100) {
        decode_int(b, end, c, cf);
        return 1;
    }
#endif
    double s = gs__db_pow2(b->e);
    uint32_t w = b->wide;
    for (uint32_t k = 0; k < w; ++k) {
        int16_t q;
        memcpy(&q, b->coef + 2 * (size_t)k, 2);
        c[k] = q * s;
        cf[k] = (float)c[k];
    }
    for (uint32_t k = w; k < n; ++k) {
        c[k] = (signed char)b->coef[w + k] * s;
        cf[k] = (float)c[k];
    }
    return 1;
}

/* f's values on a grid of g points: the path kernel for paths
 * (pair_grid.h), bit for bit gs__grid_values. */
static void grid_of(const dfun *d, uint32_t g, float *v)
{
    if (d->f.closed) gs__grid_values(&d->f, g, v);
    else gs__grid_values_path(d->cf, d->f.degree, d->f.squared, g, v);
}

static int decode(const unsigned char *p, const unsigned char *end, float minval, dfun *d)
{
    if (!p || !gs__db_fblock_parse(p, (uint64_t)(end - p), &d->b)) return 0;
    const gs__db_fblock *b = &d->b;
    d->f.kind = b->sampled ? GS_FUN_SAMPLED : GS_FUN_CHEBYSHEV;
    d->f.degree = b->degree;
    d->f.squared = b->squared;
    d->f.closed = b->closed;
    d->f.shift = b->shift;
    d->f.minval = minval;
    d->f.coef = d->coef;
    d->dip.u = d->dip.lo = d->dip.hi = NAN;
    d->dip.slope = 0.0;
    d->dip.seam = NAN;
    d->dip.seam_cell = GS_FUN_NO_CELL;
    if (b->has_dip) {
        d->dip.u = b->dip[0];
        d->dip.lo = d->dip.u + b->dip[1];
        d->dip.hi = d->dip.u + b->dip[2];
        d->dip.slope = b->dip[3];
    }
    return b->sampled || decode_coef(b, end, d->coef, d->cf);
}

/* A sampled block's value at u (piecewise linear, as gs__fun_value). */
static double sampled_at(const gs__db_fblock *b, double u)
{
    uint32_t n = b->degree + 1, k, k1;
    double x;
    if (b->closed) {
        x = (gs__fun_wrap(u) + 1.0) * 0.5 * n;
        k = x >= n ? n - 1 : (uint32_t)x;
        k1 = k + 1 == n ? 0 : k + 1;
    } else {
        u = u < -1.0 ? -1.0 : (u > 1.0 ? 1.0 : u);
        x = (u + 1.0) * 0.5 * (n - 1);
        k = x >= n - 1 ? n - 2 : (uint32_t)x;
        k1 = k + 1;
    }
    double a = gs__ldf(b->coef + 4 * (size_t)k), c = gs__ldf(b->coef + 4 * (size_t)k1);
    return a + (x - k) * (c - a);
}

static double dfun_at(const dfun *d, double u)
{
    return d->b.sampled ? sampled_at(&d->b, u) : gs__fun_value(&d->f, u);
}

static double sample_u(const gs__db_fblock *b, uint32_t k)
{
    uint32_t n = b->degree + 1;
    return b->closed ? -1.0 + 2.0 * k / n : -1.0 + 2.0 * k / (n - 1);
}

/* SEPsam: every sample of either function (exact for two of them: a
 * piecewise-linear sum is minimal at a breakpoint); a mix with a Chebyshev
 * function (not written by geosep) adds a uniform scan of 513 points. */
static double sampled_pair(const dfun *a, const dfun *b)
{
    double best = INFINITY;
    const dfun *f[2] = {a, b};
    for (int i = 0; i < 2; i++)
        for (uint32_t k = 0; f[i]->b.sampled && k <= f[i]->b.degree; k++) {
            double u = sample_u(&f[i]->b, k), v = dfun_at(a, u) + dfun_at(b, u);
            best = v < best ? v : best;
        }
    for (int k = 0; k <= 512 && a->b.sampled != b->b.sampled; k++) {
        double u = -1.0 + k / 256.0, v = dfun_at(a, u) + dfun_at(b, u);
        best = v < best ? v : best;
    }
    return best;
}

/* x's function k kept for many targets (a source, below): decoded once,
 * and tabulated on the grid of g points its last pair used (a pair's grid
 * depends on both degrees: pair_grid). state 0: not yet, 1: ready, -1:
 * malformed. */
typedef struct xfun {
    dfun d;
    float grid[GS_FUN_GRID_MAX + 8];
    uint32_t g; /* grid's size (0: none yet) */
    int state;
} xfun;

/* The grid of a pair of Chebyshev functions of degrees ma, mb on a curve
 * whose highest degree is d1 - 1: for paths, gs__fun_grid_points of the
 * pair's own higher degree (a pair of low degrees needs fewer points; the
 * same for d(x, y) and d(y, x), and for a source kept for many targets);
 * loops keep their curve's grid (a seam's windows are cells of it: on a
 * coarser grid more pairs would go to the robust minimiser). */
static inline uint32_t pair_grid(uint32_t d1, uint32_t ma, uint32_t mb, uint32_t closed)
{
    uint32_t m = ma > mb ? ma : mb;
    return gs__fun_grid_points(closed || m >= d1 ? d1 - 1 : m);
}

/* The quick reject inside a pair of paths: once both are tabulated, the
 * minimum of the sum lies within half a cell of a grid point, and a sum
 * of two distance functions changes by at most twice the arc length, so
 * it is at least the grid's minimum less the cell's arc length (curve
 * length / (g - 1)); times this safety (fits are not exactly 1-Lipschitz).
 * A pair whose bound is not below the best answer so far is not refined.
 * Pairs with a sharp dip (the grid may step over it) are always refined. */
#ifndef LIPSCHITZ_SAFETY
#define LIPSCHITZ_SAFETY 1.5
#endif

/* min over curve c of f_a + f_b (decoded; a is the lower vertex id's: the
 * order of the two functions makes d(x,y) == d(y,x) bit for bit), or some
 * value >= best when it cannot be below best. ga, gb: the functions'
 * values on the pair's grid (pair_grid) when the caller has them, else
 * NULL. */
static double pair_min_dec(const gs_db *db, uint32_t c, const dfun *a, const float *ga, const dfun *b,
                           const float *gb, double best)
{
    if (a->b.sampled || b->b.sampled) return sampled_pair(a, b);
    uint32_t d1 = db->curves[c].degree1;
    if (!d1) return gs__fun_pair_min(&a->f, &b->f, NULL);
    uint32_t g = pair_grid(d1, a->f.degree, b->f.degree, a->f.closed);
    if (!a->f.closed && !b->f.closed) { /* both paths: tabulated and summed in one pass */
        float e[GS_FUN_GRID_MAX + 16];
        uint32_t jm[2];
        double len = db->curves[c].length, margin = LIPSCHITZ_SAFETY * len / (g - 1);
        int may_reject = len >= 0.0 && !a->b.has_dip && !b->b.has_dip;
        float mn = gs__grid_pair_path(a->cf, a->f.degree, a->f.squared, ga, b->cf, b->f.degree, b->f.squared, gb, g,
                                      e + 1, jm, may_reject ? best : INFINITY, margin);
        if (may_reject && mn - margin >= best) return mn;
        return gs__fun_pair_min_grid_sum(&a->f, &b->f, e, mn, g, jm[0] == GS__GRID_NO_MARKS ? NULL : jm, &a->dip,
                                         &b->dip, NULL);
    }
    float va[GS_FUN_GRID_MAX + 8], vb[GS_FUN_GRID_MAX + 8];
    if (!ga) grid_of(a, g, va), ga = va;
    if (!gb) grid_of(b, g, vb), gb = vb;
    return gs__fun_pair_min_grid(&a->f, &b->f, ga, gb, g, &a->dip, &b->dip, NULL);
}

/* x's function k from the source's cache, decoded on first use; NULL if
 * malformed. */
static xfun *xfun_get(cursor *cx, xfun *cache, uint32_t k)
{
    xfun *f = cache + k;
    if (f->state == 0) {
        f->state = -1;
        if (decode(cursor_block(cx, k), cx->end, gs__db_min_value(cx->ent[k]), &f->d)) {
            f->g = 0;
            if (f->d.f.closed && !f->d.b.sampled) /* what the minimiser would find each time */
                f->d.dip.seam = gs__fun_seam_value(&f->d.f);
            f->state = 1;
        }
    }
    return f->state == 1 ? f : NULL;
}

/* f's values on the grid of g points (kept until another g is asked). */
static const float *xfun_grid(xfun *f, uint32_t g)
{
    if (f->g != g) {
        grid_of(&f->d, g, f->grid);
        if (f->d.f.closed) f->d.dip.seam_cell = gs__fun_seam_cell(&f->d.f, g);
        f->g = g;
    }
    return f->grid;
}

/* min over curve c of f_x + f_y (function k of both; x < y), or a value
 * >= best when it cannot be below best. With a cache (x's functions kept
 * by a source), cx is the source's cursor and x_first says whether the
 * source is the lower id. NaN: malformed. */
static double pair_min(const gs_db *db, cursor *cx, cursor *cy, uint32_t k, uint32_t c, xfun *cache, int x_first,
                       double best)
{
    dfun a, b;
    if (cache) {
        xfun *s = xfun_get(cx, cache, k);
        if (!s || !decode(cursor_block(cy, k), cy->end, gs__db_min_value(cy->ent[k]), &b)) return NAN;
        uint32_t d1 = db->curves[c].degree1;
        const float *gs = s->d.b.sampled || b.b.sampled || !d1 ? NULL
                                                               : xfun_grid(s, pair_grid(d1, s->d.f.degree, b.f.degree, s->d.f.closed));
        return x_first ? pair_min_dec(db, c, &s->d, gs, &b, NULL, best)
                       : pair_min_dec(db, c, &b, NULL, &s->d, gs, best);
    }
    if (!decode(cursor_block(cx, k), cx->end, gs__db_min_value(cx->ent[k]), &a) ||
        !decode(cursor_block(cy, k), cy->end, gs__db_min_value(cy->ent[k]), &b))
        return NAN;
    return pair_min_dec(db, c, &a, NULL, &b, NULL, best);
}

/* The prefetch helpers are always inlined: GCC counts __builtin_prefetch
 * as free of side effects, so a helper left out of line is found "const"
 * or "pure" and its calls are deleted (GCC 12 -O2 removed every one). */
#if defined(__GNUC__)
#define PREFETCH_FN inline __attribute__((always_inline))
#else
#define PREFETCH_FN inline
#endif

static PREFETCH_FN void prefetch_lines(const void *p, size_t bytes)
{
    if (!bytes) return;
    const char *r = p, *e = r + bytes - 1;
    for (; r < e; r += 64) __builtin_prefetch(r);
    __builtin_prefetch(e);
}

/* The first lines of x's record: the minima and the first blocks (the
 * root's curves, which hold most random pairs' minimum). */
#define RECORD_AHEAD 192

static PREFETCH_FN void prefetch_record(const gs_db *db, uint32_t x)
{
    const unsigned char *end, *p = gs__db_record(db, x, &end);
    size_t n = (size_t)(end - p);
    prefetch_lines(p, n < RECORD_AHEAD ? n : RECORD_AHEAD);
}

/* eq. 4-5 with the quick reject over the common curves of `top` and its
 * ancestors (cx, cy: the two cursors, x_first: whether cx's vertex is the
 * lower id; cache: the source's functions, or NULL). The candidates are
 * visited the lowest bound minval_x + minval_y first (ties bottom-up), found
 * by selection: most pairs stop after one or two, and visiting the most
 * promising curve first lets the quick reject skip more minimisations than
 * the paper's bottom-up order, for the same minimum. Stops at a candidate
 * whose bound exceeds cut (+inf: never). Beyond MAX_CANDIDATES curves (rare)
 * the rest are visited bottom-up. */
static double cross_source(const gs_db *db, cursor *cx, cursor *cy, uint32_t top, xfun *cache, int x_first,
                           double cut)
{
    candidate c[MAX_CANDIDATES];
    uint32_t n = 0, a = top;
    for (; a != GS_NONE; a = db->nodes[a].parent) {
        uint32_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        if (n + (k1 - k0) > MAX_CANDIDATES) break;
        for (uint32_t k = k0; k < k1; ++k, ++n)
            c[n].bound = (double)gs__db_min_value(cx->ent[k]) + (double)gs__db_min_value(cy->ent[k]), c[n].k = k,
            c[n].curve = db->nodes[a].curve_start + (k - k0);
    }
    double best = INFINITY;
    for (uint32_t left = n; left; --left) {
        /* the first lowest bound (a visited candidate's is +inf; a NaN
         * bound, only in a corrupt file, is taken only in the first place) */
        uint32_t m = 0;
        double bm = c[0].bound;
        for (uint32_t i = 1; i < n; ++i) {
            int lower = c[i].bound < bm;
            m = lower ? i : m, bm = lower ? c[i].bound : bm;
        }
        if (bm >= best || bm > cut) break; /* all others rejected too (and unreachable) */
        double d = pair_min(db, cx, cy, c[m].k, c[m].curve, cache, x_first, best);
        if (d != d) return NAN;
        if (d < best) best = d;
        c[m].bound = INFINITY; /* visited: +inf >= best from here on */
    }
    for (; a != GS_NONE; a = db->nodes[a].parent) { /* > MAX_CANDIDATES curves */
        uint32_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        for (uint32_t k = k0; k < k1; ++k) {
            double bound = (double)gs__db_min_value(cx->ent[k]) + (double)gs__db_min_value(cy->ent[k]);
            if (bound >= best || bound > cut) continue;
            double d = pair_min(db, cx, cy, k, db->nodes[a].curve_start + (k - k0), cache, x_first, best);
            if (d != d) return NAN;
            if (d < best) best = d;
        }
    }
    return best;
}

/* eq. 4-5 with the quick reject, x < y: cross_source's selection (most
 * queries stop after one or two candidates; a full insertion sort of the
 * ~6 candidates mispredicted its branches), the same order and answers. */
static double cross(const gs_db *db, uint32_t x, uint32_t y, uint32_t top, uint32_t nfx, uint32_t nfy)
{
    cursor cx, cy;
    cursor_init(db, x, nfx, &cx);
    cursor_init(db, y, nfy, &cy);
    return cross_source(db, &cx, &cy, top, NULL, 1, INFINITY);
}

/* The stored exact distance of a near pair (section 'near_pairs'): only
 * pairs nearer than its radius are stored, so a pair at least that far
 * apart in space costs one comparison. e2: their squared Euclidean
 * distance. */
static int near_pair(const gs_db *db, uint32_t x, uint32_t y, double e2, double *d)
{
    if (!(e2 < db->near.radius2)) return 0; /* also without the section: 0 */
    return x < y ? gs__db_near_find(&db->near, x, y, d) : gs__db_near_find(&db->near, y, x, d);
}

/* Cross-leaf distance of x != y (any order), top their leaves' lowest common
 * ancestor: the two go in vertex-id order so that d(x,y) == d(y,x). */
static double cross_leaf(const gs_db *db, uint32_t x, uint32_t y, uint32_t lx, uint32_t ly, uint32_t top)
{
    double e2 = euclidean2(db, x, y), d;
    if (!near_pair(db, x, y, e2, &d)) {
        uint32_t nfx = db->nodes[lx].curve_prefix, nfy = db->nodes[ly].curve_prefix;
        d = x < y ? cross(db, x, y, top, nfx, nfy) : cross(db, y, x, top, nfy, nfx);
    }
    double e = sqrt(e2);
    return d != d || d >= e ? d : e;
}

double gs_db_distance(const gs_db *db, uint32_t x, uint32_t y)
{
    if (!db || x >= db->nv || y >= db->nv) return NAN;
    if (x == y) return 0.0;
    uint32_t lx = db->leaf[x], ly = db->leaf[y];
    if (lx == GS_NONE || ly == GS_NONE) return INFINITY;
    if (lx == ly) return same_leaf(db, lx, x, y);
    prefetch_record(db, x), prefetch_record(db, y);
    __builtin_prefetch(db->xyz + 3 * (size_t)x), __builtin_prefetch(db->xyz + 3 * (size_t)y);
    return cross_leaf(db, x, y, lx, ly, lowest_common_ancestor(db->nodes, lx, ly));
}

/* Pipeline of the batch: while pair i is answered, the leaves and index
 * entries of pair i + 2 BATCH_AHEAD are requested, and the records and
 * positions of pair i + BATCH_AHEAD (their addresses known by then, most
 * often): a batch waits for memory in parallel over several pairs, where a
 * single query waits for its misses one after the other. The answers are
 * gs_db_distance's, bit for bit (only prefetches are added). */
enum { BATCH_AHEAD = 4 };

static PREFETCH_FN void prefetch_ids(const gs_db *db, uint32_t x, uint32_t y)
{
    if (x >= db->nv || y >= db->nv) return;
    __builtin_prefetch(db->leaf + x), __builtin_prefetch(db->leaf + y);
    __builtin_prefetch(db->index + x), __builtin_prefetch(db->index + y);
}

static PREFETCH_FN void prefetch_pair(const gs_db *db, uint32_t x, uint32_t y)
{
    if (x >= db->nv || y >= db->nv || x == y) return;
    __builtin_prefetch(db->xyz + 3 * (size_t)x), __builtin_prefetch(db->xyz + 3 * (size_t)y);
    if (db->leaf[x] == db->leaf[y]) return;
    prefetch_record(db, x), prefetch_record(db, y);
}

/* Out-of-range ids give NaN in out[] and GS_EARG naming the first one; the
 * other pairs are still answered. */
int gs_db_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out, gs_error *err)
{
    if (!db || (n && (!pairs || !out))) return gs__fail(err, GS_EARG, "gs_db_distances: NULL argument");
    size_t bad = SIZE_MAX;
    const size_t a = BATCH_AHEAD;
    for (size_t i = 0; i < 2 * a && i < n; ++i) prefetch_ids(db, pairs[2 * i], pairs[2 * i + 1]);
    for (size_t i = 0; i < n; ++i) {
        if (i + 2 * a < n) prefetch_ids(db, pairs[2 * (i + 2 * a)], pairs[2 * (i + 2 * a) + 1]);
        if (i + a < n) prefetch_pair(db, pairs[2 * (i + a)], pairs[2 * (i + a) + 1]);
        out[i] = gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        if (bad == SIZE_MAX && (pairs[2 * i] >= db->nv || pairs[2 * i + 1] >= db->nv)) bad = i;
    }
    if (bad != SIZE_MAX)
        return gs__fail(err, GS_EARG, "gs_db_distances: pair %zu (%u, %u) has a vertex id >= n_vertices %u", bad,
                        pairs[2 * bad], pairs[2 * bad + 1], db->nv);
    return GS_OK;
}

/* ---- a source kept for many targets (query_internal.h) ---- */

struct gs__qsrc {
    const gs_db *db;
    uint32_t x, lx, depth_x, nfx;
    cursor cx;             /* x's record                                  */
    xfun *cache;           /* nfx: x's functions, filled as used          */
    float *mins;           /* nfx: x's minima, decoded                    */
    uint32_t *anc;         /* depth_x + 1: x's ancestor at each depth     */
};

gs__qsrc *gs__qsrc_create(const gs_db *db, uint32_t x)
{
    gs__qsrc *s = gs__calloc(1, sizeof *s);
    if (!s) return NULL;
    s->db = db, s->x = x, s->lx = db->leaf[x];
    if (s->lx == GS_NONE) return s;
    s->depth_x = db->nodes[s->lx].depth;
    s->nfx = db->nodes[s->lx].curve_prefix;
    s->anc = gs__malloc((size_t)s->depth_x + 1, sizeof *s->anc);
    s->cache = gs__malloc(s->nfx ? s->nfx : 1, sizeof *s->cache);
    s->mins = gs__malloc(s->nfx ? s->nfx : 1, sizeof *s->mins);
    if (!s->anc || !s->cache || !s->mins) {
        gs__qsrc_free(s);
        return NULL;
    }
    for (uint32_t k = 0; k < s->nfx; ++k) s->cache[k].state = 0;
    for (uint32_t a = s->lx; a != GS_NONE; a = db->nodes[a].parent) s->anc[db->nodes[a].depth] = a;
    cursor_init(db, x, s->nfx, &s->cx);
    for (uint32_t k = 0; k < s->nfx; ++k) s->mins[k] = gs__db_min_value(s->cx.ent[k]);
    return s;
}

void gs__qsrc_free(gs__qsrc *s)
{
    if (!s) return;
    free(s->anc);
    free(s->cache);
    free(s->mins);
    free(s);
}

uint32_t gs__qsrc_leaf(const gs__qsrc *s)
{
    return s->lx;
}

const float *gs__qsrc_minima(const gs__qsrc *s)
{
    return s->lx == GS_NONE ? NULL : s->mins;
}

uint32_t gs__qsrc_ancestor(const gs__qsrc *s, uint32_t node)
{
    const gs__db_node *nodes = s->db->nodes;
    while (nodes[node].depth > s->depth_x || s->anc[nodes[node].depth] != node) node = nodes[node].parent;
    return node;
}

double gs__qsrc_cross_cut(gs__qsrc *s, uint32_t y, uint32_t ly, uint32_t top, double cut)
{
    const gs_db *db = s->db;
    cursor cy;
    cursor_init(db, y, db->nodes[ly].curve_prefix, &cy);
    double e2 = euclidean2(db, s->x, y), d; /* as cross_leaf, bit for bit */
    if (!near_pair(db, s->x, y, e2, &d)) d = cross_source(db, &s->cx, &cy, top, s->cache, s->x < y, cut);
    double e = sqrt(e2);
    return d != d || d >= e ? d : e;
}

double gs__qsrc_cross(gs__qsrc *s, uint32_t y, uint32_t ly, uint32_t top)
{
    return gs__qsrc_cross_cut(s, y, ly, top, INFINITY);
}

double gs__qsrc_distance(gs__qsrc *s, uint32_t y)
{
    const gs_db *db = s->db;
    if (y >= db->nv) return NAN;
    if (y == s->x) return 0.0;
    uint32_t ly = db->leaf[y];
    if (s->lx == GS_NONE || ly == GS_NONE) return INFINITY;
    if (ly == s->lx) return same_leaf(db, ly, s->x, y);
    return gs__qsrc_cross(s, y, ly, gs__qsrc_ancestor(s, ly));
}
