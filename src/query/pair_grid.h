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
 * elsewhere both GS__GRID_NO_MARKS. Thread-safe. */
#define GS__GRID_NO_MARKS 0xFFFFFFFEu
float gs__grid_pair_path(const float *ca, uint32_t ma, int sqa, const float *va, const float *cb, uint32_t mb,
                         int sqb, const float *vb, uint32_t g, float *s, uint32_t *jm);

#endif
