/* pair_grid.c - separator distance functions on a pair's uniform query
 * grid (pair_grid.h): tables of T_k at uniform points, built once per grid
 * size, then one dot product per point, eight points at a time; a pair of
 * paths tabulated and summed in one pass. */
#include "pair_grid.h"

#include <math.h>
#include <pthread.h>
#include <string.h>


#define ROWS (GS_FUN_MAX_DEGREE + 1)

#define SLOT0 ((GS_FUN_GRID_MIN - GS_FUN_GRID_B) / GS_FUN_GRID_A + 1) /* rows of the smallest grid */

/* Rows a grid of g points needs: the degrees gs__fun_grid_points gives g
 * for (fun.h; the largest grid serves every degree), so that a small
 * grid's table stays small in memory. */
static inline uint32_t rows_for(uint32_t g)
{
    if (g >= GS_FUN_GRID_MAX) return ROWS;
    uint32_t r = g >= GS_FUN_GRID_B ? (g - GS_FUN_GRID_B) / GS_FUN_GRID_A + 1 : 1;
    return r > ROWS ? ROWS : (r < SLOT0 ? SLOT0 : r);
}
/* g + 3 points, padded to 16: whole vectors of 16 from a row's start stay
 * inside the row (the AVX-512 kernel reads them without masks) */
#define STRIDE(g) ((((g) + 3u) + 15u) & ~15u)

/* The grids the query uses are those of gs__fun_grid_points (one per row
 * count SLOT0..ROWS); their tables are packed one after the other (about
 * 100 KB for each kind), so that those a process touches stay small in
 * memory beside the mapped file. Any other g is tabulated without a table
 * (slow; only callers outside the query). */
#define SLOTS (ROWS - SLOT0 + 1)
#define POOL (GS_FUN_GRID_A * ROWS * ROWS * ROWS / 3 + (GS_FUN_GRID_B + 24) * ROWS * ROWS) /* > sum of r STRIDE(g(r)) */

/* Whether g is a grid of gs__fun_grid_points (and so has a table). */
static inline int tabled(uint32_t g)
{
    return g >= 3 && g <= GS_FUN_GRID_MAX && gs__fun_grid_points(rows_for(g) - 1) == g;
}

/* pool[kind]: for each tabled g, rows_for(g) rows of STRIDE(g) floats:
 * T_k(t_j), paths t_j = -1 + 2j/(g-1) (j < g), loops t_j = -1 + 2(j-1)/g
 * (j <= g + 2: one point beyond each end, for the cubic interpolation of
 * the points next to them); padding repeats the last point. */
static float g_pool[2][POOL] __attribute__((aligned(64))); /* rows start on cache lines */
static const float *g_ptr[2][SLOTS];
static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static unsigned char g_done[2][SLOTS];

/* T_k(t_j) of row k and point j of (loop, g)'s table. */
static double table_t(int loop, uint32_t g, uint32_t j)
{
    uint32_t n = loop ? g + 3 : g, jj = j < n ? j : n - 1;
    return loop ? -1.0 + 2.0 * ((double)jj - 1.0) / g : (jj + 1 == n ? 1.0 : -1.0 + 2.0 * jj / (g - 1));
}

static void fill(float *tab, int loop, uint32_t g)
{
    uint32_t s = STRIDE(g);
    for (uint32_t j = 0; j < s; ++j) {
        double t = table_t(loop, g, j), t0 = 1.0, t1 = t;
        tab[j] = 1.0f;
        for (uint32_t k = 1; k < rows_for(g); ++k) {
            tab[(size_t)k * s + j] = (float)t1;
            double t2 = 2.0 * t * t1 - t0;
            t0 = t1, t1 = t2;
        }
    }
}

/* The table of (loop, g) for a tabled g, built on first use (the fast
 * path: one acquire load of its pointer). */
static const float *table_build(int loop, uint32_t g)
{
    uint32_t slot = rows_for(g) - SLOT0;
    pthread_mutex_lock(&g_lock);
    if (!g_done[loop][slot]) {
        size_t off = 0;
        for (uint32_t r = SLOT0; r < rows_for(g); ++r) off += (size_t)r * STRIDE(gs__fun_grid_points(r - 1));
        fill(g_pool[loop] + off, loop, g);
        __atomic_store_n(&g_ptr[loop][slot], g_pool[loop] + off, __ATOMIC_RELEASE);
        g_done[loop][slot] = 1;
    }
    pthread_mutex_unlock(&g_lock);
    return g_ptr[loop][slot];
}

static inline const float *table(int loop, uint32_t g)
{
    const float *t = __atomic_load_n(&g_ptr[loop][rows_for(g) - SLOT0], __ATOMIC_ACQUIRE);
    return t ? t : table_build(loop, g);
}

/* p_j (j < n) of a g without a table: the series at each point. */
static void dot_slow(int loop, uint32_t g, const double *c, uint32_t m, uint32_t n, float *p)
{
    for (uint32_t j = 0; j < n; ++j) {
        double t = table_t(loop, g, j), t0 = 1.0, t1 = t, a = c[0];
        for (uint32_t k = 1; k <= m; ++k) {
            a += c[k] * t1;
            double t2 = 2.0 * t * t1 - t0;
            t0 = t1, t1 = t2;
        }
        p[j] = (float)a;
    }
}

/* p_j = sum_k c_k tab[k][j] for j < n (n <= stride, a multiple of 4 read):
 * SSE2, or AVX2 with FMA on hosts that have them (x86-64, GCC or clang). */
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HAVE_AVX2_PATH 1
/* Eight (then four) vectors of 8 points at once, in registers: independent
 * sums, whose multiply-adds overlap instead of waiting for each other. */
__attribute__((target("avx2,fma"))) static void dot_avx2(const float *tab, uint32_t s, const float *cf, uint32_t m,
                                                          uint32_t n, float *p)
{
    uint32_t j = 0;
    for (; j + 64 <= n; j += 64) {
        __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0, a4 = a0, a5 = a0, a6 = a0, a7 = a0;
        for (uint32_t k = 0; k <= m; ++k) {
            __m256 ck = _mm256_set1_ps(cf[k]);
            const float *r = tab + (size_t)k * s + j;
            a0 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r), a0);
            a1 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 8), a1);
            a2 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 16), a2);
            a3 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 24), a3);
            a4 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 32), a4);
            a5 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 40), a5);
            a6 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 48), a6);
            a7 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 56), a7);
        }
        _mm256_storeu_ps(p + j, a0), _mm256_storeu_ps(p + j + 8, a1);
        _mm256_storeu_ps(p + j + 16, a2), _mm256_storeu_ps(p + j + 24, a3);
        _mm256_storeu_ps(p + j + 32, a4), _mm256_storeu_ps(p + j + 40, a5);
        _mm256_storeu_ps(p + j + 48, a6), _mm256_storeu_ps(p + j + 56, a7);
    }
    for (; j + 32 <= n; j += 32) {
        __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
        for (uint32_t k = 0; k <= m; ++k) {
            __m256 ck = _mm256_set1_ps(cf[k]);
            const float *r = tab + (size_t)k * s + j;
            a0 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r), a0);
            a1 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 8), a1);
            a2 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 16), a2);
            a3 = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 24), a3);
        }
        _mm256_storeu_ps(p + j, a0), _mm256_storeu_ps(p + j + 8, a1);
        _mm256_storeu_ps(p + j + 16, a2), _mm256_storeu_ps(p + j + 24, a3);
    }
    for (; j + 8 <= n; j += 8) {
        __m256 a0 = _mm256_setzero_ps();
        for (uint32_t k = 0; k <= m; ++k)
            a0 = _mm256_fmadd_ps(_mm256_set1_ps(cf[k]), _mm256_loadu_ps(tab + (size_t)k * s + j), a0);
        _mm256_storeu_ps(p + j, a0);
    }
    for (; j < n; j += 4) {
        __m128 a0 = _mm_setzero_ps();
        for (uint32_t k = 0; k <= m; ++k) a0 = _mm_fmadd_ps(_mm_set1_ps(cf[k]), _mm_loadu_ps(tab + (size_t)k * s + j), a0);
        _mm_storeu_ps(p + j, a0);
    }
}
#endif
#ifdef __SSE2__
#include <emmintrin.h>
#endif

static void dot(const float *tab, uint32_t s, const double *c, uint32_t m, uint32_t n, float *p)
{
    float cf[ROWS];
    for (uint32_t k = 0; k <= m; ++k) cf[k] = (float)c[k];
#ifdef HAVE_AVX2_PATH
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        dot_avx2(tab, s, cf, m, n, p);
        return;
    }
#endif
    uint32_t j = 0;
#ifdef __SSE2__
    for (; j + 16 <= n; j += 16) { /* four independent sums */
        __m128 a0 = _mm_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
        for (uint32_t k = 0; k <= m; ++k) {
            __m128 ck = _mm_set1_ps(cf[k]);
            const float *r = tab + (size_t)k * s + j;
            a0 = _mm_add_ps(a0, _mm_mul_ps(ck, _mm_loadu_ps(r)));
            a1 = _mm_add_ps(a1, _mm_mul_ps(ck, _mm_loadu_ps(r + 4)));
            a2 = _mm_add_ps(a2, _mm_mul_ps(ck, _mm_loadu_ps(r + 8)));
            a3 = _mm_add_ps(a3, _mm_mul_ps(ck, _mm_loadu_ps(r + 12)));
        }
        _mm_storeu_ps(p + j, a0), _mm_storeu_ps(p + j + 4, a1);
        _mm_storeu_ps(p + j + 8, a2), _mm_storeu_ps(p + j + 12, a3);
    }
    for (; j + 4 <= n; j += 4) {
        __m128 a0 = _mm_setzero_ps();
        for (uint32_t k = 0; k <= m; ++k)
            a0 = _mm_add_ps(a0, _mm_mul_ps(_mm_set1_ps(cf[k]), _mm_loadu_ps(tab + (size_t)k * s + j)));
        _mm_storeu_ps(p + j, a0);
    }
#endif
    for (; j < n; ++j) {
        float a = 0.0f;
        for (uint32_t k = 0; k <= m; ++k) a += cf[k] * tab[(size_t)k * s + j];
        p[j] = a;
    }
}

/* p -> the distance: max(p, 0), its square root for a squared series
 * (n a multiple of 4, p readable that far). */
#ifdef HAVE_AVX2_PATH
__attribute__((target("avx2,fma"))) static void to_values_avx2(float *p, uint32_t n, int squared)
{
    const __m256 z = _mm256_setzero_ps();
    uint32_t j = 0;
    if (squared)
        for (; j + 8 <= n; j += 8) _mm256_storeu_ps(p + j, _mm256_sqrt_ps(_mm256_max_ps(_mm256_loadu_ps(p + j), z)));
    else
        for (; j + 8 <= n; j += 8) _mm256_storeu_ps(p + j, _mm256_max_ps(_mm256_loadu_ps(p + j), z));
    for (; j < n; ++j) {
        float v = p[j] > 0.0f ? p[j] : 0.0f;
        p[j] = squared ? sqrtf(v) : v;
    }
}
#endif

#ifdef HAVE_AVX2_PATH
/* One function's values on NB vectors of 8 points from tab's first column
 * on, in one pass over the rows: independent sums in registers (their
 * multiply-adds overlap), then max(p, 0) and the square root of a squared
 * series (the same operations per point as dot_avx2 and to_values_avx2);
 * or loaded when cached (v). */
__attribute__((target("avx2,fma"), always_inline)) static inline void fun_blocks(const float *tab, uint32_t st,
                                                                                const float *cf, uint32_t m,
                                                                                int squared, const float *v,
                                                                                __m256 *a, const int NB)
{
    if (v) {
#pragma GCC unroll 12
        for (int b = 0; b < NB; ++b) a[b] = _mm256_loadu_ps(v + 8 * b);
        return;
    }
#pragma GCC unroll 12
    for (int b = 0; b < NB; ++b) a[b] = _mm256_setzero_ps();
    for (uint32_t k = 0; k <= m; ++k) {
        __m256 ck = _mm256_set1_ps(cf[k]);
        const float *r = tab + (size_t)k * st;
#pragma GCC unroll 12
        for (int b = 0; b < NB; ++b) a[b] = _mm256_fmadd_ps(ck, _mm256_loadu_ps(r + 8 * b), a[b]);
    }
    const __m256 z = _mm256_setzero_ps();
#pragma GCC unroll 12
    for (int b = 0; b < NB; ++b) {
        __m256 x = _mm256_max_ps(a[b], z);
        a[b] = squared ? _mm256_sqrt_ps(x) : x;
    }
}

/* fun_blocks of the NB vectors from point j on, stored to v. */
__attribute__((target("avx2,fma"), always_inline)) static inline void path_blocks(const float *tab, uint32_t s,
                                                                                 const float *cf, uint32_t m,
                                                                                 int squared, uint32_t j, float *v,
                                                                                 const int NB)
{
    __m256 a[6];
    fun_blocks(tab + j, s, cf, m, squared, NULL, a, NB);
#pragma GCC unroll 6
    for (int b = 0; b < NB; ++b) _mm256_storeu_ps(v + j + 8 * b, a[b]);
}

__attribute__((target("avx2,fma"))) static void path_avx2(const float *tab, uint32_t s, const float *cf, uint32_t m,
                                                           int squared, uint32_t g, float *v)
{
    uint32_t nb = (g + 7) / 8, j = 0;
    while (nb) {
        uint32_t b = nb <= 6 ? nb : (nb + 1) / 2;
        switch (b) {
        case 1: path_blocks(tab, s, cf, m, squared, j, v, 1); break;
        case 2: path_blocks(tab, s, cf, m, squared, j, v, 2); break;
        case 3: path_blocks(tab, s, cf, m, squared, j, v, 3); break;
        case 4: path_blocks(tab, s, cf, m, squared, j, v, 4); break;
        case 5: path_blocks(tab, s, cf, m, squared, j, v, 5); break;
        default: b = 6; path_blocks(tab, s, cf, m, squared, j, v, 6); break;
        }
        nb -= b, j += 8 * b;
    }
}
#endif

static void to_values(float *p, uint32_t n, int squared)
{
#ifdef HAVE_AVX2_PATH
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        to_values_avx2(p, n, squared);
        return;
    }
#endif
#ifdef __SSE2__
    const __m128 z = _mm_setzero_ps();
    if (squared)
        for (uint32_t j = 0; j < n; j += 4) _mm_storeu_ps(p + j, _mm_sqrt_ps(_mm_max_ps(_mm_loadu_ps(p + j), z)));
    else
        for (uint32_t j = 0; j < n; j += 4) _mm_storeu_ps(p + j, _mm_max_ps(_mm_loadu_ps(p + j), z));
#else
    for (uint32_t j = 0; j < n; ++j) {
        float v = p[j] > 0.0f ? p[j] : 0.0f;
        p[j] = squared ? sqrtf(v) : v;
    }
#endif
}

void gs__grid_values(const gs__fun *f, uint32_t g, float *v)
{
    g = g < 3 ? 3 : (g > GS_FUN_GRID_MAX ? GS_FUN_GRID_MAX : g);
    int loop = f->closed != 0;
    uint32_t s = STRIDE(g), n = loop ? g + 3 : g;
    float p[STRIDE(GS_FUN_GRID_MAX) + 4];
    /* a degree beyond the grid's rows (a curve's degree1 below one of its
     * functions: a corrupt file not verified) reads no further than them */
    uint32_t m = f->degree < rows_for(g) ? f->degree : rows_for(g) - 1;
    if (tabled(g)) dot(table(loop, g), s, f->coef, m, (n + 3u) & ~3u, p);
    else dot_slow(loop, g, f->coef, m, (n + 3u) & ~3u, p);
    if (!loop) {
        to_values(p, (g + 3u) & ~3u, f->squared);
        memcpy(v, p, sizeof *v * g);
        return;
    }
    /* u_j - shift, in grid units of t, wrapped into [0, g): j + b + phi;
     * the series there by cubic interpolation of its four neighbours
     * (table index + 1: the table starts one point before t = -1) */
    double S = -f->shift * 0.5 * g, fb = floor(S), phi = S - fb;
    long b = (long)fb % (long)g;
    if (b < 0) b += g;
    float x = (float)phi, wm = -x * (x - 1) * (x - 2) / 6, w0 = (x + 1) * (x - 1) * (x - 2) / 2,
          w1 = -(x + 1) * x * (x - 2) / 2, w2 = (x + 1) * x * (x - 1) / 6;
    uint32_t i = (uint32_t)b;
    float q[GS_FUN_GRID_MAX + 4];
    for (uint32_t j = 0; j < g; ++j) {
        q[j] = wm * p[i] + w0 * p[i + 1] + w1 * p[i + 2] + w2 * p[i + 3];
        if (++i == g) i = 0;
    }
    for (uint32_t j = g; j < ((g + 3u) & ~3u); ++j) q[j] = 0.0f;
    to_values(q, (g + 3u) & ~3u, f->squared);
    memcpy(v, q, sizeof *v * g);
}

void gs__grid_values_path(const float *cf, uint32_t m, int squared, uint32_t g, float *v)
{
    g = g < 3 ? 3 : (g > GS_FUN_GRID_MAX ? GS_FUN_GRID_MAX : g);
    uint32_t s = STRIDE(g);
    m = m < rows_for(g) ? m : rows_for(g) - 1;
    if (!tabled(g)) {
        double c[ROWS];
        float p[STRIDE(GS_FUN_GRID_MAX)];
        for (uint32_t k = 0; k <= m; ++k) c[k] = cf[k];
        dot_slow(0, g, c, m, g, p);
        for (uint32_t j = 0; j < g; ++j) {
            float a = p[j] > 0.0f ? p[j] : 0.0f;
            v[j] = squared ? sqrtf(a) : a;
        }
        return;
    }
    const float *tab = table(0, g);
#ifdef HAVE_AVX2_PATH
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        path_avx2(tab, s, cf, m, squared, g, v);
        return;
    }
#endif
    for (uint32_t j = 0; j < g; ++j) {
        float a = 0.0f;
        for (uint32_t k = 0; k <= m; ++k) a += cf[k] * tab[(size_t)k * s + j];
        a = a > 0.0f ? a : 0.0f;
        v[j] = squared ? sqrtf(a) : a;
    }
}

/* ---- both functions of a path pair at once -------------------------------- */

#ifdef HAVE_AVX2_PATH
static const int32_t lane_mask[16] = {-1, -1, -1, -1, -1, -1, -1, -1, 0, 0, 0, 0, 0, 0, 0, 0};

/* The whole grid (NB = its vectors of 8 points) in one pass over each
 * function's rows: a's values go to s, then b's are added to them. */
__attribute__((target("avx2,fma"), always_inline)) static inline float pair_nb(
    const float *tab, uint32_t st, const float *ca, uint32_t ma, int sqa, const float *va, const float *cb,
    uint32_t mb, int sqb, const float *vb, uint32_t g, float *s, const int NB)
{
    __m256 a[12];
    fun_blocks(tab, st, ca, ma, sqa, va, a, NB);
#pragma GCC unroll 12
    for (int i = 0; i < NB; ++i) _mm256_storeu_ps(s + 8 * i, a[i]);
    fun_blocks(tab, st, cb, mb, sqb, vb, a, NB);
    __m256 mn = _mm256_set1_ps(INFINITY);
#pragma GCC unroll 12
    for (int i = 0; i < NB; ++i) {
        __m256 x = _mm256_add_ps(_mm256_loadu_ps(s + 8 * i), a[i]);
        _mm256_storeu_ps(s + 8 * i, x);
        if (i < NB - 1) mn = _mm256_min_ps(mn, x);
        else /* the lanes beyond the grid: not a minimum */
            mn = _mm256_min_ps(mn, _mm256_blendv_ps(_mm256_set1_ps(INFINITY), x,
                                                    _mm256_castsi256_ps(_mm256_loadu_si256(
                                                        (const __m256i *)(lane_mask + 8 - (g - 8 * i))))));
    }
    __m128 m4 = _mm_min_ps(_mm256_castps256_ps128(mn), _mm256_extractf128_ps(mn, 1));
    m4 = _mm_min_ps(m4, _mm_movehl_ps(m4, m4));
    m4 = _mm_min_ss(m4, _mm_shuffle_ps(m4, m4, 1));
    return _mm_cvtss_f32(m4);
}

#define PAIR_NB(n) \
    case n: return pair_nb(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s, n)

__attribute__((target("avx2,fma"))) static float pair_path_avx2(const float *tab, uint32_t st, const float *ca,
                                                                 uint32_t ma, int sqa, const float *va,
                                                                 const float *cb, uint32_t mb, int sqb,
                                                                 const float *vb, uint32_t g, float *s)
{
    switch ((g + 7) / 8) { /* g <= GS_FUN_GRID_MAX = 96: at most 12 */
        PAIR_NB(1); PAIR_NB(2); PAIR_NB(3); PAIR_NB(4); PAIR_NB(5); PAIR_NB(6);
        PAIR_NB(7); PAIR_NB(8); PAIR_NB(9); PAIR_NB(10); PAIR_NB(11);
    default: return pair_nb(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s, 12);
    }
}
#endif

#ifdef HAVE_AVX2_PATH
#define HAVE_AVX512_PATH 1
#define AVX512 __attribute__((target("avx512f,avx2,fma")))

/* fun_blocks sixteen points a vector (the same operations per point, so
 * the same values bit for bit): NB vectors (table rows: whole vectors, a
 * masked load would lengthen each row's chain; given values v: the last
 * vector's lanes beyond `last` not read, zeros). */
AVX512 __attribute__((always_inline)) static inline void fun_blocks16(const float *tab, uint32_t st,
                                                                      const float *cf, uint32_t m, int squared,
                                                                      const float *v, __mmask16 last, __m512 *a,
                                                                      const int NB)
{
    if (v) {
#pragma GCC unroll 6
        for (int b = 0; b < NB; ++b) a[b] = b < NB - 1 ? _mm512_loadu_ps(v + 16 * b) : _mm512_maskz_loadu_ps(last, v + 16 * b);
        return;
    }
#pragma GCC unroll 6
    for (int b = 0; b < NB; ++b) a[b] = _mm512_setzero_ps();
    for (uint32_t k = 0; k <= m; ++k) {
        __m512 ck = _mm512_set1_ps(cf[k]);
        const float *r = tab + (size_t)k * st;
#pragma GCC unroll 6
        for (int b = 0; b < NB; ++b)
            a[b] = _mm512_fmadd_ps(ck, _mm512_loadu_ps(r + 16 * b), a[b]);
    }
    const __m512 z = _mm512_setzero_ps();
    const __mmask16 sq = (__mmask16)(squared ? 0xFFFFu : 0u); /* a select, not a branch */
#pragma GCC unroll 6
    for (int b = 0; b < NB; ++b) {
        __m512 x = _mm512_max_ps(a[b], z);
        a[b] = _mm512_mask_sqrt_ps(x, sq, x);
    }
}

/* pair_nb sixteen points a vector, the sum kept in registers for the
 * grid's candidate points (grid_minima's rule in pair_min.c: jm[0] the
 * first point equal to the minimum, jm[1] the first of the lowest other
 * discrete local minima, both <= 1.02 times the minimum; the ends' outer
 * neighbours +inf): lanes beyond the grid are +inf. */
AVX512 __attribute__((always_inline)) static inline float pair16(const float *tab, uint32_t st, const float *ca,
                                                                 uint32_t ma, int sqa, const float *va,
                                                                 const float *cb, uint32_t mb, int sqb,
                                                                 const float *vb, uint32_t g, float *s, uint32_t *jm,
                                                                 double best, double margin, const int NB)
{
    __m512 x[6], y[6];
    const __mmask16 last = (__mmask16)((1u << (g - 16 * (NB - 1))) - 1u);
    const __m512 inf = _mm512_set1_ps(INFINITY);
    fun_blocks16(tab, st, ca, ma, sqa, va, last, x, NB);
    fun_blocks16(tab, st, cb, mb, sqb, vb, last, y, NB);
    __m512 mv = inf;
#pragma GCC unroll 6
    for (int i = 0; i < NB; ++i) {
        x[i] = _mm512_add_ps(x[i], y[i]);
        if (i == NB - 1) x[i] = _mm512_mask_blend_ps(last, inf, x[i]);
        _mm512_storeu_ps(s + 16 * i, x[i]);
        mv = _mm512_min_ps(mv, x[i]);
    }
    float mn = _mm512_reduce_min_ps(mv);
    if (!jm || mn - margin >= best) return mn; /* the caller's quick reject: no marks */
    const __m512 t = _mm512_set1_ps(mn * 1.02f), m = _mm512_set1_ps(mn);
    uint64_t eq[2] = {0, 0}, lm[2] = {0, 0};
#pragma GCC unroll 6
    for (int i = 0; i < NB; ++i) {
        __m512i c = _mm512_castps_si512(x[i]);
        __m512 l = _mm512_castsi512_ps(_mm512_alignr_epi32(c, _mm512_castps_si512(i ? x[i - 1] : inf), 15));
        __m512 r = _mm512_castsi512_ps(_mm512_alignr_epi32(_mm512_castps_si512(i < NB - 1 ? x[i + 1] : inf), c, 1));
        __mmask16 le = _mm512_cmp_ps_mask(x[i], t, _CMP_LE_OQ);
        __mmask16 q = _mm512_mask_cmp_ps_mask(le, x[i], m, _CMP_EQ_OQ);
        __mmask16 n = _mm512_mask_cmp_ps_mask(_mm512_mask_cmp_ps_mask(le, x[i], l, _CMP_LE_OQ), x[i], r, _CMP_LE_OQ);
        if (i == NB - 1) q &= last, n &= last;
        eq[i >> 2] |= (uint64_t)q << (16 * (i & 3));
        lm[i >> 2] |= (uint64_t)n << (16 * (i & 3));
    }
    gs__grid_marks_pick(eq, lm, s, &jm[0], &jm[1]);
    return mn;
}

#define PAIR16(n) \
    case n: return pair16(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s, jm, best, margin, n)

AVX512 static float pair_path_avx512(const float *tab, uint32_t st, const float *ca, uint32_t ma, int sqa,
                                     const float *va, const float *cb, uint32_t mb, int sqb, const float *vb,
                                     uint32_t g, float *s, uint32_t *jm, double best, double margin)
{
    switch ((g + 15) / 16) { /* g <= GS_FUN_GRID_MAX = 96: at most 6 */
        PAIR16(1); PAIR16(2); PAIR16(3); PAIR16(4); PAIR16(5);
    default: return pair16(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s, jm, best, margin, 6);
    }
}
#endif

/* One function's value at path grid point j (gs__grid_values_path's
 * scalar operations). */
static inline float fun_point(const float *tab, uint32_t st, const float *cf, uint32_t m, int squared, uint32_t j)
{
    float a = 0.0f;
    for (uint32_t k = 0; k <= m; ++k) a += cf[k] * tab[(size_t)k * st + j];
    a = a > 0.0f ? a : 0.0f;
    return squared ? sqrtf(a) : a;
}

float gs__grid_pair_path(const float *ca, uint32_t ma, int sqa, const float *va, const float *cb, uint32_t mb,
                         int sqb, const float *vb, uint32_t g, float *s, uint32_t *jm, double best,
                         double margin)
{
    if (jm) jm[0] = jm[1] = GS__GRID_NO_MARKS;
    uint32_t r = rows_for(g);
    if (g < 3 || g > GS_FUN_GRID_MAX || gs__fun_grid_points(r - 1) != g || ma >= r || mb >= r) {
        float ta[GS_FUN_GRID_MAX + 8], tb[GS_FUN_GRID_MAX + 8], mn = INFINITY;
        if (!va) gs__grid_values_path(ca, ma, sqa, g, ta), va = ta;
        if (!vb) gs__grid_values_path(cb, mb, sqb, g, tb), vb = tb;
        g = g < 3 ? 3 : (g > GS_FUN_GRID_MAX ? GS_FUN_GRID_MAX : g);
        for (uint32_t j = 0; j < g; ++j) s[j] = va[j] + vb[j], mn = s[j] < mn ? s[j] : mn;
        return mn;
    }
    const float *tab = table(0, g);
    uint32_t st = STRIDE(g);
#ifdef HAVE_AVX512_PATH
    if (__builtin_cpu_supports("avx512f")) return pair_path_avx512(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s, jm, best, margin);
#endif
#ifdef HAVE_AVX2_PATH
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
        return pair_path_avx2(tab, st, ca, ma, sqa, va, cb, mb, sqb, vb, g, s);
#endif
    float mn = INFINITY;
    for (uint32_t j = 0; j < g; ++j) {
        float x = (va ? va[j] : fun_point(tab, st, ca, ma, sqa, j)) + (vb ? vb[j] : fun_point(tab, st, cb, mb, sqb, j));
        s[j] = x;
        mn = x < mn ? x : mn;
    }
    return mn;
}
