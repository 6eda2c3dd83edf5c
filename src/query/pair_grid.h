/* pair_grid.h - a separator distance function tabulated on a uniform query
 * grid of its curve, from its Chebyshev coefficients (paper sec. 4.3, made
 * fast): table dot products with T_k at uniform points, a loop's shift
 * applied by linear interpolation between neighbouring table points.
 * Internal; the query hot path: no allocation. */
#ifndef GS_PAIR_GRID_H
#define GS_PAIR_GRID_H

#include "../fit/fun.h"

/* f's values on the uniform grid of g points (3 <= g <= GS_FUN_GRID_MAX;
 * paths: u_j = -1 + 2j/(g-1); loops: u_j = -1 + 2j/g) into v[0..g): exact
 * (to float rounding) for paths; for loops the series at the uniform
 * points of its own variable t, interpolated linearly to the u grid (within
 * a cell's curvature: the grid locates the minimum, the series then gives
 * the value). Thread-safe (tables built once per g). */
void gs__grid_values(const gs__fun *f, uint32_t g, float *v);

/* gs__grid_values of a path (not closed) of degree m with float
 * coefficients cf[0..m] (the double ones rounded to float), squared or not,
 * into v[0 .. g rounded up to 8) (v must hold that many; the points beyond
 * g are padding): the query's fast path. Thread-safe. */
void gs__grid_values_path(const float *cf, uint32_t m, int squared, uint32_t g, float *v);

/* The sum of two paths' values on the grid of g points (tabled: a g of
 * gs__fun_grid_points; else by gs__grid_values_path), each from its float
 * coefficients (cf, degree m, squared) or given (v: its
 * gs__grid_values_path values, NULL: computed), bit for bit the sum of
 * gs__grid_values_path's: s[0 .. g rounded up to 16) (beyond g: padding);
 * returns the smallest s[j], j < g. jm (or
 * NULL): on hosts where the sum is found in registers (AVX-512), the grid's
 * candidate points as gs__fun_pair_min_grid_sum takes them (jm[0], jm[1]);
 * elsewhere, and when the caller's quick reject holds (the smallest s[j]
 * mn has mn - margin >= best: the caller will not refine the pair), both
 * GS__GRID_NO_MARKS (best = +inf: never). Thread-safe. */
#define GS__GRID_NO_MARKS 0xFFFFFFFEu
float gs__grid_pair_path(const float *ca, uint32_t ma, int sqa, const float *va, const float *cb, uint32_t mb,
                         int sqb, const float *vb, uint32_t g, float *s, uint32_t *jm, double best,
                         double margin);

/* The grid's candidate points from bit masks of its g <= 128 points (bit
 * j of word j / 64): eq, the points <= 1.02 times the minimum and equal to
 * it; lm, those <= 1.02 times it that are discrete local minima. *j1: the
 * first of eq; *j2: the lowest s[j] of lm other than *j1, the first on
 * ties (GS_FUN_NO_CELL for none): the rule of grid_minima (pair_min.c),
 * shared by the kernels that build the masks in registers (inlined into
 * each: the hot path). lm is spent. */
static inline __attribute__((always_inline)) void gs__grid_marks_pick(const uint64_t eq[2], uint64_t lm[2],
                                                                       const float *s, uint32_t *j1, uint32_t *j2)
{
    uint32_t a = eq[0] ? (uint32_t)__builtin_ctzll(eq[0])
                       : eq[1] ? 64 + (uint32_t)__builtin_ctzll(eq[1]) : GS_FUN_NO_CELL;
    if (a != GS_FUN_NO_CELL) lm[a >> 6] &= ~(1ull << (a & 63));
    uint32_t b = GS_FUN_NO_CELL;
    float bv = 0.0f;
    for (int w = 0; w < 2; ++w)
        for (uint64_t z = lm[w]; z; z &= z - 1) {
            uint32_t i = 64 * (uint32_t)w + (uint32_t)__builtin_ctzll(z);
            if (b == GS_FUN_NO_CELL || s[i] < bv) b = i, bv = s[i];
        }
    *j1 = a, *j2 = b;
}

#endif
