/* cheb.h - Chebyshev series kernels behind the separator distance functions
 * (paper sec. 4.2/4.3): Clenshaw evaluation, value with first and second
 * derivative, and precomputed Chebyshev-Lobatto grid tables. Internal. */
#ifndef GS_CHEB_H
#define GS_CHEB_H

#include <stdint.h>

#include "fun.h"

/* Largest coarse grid used by the pair minimiser (intervals, not points). */
#define GS_CHEB_GRID_MAX (3 * GS_FUN_MAX_DEGREE + 8)

/* p(t) = sum_{k<=m} c_k T_k(t) by Clenshaw's recurrence. */
double gs__cheb_eval(const double *c, uint32_t m, double t);

/* p, p' and p'' at t (forward three-term recurrences for T_k, T_k', T_k''). */
void gs__cheb_eval3(const double *c, uint32_t m, double t, double *p, double *p1, double *p2);

/* A Chebyshev-Lobatto grid x_j = -cos(pi j / g), j = 0..g (increasing), with
 * the table tk[k * (g + 1) + j] = T_k(x_j) for k = 0..rows-1. */
typedef struct gs__cheb_grid {
    uint32_t g, rows;
    const double *x;
    const double *tk;
    /* The same nodes padded to np points (a multiple of GS_CHEB_PAD; the
     * padding repeats x_g = 1), 64-byte aligned tables of stride np:
     * tp[k * np + j] = T_k(x_j), dp[k * np + j] = T_k'(x_j). */
    uint32_t np;
    const double *tp;
    const double *dp;
} gs__cheb_grid;

#define GS_CHEB_PAD 8

/* The coarse grid used for series of degree <= m (thread-safe, immutable). */
const gs__cheb_grid *gs__cheb_grid_for(uint32_t m);

/* The fine grid (no table) used to find a single function's minimum. */
#define GS_CHEB_FINE 256
const double *gs__cheb_fine_grid(void);

/* Coarse grid size (number of intervals) for degree m. */
uint32_t gs__cheb_grid_size(uint32_t m);

#endif
