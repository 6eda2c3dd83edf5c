/* test_eval.c - the error measures: gs_field_errors_compute and the tail
 * accumulator gs_error_acc on hand-made fields with known answers (means,
 * nearest-rank quantiles, near pairs against the median, under/over). */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <string.h>

static int close_to(double a, double b) { return fabs(a - b) <= 1e-6 * fmax(1, fabs(b)); }

static void known_answers(void)
{
    gs_error err = {0};
    gs_error_acc *acc = NULL;
    CHECK(gs_error_acc_create(&acc, &err) == GS_OK && acc);
    /* field 1, source 0: exact 0,1,2,4,8; approx errors 0, +10%, -50%, +0%, -1%  */
    double d1[5] = {0, 1, 2, 4, 8}, a1[5] = {0, 1.1, 1, 4, 7.92};
    CHECK(gs_error_acc_add(acc, d1, a1, 5, 0, &err) == GS_OK);
    /* field 2, source 4: exact 10,20,30,40,0 (one invalid candidate, one inf d) */
    double d2[5] = {10, INFINITY, 30, 40, 0}, a2[5] = {10.4, 3, -1, 40, 0};
    CHECK(gs_error_acc_add(acc, d2, a2, 5, 4, &err) == GS_OK);
    gs_error_stats st;
    CHECK(gs_error_acc_result(acc, 0.5, &st, &err) == GS_OK);
    /* used pairs: e = .1 (d 1), .5 (d 2), 0 (d 4), .01 (d 8), .04 (d 10), 0 (d 40) */
    CHECK(st.n_used == 6 && st.n_fields == 2 && st.n_skipped == 1 && st.n_invalid == 1);
    double me1 = (0.1 + 0.5 + 0 + 0.01) / 4, me2 = (0.04 + 0) / 2;
    CHECK_MSG(close_to(st.me, (me1 + me2) / 2), "me %g", st.me);
    double r1 = sqrt((0.01 + 0.25 + 0.0001) / 4), r2 = sqrt(0.0016 / 2);
    CHECK_MSG(close_to(st.rmse, (r1 + r2) / 2), "rmse %g", st.rmse);
    CHECK(close_to(st.max, 0.5) && close_to(st.max_under, 0.5) && close_to(st.max_over, 0.1));
    /* sorted e: 0 0 .01 .04 .1 .5: rank ceil(.99*6) = 6 -> .5 */
    CHECK(close_to(st.p99, 0.5) && close_to(st.p999, 0.5));
    /* sorted d: 1 2 4 8 10 40: median rank 3 -> 4; near: d < 2 -> only d = 1 */
    CHECK_MSG(close_to(st.median_d, 4) && st.n_near == 1 && close_to(st.near_me, 0.1), "median %g near %llu %g",
              st.median_d, (unsigned long long)st.n_near, st.near_me);
    CHECK(st.n_under_5pct == 1 && st.n_over_5pct == 1);
    /* a second reading gives the same */
    gs_error_stats st2;
    CHECK(gs_error_acc_result(acc, 0.5, &st2, &err) == GS_OK && !memcmp(&st, &st2, sizeof st));
    CHECK(gs_error_acc_result(acc, -1, &st2, &err) == GS_EARG);
    CHECK(gs_error_acc_add(acc, d1, NULL, 5, 0, &err) == GS_EARG);
    CHECK(gs_error_acc_add(acc, d1, a1, 5, 5, &err) == GS_EARG);
    gs_error_acc_free(acc);
}

static void quantiles(void)
{
    gs_error err = {0};
    gs_error_acc *acc = NULL;
    CHECK(gs_error_acc_create(&acc, &err) == GS_OK);
    /* 2001 vertices, source 0; e of vertex y = y / 10000 in shuffled order */
    enum { N = 2001 };
    static double d[N], a[N];
    for (uint32_t y = 0; y < N; ++y) {
        uint32_t k = (y * 7919u) % N; /* a permutation (7919 prime, N = 3 * 23 * 29) */
        d[y] = 1 + y;
        a[y] = d[y] * (1 + k / 10000.0);
    }
    CHECK(gs_error_acc_add(acc, d, a, N, 0, &err) == GS_OK);
    gs_error_stats st;
    CHECK(gs_error_acc_result(acc, 0.1, &st, &err) == GS_OK);
    /* e values: {k / 10000 : k = perm(y), y = 1..2000}, i.e. 2000 of the 2001
     * values 0..2000 (the missing one: perm(0) = 0). Rank ceil(.99 * 2000) =
     * 1980 -> 1980/10000; rank 1998 -> .1998; max .2 */
    CHECK_MSG(close_to(st.p99, 0.198), "p99 %g", st.p99);
    CHECK_MSG(close_to(st.p999, 0.1998), "p99.9 %g", st.p999);
    CHECK(close_to(st.max, 0.2) && st.max_under == 0 && st.n_under_5pct == 0);
    gs_error_acc_free(acc);
    /* nothing added: NaN */
    CHECK(gs_error_acc_create(&acc, &err) == GS_OK);
    CHECK(gs_error_acc_result(acc, 0.1, &st, &err) == GS_OK && isnan(st.me) && isnan(st.max) && st.n_used == 0);
    gs_error_acc_free(acc);
}

int main(void)
{
    known_answers();
    quantiles();
    return gs_test_finish("test_eval");
}
