/* eval.c - accuracy of a candidate distance field against an exact one, as
 * the paper's section 5 measures it: ME (L1) and RMSE (L2) of the relative
 * error e(y) = |d - d^| / d per vertex, and the largest e; and the tail over
 * many fields (gs_error_acc): quantiles, max, near pairs, under/over. */
#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Rules (shared/groundtruth/README.md, "Error measures"): y == source is
 * left out; y with d == 0 or d not finite is skipped (n_skipped); where d is
 * finite and > 0, a candidate that is negative or not finite is counted in
 * n_invalid and left out of the means; all other y are used. With no pair
 * used, me = rmse = max = NaN. */
int gs_field_errors_compute(const double *exact, const double *approx, uint32_t n, uint32_t source,
                            gs_field_errors *out, gs_error *err)
{
    if (!exact || !approx || !out) return gs__fail(err, GS_EARG, "gs_field_errors_compute: NULL argument");
    if (source >= n) return gs__fail(err, GS_EARG, "gs_field_errors_compute: source %u >= n %u", source, n);
    memset(out, 0, sizeof *out);
    double sum = 0, sum2 = 0, max = 0;
    for (uint32_t y = 0; y < n; ++y) {
        if (y == source) continue;
        double d = exact[y], a = approx[y];
        if (!isfinite(d) || !(d > 0)) { /* d <= 0 never happens for exact fields */
            out->n_skipped++;
            continue;
        }
        if (!isfinite(a) || a < 0) {
            out->n_invalid++;
            continue;
        }
        double e = fabs(d - a) / d;
        sum += e;
        sum2 += e * e;
        if (e > max) max = e;
        out->n_used++;
    }
    if (out->n_used) {
        out->me = sum / (double)out->n_used;
        out->rmse = sqrt(sum2 / (double)out->n_used);
        out->max = max;
    } else {
        out->me = out->rmse = out->max = NAN;
    }
    return GS_OK;
}

/* ---- tail statistics over many fields ------------------------------------ */

struct gs_error_acc {
    float *e, *d;           /* per pair: relative error, exact distance */
    signed char *sgn;       /* +1 over, -1 under, 0 exact                */
    size_t n, cap;
    double sum_me, sum_rmse; /* per-source means, summed                 */
    uint32_t n_fields;
    uint64_t n_skipped, n_invalid;
};

int gs_error_acc_create(gs_error_acc **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_error_acc_create: NULL argument");
    *out = gs__calloc(1, sizeof **out);
    return *out ? GS_OK : gs__fail(err, GS_ENOMEM, "out of memory");
}

void gs_error_acc_free(gs_error_acc *a)
{
    if (!a) return;
    free(a->e);
    free(a->d);
    free(a->sgn);
    free(a);
}

static int acc_reserve(gs_error_acc *a, size_t need, gs_error *err)
{
    if (need <= a->cap) return GS_OK;
    size_t cap = a->cap ? a->cap : 4096;
    while (cap < need) cap *= 2;
    float *e = gs__realloc(a->e, cap, sizeof *e);
    if (e) a->e = e;
    float *d = e ? gs__realloc(a->d, cap, sizeof *d) : NULL;
    if (d) a->d = d;
    signed char *s = d ? gs__realloc(a->sgn, cap, sizeof *s) : NULL;
    if (s) a->sgn = s;
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory for the errors of %zu pairs", need);
    a->cap = cap;
    return GS_OK;
}

int gs_error_acc_add(gs_error_acc *a, const double *exact, const double *approx, uint32_t n, uint32_t source,
                     gs_error *err)
{
    if (!a || !exact || !approx) return gs__fail(err, GS_EARG, "gs_error_acc_add: NULL argument");
    gs_field_errors fe;
    int rc = gs_field_errors_compute(exact, approx, n, source, &fe, err);
    if (rc) return rc;
    if ((rc = acc_reserve(a, a->n + fe.n_used, err))) return rc;
    for (uint32_t y = 0; y < n; ++y) {
        double d = exact[y], x = approx[y];
        if (y == source || !isfinite(d) || !(d > 0) || !isfinite(x) || x < 0) continue;
        a->e[a->n] = (float)(fabs(d - x) / d);
        a->d[a->n] = (float)d;
        a->sgn[a->n] = x > d ? 1 : x < d ? -1 : 0;
        a->n++;
    }
    if (fe.n_used) {
        a->sum_me += fe.me;
        a->sum_rmse += fe.rmse;
        a->n_fields++;
    }
    a->n_skipped += fe.n_skipped;
    a->n_invalid += fe.n_invalid;
    return GS_OK;
}

/* The k-th smallest (0-based) of v[0..n-1] (reorders v): Hoare selection. */
static float select_kth(float *v, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        float p = v[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < p) ++i;
            while (v[j] > p) --j;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
                ++i;
                if (j == 0) break;
                --j;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else break;
    }
    return v[k];
}

/* Nearest-rank quantile: the value at rank ceil(q n) (1-based). */
static double quantile(const float *src, size_t n, double q, float *tmp)
{
    memcpy(tmp, src, n * sizeof *tmp);
    size_t r = (size_t)ceil(q * (double)n);
    if (r < 1) r = 1;
    if (r > n) r = n;
    return select_kth(tmp, n, r - 1);
}

int gs_error_acc_result(const gs_error_acc *a, double near_frac, gs_error_stats *out, gs_error *err)
{
    if (!a || !out) return gs__fail(err, GS_EARG, "gs_error_acc_result: NULL argument");
    if (!(near_frac >= 0) || !isfinite(near_frac))
        return gs__fail(err, GS_EARG, "gs_error_acc_result: near_frac %g is not a finite number >= 0", near_frac);
    memset(out, 0, sizeof *out);
    out->near_frac = near_frac;
    out->n_fields = a->n_fields;
    out->n_used = a->n;
    out->n_skipped = a->n_skipped;
    out->n_invalid = a->n_invalid;
    if (!a->n) {
        out->me = out->rmse = out->p99 = out->p999 = out->max = out->near_me = out->median_d = NAN;
        out->max_under = out->max_over = NAN;
        return GS_OK;
    }
    float *tmp = gs__malloc(a->n, sizeof *tmp);
    if (!tmp) return gs__fail(err, GS_ENOMEM, "out of memory for the quantiles of %zu pairs", a->n);
    out->me = a->sum_me / a->n_fields;
    out->rmse = a->sum_rmse / a->n_fields;
    out->median_d = quantile(a->d, a->n, 0.5, tmp);
    out->p99 = quantile(a->e, a->n, 0.99, tmp);
    out->p999 = quantile(a->e, a->n, 0.999, tmp);
    free(tmp);
    double near = near_frac * out->median_d, sum_near = 0, mx = 0, under = 0, over = 0;
    for (size_t i = 0; i < a->n; ++i) {
        double e = a->e[i];
        if (e > mx) mx = e;
        if (a->sgn[i] < 0 && e > under) under = e;
        if (a->sgn[i] > 0 && e > over) over = e;
        if (e > 0.05) {
            if (a->sgn[i] < 0) out->n_under_5pct++;
            else out->n_over_5pct++;
        }
        if (a->d[i] < near) {
            sum_near += e;
            out->n_near++;
        }
    }
    out->max = mx;
    out->max_under = under;
    out->max_over = over;
    out->near_me = out->n_near ? sum_near / (double)out->n_near : NAN;
    return GS_OK;
}
