/* fit.h - fitting separator distance functions (paper sec. 4.2): weighted
 * least squares (weights 1/d) of d and of d^2 by Chebyshev series of degree
 * 2..m_max, the better kept, stopping at the first degree whose mean
 * relative error is below tol; loops shifted so the largest distance sits
 * at the interval ends. Internal. Arrays in, coefficients out. */
#ifndef GS_FIT_H
#define GS_FIT_H

#include "fun.h"
#include "../core/internal.h"

typedef struct gs__fit_options {
    uint32_t m_min;   /* 2  */
    uint32_t m_max;   /* 12 */
    double tol;       /* 0.005: mean relative error target */
} gs__fit_options;

void gs__fit_options_default(gs__fit_options *o);

/* Result of one fit; coef has room for GS_FUN_MAX_DEGREE+1 values. */
typedef struct gs__fit_result {
    gs__fun fun;                             /* fun.coef points into coef[] */
    double coef[GS_FUN_MAX_DEGREE + 1];
    double mean_rel_err, max_rel_err;       /* on the samples              */
    double cert_err;                        /* between them: the largest   */
                                            /*   relative step outside the */
                                            /*   samples' Lipschitz band   */
    double abs_err;                         /* the largest absolute error, */
                                            /*   at the samples or outside */
                                            /*   the band (units of d)     */
    uint32_t cost;                          /* doubles to store: gs__fun_cost */
} gs__fit_result;

/* Relative errors are measured against max(d, GS_FIT_DFLOOR * max d), and the
 * least-squares weights use the same floor (a vertex on the curve, d = 0,
 * must not blow up). */
#define GS_FIT_DFLOOR 1e-3

/* The tolerance for the functions of the curves of a tree node at `depth`:
 * tol at the root, GS_FIT_TOL_GROWTH times looser per level, but never
 * looser than max(tol, GS_FIT_TOL_CAP). The curves of depth d decide the
 * distances of about 2^-d of the vertex pairs (those split there), so
 * spending the coefficients near the root buys the most accuracy. */
#define GS_FIT_TOL_GROWTH 1.5
#define GS_FIT_TOL_CAP 0.02
double gs__fit_tol_at_depth(double tol, uint32_t depth);

/* The certificate (fit.c, certify): between two samples, the true distance
 * lies in the band the 1-Lipschitz bound allows around them; the fit is
 * checked at GS_FIT_CERT_POINTS points of every interval. A fit is kept at
 * the first degree whose mean error is below tol and whose largest error,
 * at the samples or outside that band, is below GS_FIT_MAX_ERR (else the
 * candidate with the smallest such error). */
#define GS_FIT_CERT_POINTS 3
#define GS_FIT_MAX_ERR 0.02

/* Scratch space for fitting, one per thread. */
typedef struct gs__fit_work gs__fit_work;
int gs__fit_work_create(uint32_t max_samples, const gs__fit_options *o, gs__fit_work **out,
                       gs_error *err);
void gs__fit_work_free(gs__fit_work *w);

/* Fit n samples: u[k] in [-1,1] increasing (curve parameter; for loops in
 * [-1,1), spacing uniform), d[k] > 0 the distances (d[k] == 0 allowed: the
 * vertex lies on the curve; non-finite values are an error). closed: loop.
 * ulen: the curve's arc length per unit of u (length / 2), for the
 * certificate between samples (0: none). The result's fun.coef points into
 * res->coef. */
int gs__fit_distance(gs__fit_work *w, const double *u, const double *d, uint32_t n,
                    int closed, double ulen, gs__fit_result *res, gs_error *err);

/* SEPsam: a function holding the n >= 1 sample values d[k] >= 0 (finite) at
 * uniform u (paths: u_k = -1 + 2k/(n-1); loops: u_k = -1 + 2k/n), evaluated
 * by piecewise-linear interpolation. The values are copied to coef (n
 * doubles, caller-owned, may alias d); out->coef points to coef. */
int gs__fun_make_sampled(const double *d, uint32_t n, int closed, double *coef, gs__fun *out,
                        gs_error *err);

#endif
