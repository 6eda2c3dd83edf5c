/* field_batch.c - gs_db_field's batched kernel (query_internal.h): the
 * same answers as one query source per target (query.c cross_source), bit
 * for bit, computed target-parallel. A single query runs one long chain of
 * dependent steps per candidate curve (walk y's record, decode its block,
 * tabulate on the pair's grid, locate the grid's minimum, refine it by a
 * cubic, evaluate both series there): latency, branches, a few FLOPs. Here
 * the targets advance in rounds: each round every open target takes its
 * next candidate (lowest bound first, cross_source's order and stopping
 * rule), the round's jobs are grouped by (curve, grid), and each group of
 * up to 16 jobs is tabulated with one target per AVX-512 lane (every grid
 * point the same fused multiply-adds in the same order as pair_grid.c's
 * kernel, so the same floats), its candidate grid points found lane by
 * lane, and the final values of 8 candidate points at a time evaluated by
 * the same double operations as pair_min.c's pair_value, lane by lane. The
 * per-job scalar rest (the Lipschitz reject, the cubic) mirrors pair_min_dec
 * and grid_core's path branch line by line. Anything else (loops, sampled
 * functions, dips, near pairs, over 64 candidates, malformed blocks, grids
 * that are not finite) goes to the scalar source (gs__qsrc_pair,
 * gs__qsrc_cross): the common path is fast, every path is exact. The tests
 * (test_fields, test_within) compare every target with gs_db_distance. */
#include "../fit/fun_internal.h"
#include "pair_grid.h"
#include "query_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define FB_HAVE 1
#endif

#ifdef FB_HAVE

#define FB_MAXC 64                     /* cross_source's MAX_CANDIDATES        */
#define FB_ROWS (GS_FUN_MAX_DEGREE + 1)
#define FB_LIPSCHITZ 1.5               /* query.c's LIPSCHITZ_SAFETY           */
#define FB_NONE 0xFFFFFFFFu
#define FB_AHEAD 12u                   /* records prefetched this many targets ahead */
#define FB_BLOCK 1024u                 /* targets per batch (their records stay in cache) */
#define AVX512 __attribute__((target("avx512f,avx2,fma")))

/* x's function k: decoded once (state 1: a path without dip, ready for the
 * kernel; 2: anything else, scalar; 0: not yet). */
typedef struct fb_xf {
    int state;
    uint32_t m, sq;
    double c[FB_ROWS];
    float cf[FB_ROWS];
} fb_xf;

/* a target in the batch */
typedef struct fb_tgt {
    const unsigned char *rec, *end; /* y's record                               */
    double best, e2;
    uint32_t y, ly, list, n;        /* list: offset in the arena, n candidates  */
    uint32_t nw;                    /* blocks walked (offs valid below)         */
    uint32_t po, bo;                /* its blocks' offsets at po, bounds at bo  */
} fb_tgt;

/* a job: target t's candidate (k, curve) */
typedef struct fb_job {
    uint32_t t, k, curve, g, my, sqy;
    const unsigned char *blk;
    double res;
    int fall; /* 1: scalar */
} fb_job;

typedef struct fb_ctx {
    gs__qsrc *s;
    const gs_db *db;
    uint32_t x, lx, nfx;
    const uint16_t *xent;
    fb_xf *xf;
    /* candidate lists per common ancestor (lazily): arena of (k, curve) */
    uint32_t *node_list, *node_n;
    uint32_t *ak, *acurve, na, cap;
    uint32_t *top; /* per leaf: its lowest common ancestor with x's leaf */
} fb_ctx;

static inline float min_val(const uint16_t *ent, uint32_t k)
{
    return gs__db_min_value(ent[k]);
}

/* The candidates of common ancestor `top`, bottom-up (cross_source's
 * order); FB_NONE n when over FB_MAXC. Returns 0 when out of memory. */
static int node_list(fb_ctx *c, uint32_t top)
{
    if (c->node_list[top] != FB_NONE) return 1;
    const gs__db_node *nodes = c->db->nodes;
    uint32_t n = 0;
    for (uint32_t a = top; a != GS_NONE; a = nodes[a].parent) n += nodes[a].n_curves;
    if (n > FB_MAXC) {
        c->node_list[top] = 0, c->node_n[top] = FB_NONE;
        return 1;
    }
    if (c->na + n > c->cap) {
        uint32_t cap = 2 * c->cap + n + 64;
        uint32_t *k = realloc(c->ak, cap * sizeof *k);
        if (!k) return 0;
        c->ak = k;
        uint32_t *cv = realloc(c->acurve, cap * sizeof *cv);
        if (!cv) return 0;
        c->acurve = cv, c->cap = cap;
    }
    uint32_t o = c->na;
    for (uint32_t a = top; a != GS_NONE; a = nodes[a].parent) {
        uint32_t k0 = nodes[a].curve_prefix, k1 = k0 + nodes[a].n_curves;
        for (uint32_t k = k0; k < k1; ++k, ++c->na) c->ak[c->na] = k, c->acurve[c->na] = nodes[a].curve_start + (k - k0);
    }
    c->node_list[top] = o, c->node_n[top] = n;
    return 1;
}

/* q_k 2^e exactly as doubles and floats (query.c decode_coef's values),
 * coefficient k at c[k * stride], cf[k * stride]; 0: malformed. */
static int decode_coef(const gs__db_fblock *b, double *c, float *cf, uint32_t stride)
{
    uint32_t n = b->degree + 1;
    if (b->f32) {
        for (uint32_t k = 0; k < n; ++k) {
            float v = gs__ldf(b->coef + 4 * (size_t)k);
            if (!(fabsf(v) <= 1e30f)) return 0;
            c[k * stride] = v, cf[k * stride] = v;
        }
        return 1;
    }
    if (b->e < GS__FB_EXP_MIN || b->e > GS__FB_EXP_MAX) return 0;
    double s = gs__db_pow2(b->e);
    uint32_t w = b->wide;
    for (uint32_t k = 0; k < w; ++k) {
        int16_t q;
        memcpy(&q, b->coef + 2 * (size_t)k, 2);
        double v = q * s;
        c[k * stride] = v, cf[k * stride] = (float)v;
    }
    for (uint32_t k = w; k < n; ++k) {
        double v = (signed char)b->coef[w + k] * s;
        c[k * stride] = v, cf[k * stride] = (float)v;
    }
    return 1;
}

/* y's block at p (next_job checked its head: a path without a dip,
 * degree <= 24), its coefficients to c[16 k], cf[16 k]: the checks of
 * gs__db_fblock_parse and decode_coef for that case; 0: malformed. */
static inline __attribute__((always_inline)) int block_coef(const unsigned char *p, const unsigned char *end,
                                                            double *c, float *cf)
{
    uint64_t avail = (uint64_t)(end - p);
    uint32_t n = (p[0] & GS__FB_DEG_MASK) + 1;
    int e = (int)(signed char)p[1];
    if (e == GS__FB_F32) {
        if (avail < 2 + 4 * (uint64_t)n) return 0;
        for (uint32_t k = 0; k < n; ++k) {
            float v = gs__ldf(p + 2 + 4 * (size_t)k);
            if (!(fabsf(v) <= 1e30f)) return 0;
            c[16 * k] = v, cf[16 * k] = v;
        }
        return 1;
    }
    uint32_t w = p[2];
    if (w > n || avail < 3 + (uint64_t)n + w || e < GS__FB_EXP_MIN || e > GS__FB_EXP_MAX) return 0;
    const double s = gs__db_pow2(e);
    const unsigned char *q = p + 3;
    for (uint32_t k = 0; k < w; ++k) {
        int16_t v;
        memcpy(&v, q + 2 * (size_t)k, 2);
        double d = v * s;
        c[16 * k] = d, cf[16 * k] = (float)d;
    }
    for (uint32_t k = w; k < n; ++k) {
        double d = (signed char)q[w + k] * s;
        c[16 * k] = d, cf[16 * k] = (float)d;
    }
    return 1;
}

/* x's function k for the kernel (state 1) or not (2) */
static fb_xf *xf_get(fb_ctx *c, uint32_t k)
{
    fb_xf *f = c->xf + k;
    if (f->state) return f;
    f->state = 2;
    const unsigned char *end, *p = gs__db_record(c->db, c->x, &end);
    p += GS__DB_MIN_BYTES * (size_t)c->nfx;
    for (uint32_t i = 0; i < k; ++i) {
        if (c->xent[i] == GS__DB_MIN_INF) continue;
        uint32_t b = gs__db_fblock_size(p, (uint64_t)(end - p));
        if (!b) return f;
        p += b;
    }
    gs__db_fblock b;
    if (!gs__db_fblock_parse(p, (uint64_t)(end - p), &b) || b.sampled || b.closed || b.has_dip) return f;
    if (!decode_coef(&b, f->c, f->cf, 1)) return f;
    f->m = b.degree, f->sq = b.squared;
    f->state = 1;
    return f;
}

/* y's blocks 0 .. K-1 (K: the candidates' highest k + 1) located once,
 * and the candidates' bounds minval_x + minval_y (cross_source's) in the
 * list's order ak[0..n), padded with +inf to whole vectors of 8; returns 0
 * when a bound is NaN (cross_source's selection then differs from a
 * minimum: the scalar source answers). */
static int walk(const fb_tgt *t, uint32_t nf, uint32_t K, const uint16_t *xent, const uint32_t *ak, uint32_t n,
                uint32_t *offs, double *bl, uint32_t *nw)
{
    const uint16_t *ent = (const uint16_t *)(const void *)t->rec;
    const unsigned char *p = t->rec + GS__DB_MIN_BYTES * (size_t)nf, *end = t->end;
    int ok = 1;
    for (uint32_t i = 0; i < n; ++i) {
        double b = (double)min_val(xent, ak[i]) + (double)min_val(ent, ak[i]);
        ok &= b == b;
        bl[i] = b;
    }
    for (uint32_t i = n; i & 7; ++i) bl[i] = INFINITY;
    uint32_t i = 0;
    for (; i < K; ++i) {
        offs[i] = (uint32_t)(p - t->rec);
        if (ent[i] == GS__DB_MIN_INF) continue;
        uint32_t b = gs__db_fblock_size(p, (uint64_t)(end - p));
        if (!b) break;
        p += b;
    }
    *nw = i; /* block i itself may be malformed too: parsed before use */
    return ok;
}

/* The first lowest of n8 (a multiple of 8) bounds, none NaN: cross_source's
 * selection (visited ones are +inf). */
AVX512 static uint32_t fb_select(const double *bl, uint32_t n8, double *bm)
{
    __m512d m = _mm512_loadu_pd(bl);
    for (uint32_t i = 8; i < n8; i += 8) m = _mm512_min_pd(m, _mm512_loadu_pd(bl + i));
    double v = _mm512_reduce_min_pd(m);
    __m512d vv = _mm512_set1_pd(v);
    *bm = v;
    for (uint32_t i = 0;; i += 8) {
        __mmask8 q = _mm512_cmp_pd_mask(_mm512_loadu_pd(bl + i), vv, _CMP_EQ_OQ);
        if (q) return i + (uint32_t)__builtin_ctz(q);
    }
}

#ifdef FB_TIMING /* a developer's breakdown (cycles per phase): -DFB_TIMING */
#include <x86intrin.h>
unsigned long long fbt[16];
#define TS(i) unsigned long long _t##i = __rdtsc()
#define TA(i, a, b) (fbt[i] += _t##b - _t##a)
#else
#define TS(i)
#define TA(i, a, b) ((void)0)
#endif

/* ---- the kernel: up to 16 jobs of one (k, g) ---- */

/* Lane results of the tabulation: the sum's grid S[j * 16 + lane], its
 * minimum and candidate points per lane. */
typedef struct fb_grid {
    float S[GS_FUN_GRID_MAX * 16];
    float mn[16];
    uint32_t j1[16], j2[16];
} fb_grid;

/* tabulate y's series (transposed float coefficients CF[kk * 16 + lane],
 * zeros beyond each lane's degree; mmax the largest), add x's grid gx, and
 * find each lane's grid minimum and candidate points (pair_grid.c pair16's
 * rule) */
AVX512 static void fb_tab(const float *tab, uint32_t st, const float *CF, uint32_t mmax, __mmask16 sqm,
                          const float *gx, uint32_t g, fb_grid *r)
{
    const __m512 z = _mm512_setzero_ps();
    __m512 mv = _mm512_set1_ps(INFINITY);
    /* four points at a time: independent chains (the table has rows
     * beyond g: stride >= g + 3) */
    for (uint32_t j = 0; j < g; j += 4) {
        __m512 a0 = z, a1 = z, a2 = z, a3 = z;
        for (uint32_t k = 0; k <= mmax; ++k) {
            const __m512 ck = _mm512_load_ps(CF + 16 * k);
            const float *tr = tab + (size_t)k * st + j;
            a0 = _mm512_fmadd_ps(ck, _mm512_set1_ps(tr[0]), a0);
            a1 = _mm512_fmadd_ps(ck, _mm512_set1_ps(tr[1]), a1);
            a2 = _mm512_fmadd_ps(ck, _mm512_set1_ps(tr[2]), a2);
            a3 = _mm512_fmadd_ps(ck, _mm512_set1_ps(tr[3]), a3);
        }
        __m512 a[4] = {a0, a1, a2, a3};
        for (uint32_t q = 0; q < 4 && j + q < g; ++q) {
            __m512 v = _mm512_max_ps(a[q], z);
            v = _mm512_mask_sqrt_ps(v, sqm, v);
            v = _mm512_add_ps(_mm512_set1_ps(gx[j + q]), v);
            _mm512_store_ps(r->S + 16 * (j + q), v);
            mv = _mm512_min_ps(mv, v);
        }
    }
    _mm512_storeu_ps(r->mn, mv);
    /* j1: the first point equal to the minimum (it is <= thr); j2: among
     * the other discrete local minima <= thr, the lowest, the first of
     * equals: its value, then its first point (no chain through masks) */
    const __m512 thr = _mm512_mul_ps(mv, _mm512_set1_ps(1.02f)), inf = _mm512_set1_ps(INFINITY);
    const __m512i none = _mm512_set1_epi32((int)FB_NONE);
    __m512i ja = none, jb = none;
    for (uint32_t j = 0; j < g; ++j) {
        __mmask16 q = _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(_mm512_load_ps(r->S + 16 * j), thr, _CMP_LE_OQ),
                                              _mm512_load_ps(r->S + 16 * j), mv, _CMP_EQ_OQ);
        ja = _mm512_min_epu32(ja, _mm512_mask_mov_epi32(none, q, _mm512_set1_epi32((int)j)));
    }
    __mmask16 lmk[GS_FUN_GRID_MAX];
    __m512 bv = inf;
    for (uint32_t j = 0; j < g; ++j) {
        __m512 cur = _mm512_load_ps(r->S + 16 * j);
        __m512 prev = j ? _mm512_load_ps(r->S + 16 * (j - 1)) : inf;
        __m512 next = j + 1 < g ? _mm512_load_ps(r->S + 16 * (j + 1)) : inf;
        __mmask16 lm = _mm512_cmp_ps_mask(cur, thr, _CMP_LE_OQ);
        lm = _mm512_mask_cmp_ps_mask(lm, cur, prev, _CMP_LE_OQ);
        lm = _mm512_mask_cmp_ps_mask(lm, cur, next, _CMP_LE_OQ);
        lm = _mm512_mask_cmpneq_epi32_mask(lm, ja, _mm512_set1_epi32((int)j));
        lmk[j] = lm;
        bv = _mm512_min_ps(bv, _mm512_mask_mov_ps(inf, lm, cur));
    }
    for (uint32_t j = 0; j < g; ++j) {
        __mmask16 q = _mm512_mask_cmp_ps_mask(lmk[j], _mm512_load_ps(r->S + 16 * j), bv, _CMP_EQ_OQ);
        jb = _mm512_min_epu32(jb, _mm512_mask_mov_epi32(none, q, _mm512_set1_epi32((int)j)));
    }
    _mm512_storeu_si512(r->j1, ja);
    _mm512_storeu_si512(r->j2, jb);
}

/* pair_value of 8 points: x's series (coefficients cx, degree mx: the
 * same in every lane), y's (lane l: job idx[l]'s, CD[kk * 16 + job], zeros
 * beyond each job's degree, mmax >= every lane's and mx), at the path
 * parameters u; lane by
 * lane pair_min.c's pair_value (Clenshaw; a series above its degree stays
 * exactly +0, as there). */
AVX512 static void fb_values(const double *cx, uint32_t mx, uint32_t sqx, const double *CD, __m512i idx,
                             uint32_t mmax, __mmask8 sqy, const double *u, double *out)
{
    const __m512d one = _mm512_set1_pd(1.0), mone = _mm512_set1_pd(-1.0), z = _mm512_setzero_pd();
    __m512d t = _mm512_loadu_pd(u);
    /* gs__fun_clamp1: t < -1 ? -1 : (t > 1 ? 1 : t) */
    t = _mm512_mask_mov_pd(_mm512_mask_mov_pd(t, _mm512_cmp_pd_mask(t, one, _CMP_GT_OQ), one),
                           _mm512_cmp_pd_mask(t, mone, _CMP_LT_OQ), mone);
    __m512d s = _mm512_mul_pd(_mm512_set1_pd(2.0), t);
    __m512d a1 = z, a2 = z, b1 = z, b2 = z;
    for (uint32_t k = mmax; k >= 1; --k) {
        __m512d ck = _mm512_set1_pd(k <= mx ? cx[k] : 0.0);
        __m512d a0 = _mm512_sub_pd(_mm512_add_pd(ck, _mm512_mul_pd(s, a1)), a2);
        a2 = a1, a1 = a0;
        __m512d cy = _mm512_permutex2var_pd(_mm512_load_pd(CD + 16 * k), idx, _mm512_load_pd(CD + 16 * k + 8));
        __m512d b0 = _mm512_sub_pd(_mm512_add_pd(cy, _mm512_mul_pd(s, b1)), b2);
        b2 = b1, b1 = b0;
    }
    __m512d pa = _mm512_sub_pd(_mm512_add_pd(_mm512_set1_pd(cx[0]), _mm512_mul_pd(t, a1)), a2);
    __m512d c0 = _mm512_permutex2var_pd(_mm512_load_pd(CD), idx, _mm512_load_pd(CD + 8));
    __m512d pb = _mm512_sub_pd(_mm512_add_pd(c0, _mm512_mul_pd(t, b1)), b2);
    if (mx == 0) pa = _mm512_set1_pd(cx[0]);
    /* gs__fun_term_value: p > 0 ? (sq ? sqrt p : p) : 0 */
    __mmask8 ppa = _mm512_cmp_pd_mask(pa, z, _CMP_GT_OQ), ppb = _mm512_cmp_pd_mask(pb, z, _CMP_GT_OQ);
    __m512d va = sqx ? _mm512_sqrt_pd(pa) : pa;
    va = _mm512_maskz_mov_pd(ppa, va);
    __m512d vb = _mm512_mask_sqrt_pd(pb, sqy, pb);
    vb = _mm512_maskz_mov_pd(ppb, vb);
    _mm512_storeu_pd(out, _mm512_add_pd(va, vb));
}

static inline double grid_u(uint32_t j, uint32_t g)
{
    return -1.0 + 2.0 * j / (g - 1);
}

/* grid_core's path branch for one job: its candidate parameters in the
 * order it evaluates them (1 to 4); 0: the scalar minimiser decides. s:
 * the job's sum on the grid (stride 16). */
static uint32_t fb_points(const float *S, uint32_t lane, uint32_t g, float mn, uint32_t j1, uint32_t j2, double *u)
{
#define SV(j) ((double)S[16 * (j) + lane])
    if (!(mn <= FLT_MAX)) return 0;
    if (j1 == FB_NONE) return 0;
    uint32_t n = 0;
    double h = 2.0 / (g - 1);
    for (int c = 0; c < 2; ++c) {
        uint32_t jb = c ? j2 : j1;
        if (jb == FB_NONE) continue;
        double u0 = grid_u(jb, g);
        if ((jb == 0 || jb + 1 == g) && g >= 3) {
            uint32_t m = jb ? g - 2 : 1;
            double sl = SV(m - 1), sc = SV(m), sr = SV(m + 1), den = sl - 2.0 * sc + sr;
            double t = den > 0.0 ? 0.5 * (sl - sr) / den : 0.0;
            if (jb ? t > 0.0 && t < 1.0 : t < 0.0 && t > -1.0) u[n++] = grid_u(m, g) + t * h;
        } else {
            double sl = SV(jb ? jb - 1 : g - 1), sc = SV(jb), sr = SV(jb + 1 < g ? jb + 1 : 0);
            double den = sl - 2.0 * sc + sr;
            if (den > 0.0) {
                double t = 0.5 * (sl - sr) / den;
                int fin = den < INFINITY, right = fin && sl > sr;
                if ((!fin || sl != sr) && (right ? jb + 2 < g : jb >= 2)) {
                    double dir = right ? 1.0 : -1.0, ym = right ? sl : sr, yp = right ? sr : sl;
                    double y2 = SV(right ? jb + 2 : jb - 2);
                    double bq = 0.5 * (yp + ym) - sc, c6 = (y2 - sc - 4.0 * bq) - (yp - ym);
                    double aq = 0.5 * (yp - ym) - c6 * (1.0 / 6.0), disc = bq * bq - 0.5 * aq * c6, x;
                    if (fabs(c6) <= 6e-12 * fabs(bq)) x = -aq / (2.0 * bq);
                    else if (disc >= 0.0) {
                        double r = sqrt(disc), q = -(bq + (bq >= 0.0 ? r : -r));
                        x = bq < 0.0 && r > 0.0 ? 2.0 * q / c6 : (q != 0.0 ? aq / q : 2.0 * q / c6);
                    } else x = dir * t;
                    if (x >= -1.0 && x <= 1.5) t = dir * x;
                }
                u0 += (t < -1.0 ? -1.0 : (t > 1.0 ? 1.0 : t)) * h;
                u0 = gs__fun_clamp1(u0);
            }
        }
        u[n++] = u0;
    }
#undef SV
    return n;
}

/* a group: jobs J[0..nj) (nj <= 16) of x's function xf on curve c with
 * grid g; sets each job's res (or fall) */
AVX512 static void fb_group(const fb_ctx *c, const fb_xf *xf, const fb_tgt *T, fb_job **J, uint32_t nj, uint32_t g,
                            const float *tab, uint32_t st, const float *gx, double len, fb_grid *r, float *CF,
                            double *CD, uint32_t mrow)
{
    TS(0);
    uint32_t mmax = xf->m;
    __mmask16 sqm = 0;
    const __m512 zf = _mm512_setzero_ps();
    const __m512d zd = _mm512_setzero_pd();
    for (uint32_t k = 0; k <= mrow; ++k) {
        _mm512_store_ps(CF + 16 * k, zf);
        _mm512_store_pd(CD + 16 * k, zd), _mm512_store_pd(CD + 16 * k + 8, zd);
    }
    for (uint32_t i = 0; i < nj; ++i) {
        fb_job *j = J[i];
        const fb_tgt *t = T + j->t;
        if (!block_coef(j->blk, t->end, CD + i, CF + i)) {
            for (uint32_t k = 0; k <= mrow; ++k) CD[16 * k + i] = 0.0, CF[16 * k + i] = 0.0f;
            j->fall = 1;
            continue;
        }
        if (j->sqy) sqm |= (__mmask16)(1u << i);
        if (j->my > mmax) mmax = j->my;
    }
    (void)c;
    TS(1);
    fb_tab(tab, st, CF, mmax, sqm, gx, g, r);
    TS(2);
    /* the Lipschitz reject, then the candidate points */
    double U[16 * 4];
    uint32_t owner[16 * 4], ne = 0;
    for (uint32_t i = 0; i < nj; ++i) {
        fb_job *j = J[i];
        if (j->fall) continue;
        float mn = r->mn[i];
        double best = T[j->t].best;
        if (len >= 0.0 && mn - FB_LIPSCHITZ * len / (g - 1) >= best) {
            j->res = mn;
            continue;
        }
        double u[4];
        uint32_t n = fb_points(r->S, i, g, mn, r->j1[i], r->j2[i], u);
        if (!n) {
            j->fall = 1;
            continue;
        }
        j->res = INFINITY;
        for (uint32_t q = 0; q < n; ++q) U[ne] = u[q], owner[ne++] = i;
    }
    TS(3);
    /* the values, 8 points at a time, in each job's order */
    for (uint32_t e0 = 0; e0 < ne; e0 += 8) {
        uint32_t ee = ne - e0 < 8 ? ne - e0 : 8;
        __mmask8 sqy = 0;
        double u[8], v[8];
        int32_t ix[16] = {0};
        for (uint32_t l = 0; l < 8; ++l) {
            uint32_t i = owner[e0 + (l < ee ? l : 0)];
            u[l] = U[e0 + (l < ee ? l : 0)];
            ix[l] = (int32_t)i;
            if (J[i]->sqy) sqy |= (__mmask8)(1u << l);
        }
        __m512i idx = _mm512_castsi256_si512(_mm256_loadu_si256((const __m256i *)(const void *)ix));
        idx = _mm512_cvtepi32_epi64(_mm512_castsi512_si256(idx));
        fb_values(xf->c, xf->m, xf->sq, CD, idx, mmax, sqy, u, v);
        for (uint32_t l = 0; l < ee; ++l) {
            fb_job *j = J[owner[e0 + l]];
            if (v[l] < j->res) j->res = v[l];
        }
    }
    for (uint32_t i = 0; i < nj; ++i)
        if (!J[i]->fall && J[i]->res == INFINITY) J[i]->fall = 1; /* grid_core's value at bu: scalar */
    TS(4);
    TA(0, 0, 1), TA(1, 1, 2), TA(2, 2, 3), TA(3, 3, 4);
}

/* ---- the rounds ---- */

static inline double euclid2(const double *p, const double *q)
{
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

typedef struct fb_work {
    fb_tgt *T;
    uint32_t *offs; /* FB_BLOCK x FB_MAXC: the targets' block offsets, packed */
    double *bl;     /* their candidates' bounds (list order), packed      */
    uint32_t *act;  /* the open targets                                   */
    fb_job *jobs, **sorted;
    uint32_t *cnt;  /* nfx + 1 */
    fb_grid *grid;
    float *CF;
    double *CD;
    float gx[GS_FUN_GRID_MAX + 16];
} fb_work;

/* The next candidate of target t (index ti), as a job; 0 when t is done. */
static int next_job(fb_ctx *c, fb_work *w, uint32_t ti, fb_job *j)
{
    fb_tgt *t = w->T + ti;
    if (t->best != t->best || !t->n) return 0; /* malformed: NaN; no curve */
    const uint32_t *ak = c->ak + t->list;
    double *bl = w->bl + t->bo, bm;
    uint32_t m = fb_select(bl, (t->n + 7) & ~7u, &bm);
    if (bm >= t->best) return 0;
    bl[m] = INFINITY; /* visited */
    uint32_t k = ak[m];
    j->t = ti, j->k = k, j->curve = c->acurve[t->list + m], j->fall = 1, j->blk = NULL;
    const fb_xf *xf = xf_get(c, k);
    if (xf->state != 1 || k >= t->nw) return 1;
    const unsigned char *p = t->rec + w->offs[t->po + k];
    __builtin_prefetch(p);
    if ((uint64_t)(t->end - p) < 3) return 1;
    /* the block's head (gs__db_fblock_parse's fast case): an integer or
     * float path without a dip */
    uint32_t meta = p[0], code = meta & GS__FB_DEG_MASK;
    if (code > 24 || (meta & (GS__FB_CLOSED | GS__FB_DIP))) return 1;
    uint32_t d1 = c->db->curves[j->curve].degree1;
    uint32_t mm = xf->m > code ? xf->m : code;
    if (!d1 || mm >= d1) return 1;
    j->my = code, j->sqy = (meta & GS__FB_SQUARED) != 0, j->blk = p;
    j->g = gs__fun_grid_points(mm);
    j->fall = 0;
    return 1;
}

/* one batch of targets w->T[0..nt) */
static int run_batch(fb_ctx *c, fb_work *w, uint32_t nt, double *out)
{
    const gs_db *db = c->db;
    uint32_t nopen = nt;
    for (uint32_t i = 0; i < nt; ++i) w->act[i] = i;
    while (nopen) {
        uint32_t nj = 0, na = 0;
        TS(5);
        for (uint32_t q = 0; q < nopen; ++q) {
            uint32_t i = w->act[q];
            fb_tgt *t = w->T + i;
            fb_job *j = w->jobs + nj;
            if (!next_job(c, w, i, j)) {
                double d = t->best, e = sqrt(t->e2);
                out[t->y] = d != d || d >= e ? d : e;
                continue;
            }
            w->act[na++] = i, ++nj;
        }
        nopen = na;
        TS(6);
        TA(4, 5, 6);
        /* by function k (counting sort), then grid */
        memset(w->cnt, 0, sizeof *w->cnt * (c->nfx + 1));
        for (uint32_t i = 0; i < nj; ++i) w->cnt[w->jobs[i].k + 1]++;
        for (uint32_t k = 0; k < c->nfx; ++k) w->cnt[k + 1] += w->cnt[k];
        for (uint32_t i = 0; i < nj; ++i) w->sorted[w->cnt[w->jobs[i].k]++] = w->jobs + i;
        for (uint32_t i0 = 0; i0 < nj;) {
            uint32_t k = w->sorted[i0]->k, i1 = i0;
            while (i1 < nj && w->sorted[i1]->k == k) ++i1;
            const fb_xf *xf = c->xf + k;
            /* grids of this bucket, one at a time */
            for (;;) {
                uint32_t g = 0, curve = 0;
                for (uint32_t i = i0; i < i1; ++i)
                    if (!w->sorted[i]->fall && w->sorted[i]->g) {
                        g = w->sorted[i]->g, curve = w->sorted[i]->curve;
                        break;
                    }
                if (!g) break;
                uint32_t rows, st;
                const float *tab = gs__grid_path_table(g, &rows, &st);
                fb_job *grp[16];
                uint32_t ng = 0, mrow = xf->m;
                if (tab) gs__grid_values_path(xf->cf, xf->m, (int)xf->sq, g, w->gx);
                for (uint32_t i = i0; i <= i1; ++i) {
                    if (i < i1) {
                        fb_job *j = w->sorted[i];
                        if (j->fall || j->g != g) continue;
                        j->g = 0; /* taken */
                        if (!tab || j->my >= rows || xf->m >= rows) {
                            j->fall = 1; /* no table: scalar */
                            continue;
                        }
                        grp[ng++] = j;
                        if (j->my > mrow) mrow = j->my;
                    }
                    if (ng == 16 || (i == i1 && ng)) {
                        fb_group(c, xf, w->T, grp, ng, g, tab, st, w->gx, db->curves[curve].length, w->grid, w->CF,
                                 w->CD, mrow);
                        ng = 0, mrow = xf->m;
                    }
                }
            }
            i0 = i1;
        }
        TS(7);
        TA(5, 6, 7);
        /* results */
        for (uint32_t i = 0; i < nj; ++i) {
            fb_job *j = w->jobs + i;
            fb_tgt *t = w->T + j->t;
            double d = j->fall ? gs__qsrc_pair(c->s, t->y, t->ly, j->k, j->curve, t->best) : j->res;
            if (d != d) t->best = NAN; /* malformed: NaN, as cross_source */
            else if (d < t->best) t->best = d;
        }
        TS(8);
        TA(6, 7, 8);
    }
    return 1;
}

static int fb_supported(void)
{
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

int gs__field_batch(gs__qsrc *s, const gs_db *db, uint32_t x, double *out)
{
    if (!fb_supported()) return 0;
    fb_ctx c = {0};
    fb_work w = {0};
    c.s = s, c.db = db, c.x = x, c.lx = db->leaf[x];
    c.nfx = db->nodes[c.lx].curve_prefix;
    const unsigned char *xend, *xrec = gs__db_record(db, x, &xend);
    c.xent = (const uint16_t *)(const void *)xrec;
    c.xf = calloc(c.nfx ? c.nfx : 1, sizeof *c.xf);
    c.node_list = malloc((size_t)db->n_nodes * sizeof *c.node_list);
    c.node_n = malloc((size_t)db->n_nodes * sizeof *c.node_n);
    c.top = malloc((size_t)db->n_nodes * sizeof *c.top);
    w.T = malloc(FB_BLOCK * sizeof *w.T);
    w.offs = malloc((size_t)FB_BLOCK * FB_MAXC * sizeof *w.offs);
    w.bl = malloc((size_t)FB_BLOCK * FB_MAXC * sizeof *w.bl);
    w.act = malloc(FB_BLOCK * sizeof *w.act);
    w.jobs = malloc(FB_BLOCK * sizeof *w.jobs);
    w.sorted = malloc(FB_BLOCK * sizeof *w.sorted);
    w.cnt = malloc(((size_t)c.nfx + 2) * sizeof *w.cnt);
    w.grid = aligned_alloc(64, sizeof *w.grid);
    w.CF = aligned_alloc(64, sizeof(float) * 16 * FB_ROWS);
    w.CD = aligned_alloc(64, sizeof(double) * 16 * FB_ROWS);
    int rc = 1;
    if (!c.xf || !c.node_list || !c.node_n || !c.top || !w.T || !w.offs || !w.bl || !w.act || !w.jobs || !w.sorted || !w.cnt || !w.grid ||
        !w.CF || !w.CD) {
        rc = -1;
        goto done;
    }
    for (uint32_t n = 0; n < db->n_nodes; ++n) c.node_list[n] = FB_NONE, c.top[n] = GS_NONE;
    const double *px = db->xyz + 3 * (size_t)x;
    uint32_t nt = 0, po = 0, bo = 0;
    for (uint32_t y = 0; y < db->nv; ++y) {
        uint32_t ly = db->leaf[y];
        if (y + FB_AHEAD < db->nv) { /* the records ahead: their minima and first blocks */
            const unsigned char *e, *p = gs__db_record(db, y + FB_AHEAD, &e);
            __builtin_prefetch(p), __builtin_prefetch(p + 64);
        }
        if (y == x) {
            out[y] = 0.0;
            continue;
        }
        if (ly == GS_NONE) {
            out[y] = INFINITY;
            continue;
        }
        if (ly == c.lx) {
            out[y] = gs__qsrc_distance(s, y);
            continue;
        }
        if (c.top[ly] == GS_NONE) c.top[ly] = gs__qsrc_ancestor(s, ly);
        uint32_t top = c.top[ly];
        double e2 = euclid2(px, db->xyz + 3 * (size_t)y);
        if (!node_list(&c, top)) {
            rc = -1;
            goto done;
        }
        if (c.node_n[top] == FB_NONE || e2 < db->near.radius2) { /* over 64 candidates; a near pair */
            out[y] = gs__qsrc_cross(s, y, ly, top);
            continue;
        }
        fb_tgt *t = w.T + nt;
        t->rec = gs__db_record(db, y, &t->end);
        t->y = y, t->ly = ly, t->list = c.node_list[top], t->n = c.node_n[top];
        t->best = INFINITY, t->e2 = e2, (void)0;
        uint32_t K = db->nodes[top].curve_prefix + db->nodes[top].n_curves;
        t->po = po, t->bo = bo;
        if (!walk(t, db->nodes[ly].curve_prefix, K, c.xent, c.ak + t->list, t->n, w.offs + po, w.bl + bo, &t->nw)) {
            out[y] = gs__qsrc_cross(s, y, ly, top); /* a NaN bound */
            continue;
        }
        po += K, bo += (t->n + 7) & ~7u;
        if (++nt == FB_BLOCK) {
            run_batch(&c, &w, nt, out);
            nt = po = bo = 0;
        }
    }
    if (nt) run_batch(&c, &w, nt, out);
done:
    free(c.xf), free(c.node_list), free(c.node_n), free(c.top), free(c.ak), free(c.acurve);
    free(w.T), free(w.offs), free(w.bl), free(w.act), free(w.jobs), free(w.sorted), free(w.cnt), free(w.grid), free(w.CF), free(w.CD);
    return rc;
}

#else

int gs__field_batch(gs__qsrc *s, const gs_db *db, uint32_t x, double *out)
{
    (void)s, (void)db, (void)x, (void)out;
    return 0;
}

#endif
