/* fun_internal.h - what the separator distance functions' evaluation
 * (src/fit/fun.c: a function alone, its minimum) shares with the pair
 * minimisers of the queries (src/query/pair_min.c): the frame of a sum of
 * two series, candidate refinement, the sharp-dip and seam helpers.
 * Internal. */
#ifndef GS_FUN_INTERNAL_H
#define GS_FUN_INTERNAL_H

#include "cheb.h"
#include "fun.h"

#include <math.h>
#include <stdint.h>

#define NPTS_MAX (GS_CHEB_FINE + 3)
#define NUDGE 1e-13       /* keep a loop minimiser off the seams          */
#define STOP_REL 1e-11    /* Newton stops when the predicted gain is tiny */
#define ZERO_NUDGE 1e-12  /* step inside a fit's zero set from its edge   */
#define SHARP 0.1         /* minval below SHARP * typical value: sharp     */

/* One series of a sum in the common frame x: t = x + off (per segment). */
typedef struct term {
    const double *c;
    uint32_t m, sq;
} term;

/* The sum a(x) + b(x) in the frame of a (x = t_a); for loops b's seam splits
 * [-1,1] into two segments with t_b = x + off[seg]. */
typedef struct pctx {
    term a, b;     /* b.c == NULL: a alone                 */
    double split;  /* b's seam in (-1,1), or 2: no split   */
    double off[2]; /* t_b = x + off[seg]                   */
    double frame;  /* u = x + frame (wrapped for loops)    */
    int loop;      /* segment ends are seams               */
    int sharp[2];  /* a / b has a narrow dip (near 0)      */
    int eval_only; /* sharp candidates: evaluate, no refine */
} pctx;

typedef struct best {
    double v, x;
    int seg;
} best;


#ifdef GS_FUN_STATS
extern long gs_fun_stat[8];
#define STAT(i) (gs_fun_stat[i]++)
#else
#define STAT(i) ((void)0)
#endif
static inline double gs__fun_clamp1(double t)
{
    return t < -1.0 ? -1.0 : (t > 1.0 ? 1.0 : t);
}

static inline double gs__fun_term_value(const term *f, double p)
{
    if (!(p > 0.0))
        return 0.0;
    return f->sq ? sqrt(p) : p;
}

static inline void gs__fun_best_update(best *b, double x, double v, int seg)
{
    if (v < b->v)
        b->v = v, b->x = x, b->seg = seg;
}

/* A series' value at t (clamped to [-1,1]), as a distance (0 below 0, the
 * root of a squared series). */
double gs__fun_term_at(const term *f, double t);
/* Value, first and second derivative of a term from p, p', p''. */
double gs__fun_term_post(const term *f, double p, double p1, double p2, double *v1, double *v2);
double gs__fun_term_at3(const term *f, double t, double *v1, double *v2);
/* The sum of a pctx at x of segment seg, with its first two derivatives. */
double gs__fun_seg_eval3(const pctx *c, int seg, double x, double *s1, double *s2);
/* Local minimum inside the bracket a <= m <= b (Newton, bracket kept). */
void gs__fun_refine(const pctx *c, int seg, double a, double b, double m, best *bs);
/* A series' own minimum near t in [lo, hi] (*p0: the raw series there),
 * and a root of it in [lo, hi] from t. */
double gs__fun_poly_min(const term *f, double lo, double hi, double t, double *p0);
double gs__fun_poly_root(const term *f, double lo, double hi, double t);
/* The minimum of a sharp term as a candidate of the sum (grid values pg of
 * the term on the grid gp, or NULL). */
void gs__fun_sharp_candidates(const pctx *c, int is_b, const gs_cheb_grid *gp, const double *pg, best *bs);
/* Scan of the sum at n points x (table tk, or NULL) and refinement. */
best gs__fun_minimise(const pctx *c, const double *x, const double *tk, uint32_t n);
/* The parameter u of a minimum found in the frame of c. */
double gs__fun_finish(const pctx *c, best *b);
int gs__fun_unreachable(const gs_fun *f);
/* SEPsam pairs (and a sampled function with a Chebyshev one). */
double gs__fun_sampled_pair_min(const gs_fun *a, const gs_fun *b, double *u_at);
/* A narrow dip: the minimum is small against the typical value. */
int gs__fun_is_sharp(const gs_fun *f);
/* a + b in a's frame; combines the coefficients into comb when the sum is
 * one polynomial (same frame, both plain d, no sharp dip). */
void gs__fun_pair_setup(const gs_fun *a, const gs_fun *b, pctx *c, double *comb);
/* The lower of a loop's one-sided limits at its seam, as a distance. */
double gs__fun_seam_value(const gs_fun *f);

#endif
