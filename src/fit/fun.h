/* fun.h - separator distance functions (paper sec. 4.2, 4.3): Chebyshev
 * series on [-1,1] approximating d or d^2 along a curve, evaluated with
 * Clenshaw, and the minimisation of the sum of two of them (eq. 3/4) that
 * every query runs. Internal; the query hot path: no allocation. */
#ifndef GS_FUN_H
#define GS_FUN_H

#include <stdint.h>

#define GS_FUN_MAX_DEGREE 24

/* A view of one stored function. The curve parameter u runs over [-1,1]
 * along the curve's arc length (u = -1 at its start). For a loop (closed),
 * u is periodic with period 2 and the polynomial's own variable is
 * t = wrap(u - shift) in [-1,1), chosen when fitting so that the largest
 * distance sits at the interval ends. */
enum { GS_FUN_CHEBYSHEV = 0, GS_FUN_SAMPLED = 1 };

typedef struct gs__fun {
    uint32_t kind;       /* GS_FUN_CHEBYSHEV, or GS_FUN_SAMPLED (SEPsam:  */
                         /*   coef holds degree+1 values at uniform u,    */
                         /*   piecewise linear; loops: u_k = -1 + 2k/n)   */
    uint32_t degree;     /* m: m+1 coefficients                           */
    uint32_t squared;    /* 1: the series approximates d^2 (value = sqrt) */
    uint32_t closed;     /* 1: loop                                        */
    double shift;        /* loops only; 0 for paths                        */
    double minval;       /* min over u of the distance (quick reject);     */
                         /*   +INFINITY: the curve is unreachable (no coef) */
    const double *coef;  /* m+1 Chebyshev coefficients c_0..c_m            */
} gs__fun;

/* Distance at curve parameter u (clamped to >= 0). */
double gs__fun_value(const gs__fun *f, double u);

/* min over u in [-1,1] of a(u) + b(u) for two functions of the same curve;
 * *u_at (may be NULL) receives the minimiser. Robust: never misses the
 * global minimum of the dense scan by more than 1e-9 relative (tests prove
 * it), fast: a coarse scan then Newton on the analytic derivative. */
double gs__fun_pair_min(const gs__fun *a, const gs__fun *b, double *u_at);

/* As gs__fun_pair_min, but the caller only needs the minimum when it is
 * below `best` (the query's running minimum): candidate basins that cannot
 * beat min(best, the best value found) are skipped. Returns the same value
 * and *u_at as gs__fun_pair_min whenever that is < best; otherwise some value
 * >= best (as evaluated at the returned *u_at). best = +INFINITY: exactly
 * gs__fun_pair_min. */
double gs__fun_pair_min_below(const gs__fun *a, const gs__fun *b, double best, double *u_at);

/* Number of doubles the function costs to store: its m+1 coefficients (or
 * samples), plus 1 for a Chebyshev loop's shift; 0 for an unreachable curve
 * (minval = +INFINITY, no coefficients). minval itself is not counted. */
uint32_t gs__fun_cost(const gs__fun *f);

/* The minimum over u of one function (as evaluated by gs__fun_value), found
 * with a fine grid and Newton refinement; *u_at (may be NULL) receives the
 * minimiser. The fitter stores it as minval. Ignores f->minval. */
double gs__fun_min(const gs__fun *f, double *u_at);

/* Wrap a curve parameter to the period [-1,1). */
static inline double gs__fun_wrap(double u)
{
    /* already in [-1,1): the general rule's result, without floor (below
     * 1 - 2^-53, the largest double under 1, whose u + 1 rounds to 2) */
    if (u >= -1.0 && u < 1.0 - 0x1p-53) return u;
    if (u >= 1.0 && u < 3.0) return u - 2.0; /* one period off: the rule's  */
    if (u >= -3.0 && u < -1.0) return u + 2.0; /*   floor is +-1, exactly    */
    double t = u - 2.0 * __builtin_floor((u + 1.0) * 0.5);
    return t < -1.0 ? -1.0 : (t >= 1.0 ? -1.0 : t);
}

/* Largest grid of gs__fun_pair_min_grid. */
#define GS_FUN_GRID_MAX 96

/* The query's grid for a pair of functions whose higher degree is m (the
 * pair's own, not its curve's: a pair of low degrees needs fewer points):
 * GS_FUN_GRID_A m + GS_FUN_GRID_B points, at least GS_FUN_GRID_MIN, at most
 * GS_FUN_GRID_MAX (gs__fun_grid_points). Coarser grids (2 m + 9, m + 12)
 * keep the all-pairs errors against exact distances but leave the grid
 * minimiser further above the robust one than test_fit and test_query
 * allow (doc/performance.md, "What a query does"). */
#ifndef GS_FUN_GRID_A
#define GS_FUN_GRID_A 4u
#endif
#ifndef GS_FUN_GRID_B
#define GS_FUN_GRID_B 9u
#endif
#ifndef GS_FUN_GRID_MIN
#define GS_FUN_GRID_MIN 33u
#endif

/* Grid points for a pair of functions whose higher degree is m (above). */
static inline uint32_t gs__fun_grid_points(uint32_t m)
{
    uint32_t g = GS_FUN_GRID_A * m + GS_FUN_GRID_B;
    g = g < GS_FUN_GRID_MIN ? GS_FUN_GRID_MIN : g;
    return g > GS_FUN_GRID_MAX ? GS_FUN_GRID_MAX : g;
}

/* Whether f has a sharp dip (its minimum is below a tenth of its typical
 * value: a vertex close to the curve), the case where
 * gs__fun_pair_min_grid needs f's own minimiser. */
int gs__fun_is_sharp(const gs__fun *f);

/* The dip of a sharp function: its own minimiser u and, when its fit dips
 * below 0 there (the value is clamped to 0), the edges lo < u < hi of that
 * zero set (else lo = hi = u); u = NaN: not sharp. Loops: lo and hi are u
 * plus offsets (wrap them). */
typedef struct gs__fun_dip {
    double u, lo, hi;
    double slope;  /* the dip's hyperbola: f(u + s) ~ sqrt(f(u)^2 + (slope
                    *   s)^2), slope = sqrt(f(u) f''(u)); 0 when f has a
                    *   zero set (lo < hi) or u = NaN                       */
    double seam;   /* loops: the lower of f's one-sided limits at its seam
                    *   (t = 1 and t = -1); NaN for paths                   */
    uint32_t seam_cell; /* loops, for the grid of g points the caller uses:
                    *   gs__fun_seam_cell(f, g), kept so that each query
                    *   need not find it again; GS_FUN_NO_CELL: not given
                    *   (found when needed)                                 */
} gs__fun_dip;

#define GS_FUN_NO_CELL 0xFFFFFFFFu

/* The dip of f (u = NaN unless gs__fun_is_sharp(f)) and a loop's seam
 * value (for every loop); seam_cell = GS_FUN_NO_CELL. */
void gs__fun_dip_find(const gs__fun *f, gs__fun_dip *d);

/* A loop's seam (u_s = wrap(shift - 1), where its t passes from 1 to -1)
 * on the uniform grid of g points: the cell j with u_j <= u_s < u_{j+1}
 * (j + 1 taken modulo g), by the rule gs__fun_pair_min_grid uses. */
uint32_t gs__fun_seam_cell(const gs__fun *f, uint32_t g);

/* The query hot path: min over u of a(u) + b(u) given both functions'
 * values on the same grid of g points (src/query/pair_grid.h) and each
 * function's dip (da, db: gs__fun_dip_find; NULL or u = NaN: none). The
 * grid cell of the minimum is found from the tables and refined by a
 * parabola through the three values around it, where the exact sum is
 * evaluated; a path's end cell by the parabola of the last three; when a
 * function has a sharp dip (a vertex close to the curve) its own minimiser
 * is refined by Newton and its zero set's edges are candidates; for a loop,
 * a window of a few cells around a sharp dip, and each side of a seam that
 * may hold the minimum (the fit jumps there), is searched with the series
 * (values and slopes, then a bracketed Newton). The result is a value the
 * functions reach (tests compare it with gs__fun_pair_min). Sampled and
 * unreachable functions, grids without a step, two seams close together
 * and windows that bracket nothing clearly (rare) go to gs__fun_pair_min. */
double gs__fun_pair_min_grid(const gs__fun *a, const gs__fun *b, const float *ga, const float *gb, uint32_t g,
                            const gs__fun_dip *da, const gs__fun_dip *db, double *u_at);

/* gs__fun_pair_min_grid of two paths given the sum of their grid values
 * instead: s = e + 1 holds s[j] = ga[j] + gb[j] for j < g (e readable and
 * writable from e[0] to e[g + 8]: the ends' neighbours go there), mn the
 * smallest s[j]. jm: the grid's two candidate points when the caller found
 * them with the sum (jm[0]: the first j with s[j] == mn <= 1.02 mn; jm[1]:
 * the first j != jm[0] of the lowest other discrete local minimum s[j] <=
 * 1.02 mn, the ends' outer neighbours +inf; GS_FUN_NO_CELL: none), NULL:
 * searched here. The same result, bit for bit (loops: gs__fun_pair_min). */
double gs__fun_pair_min_grid_sum(const gs__fun *a, const gs__fun *b, float *e, float mn, uint32_t g,
                                const uint32_t *jm, const gs__fun_dip *da, const gs__fun_dip *db, double *u_at);

#endif
