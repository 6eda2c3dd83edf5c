/* eval.c - accuracy of a candidate distance field against an exact one, as
 * the paper's section 5 measures it: ME (L1) and RMSE (L2) of the relative
 * error e(y) = |d - d^| / d per vertex, and the largest e. */
#include "../core/internal.h"

#include <math.h>
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
