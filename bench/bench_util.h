/* bench_util.h - what every benchmark needs: a monotonic clock, the median
 * of a sample, the clock's own cost. Header only (each bench/NAME.c is its
 * own program); nothing here is part of the library. */
#ifndef GEOSEP_BENCH_UTIL_H
#define GEOSEP_BENCH_UTIL_H

#include <stdlib.h>
#include <time.h>

/* Seconds on the monotonic clock. */
static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort's comparison of doubles (ascending). */
static inline int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of v[0..n) (n >= 1); sorts v. */
static inline double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return 0.5 * (v[(n - 1) / 2] + v[n / 2]);
}

/* Median cost of reading the clock twice, subtracted from single timings. */
static inline double timer_overhead(void)
{
    double t[1000];
    for (int i = 0; i < 1000; ++i) {
        double a = now();
        t[i] = now() - a;
    }
    qsort(t, 1000, sizeof *t, cmp_double);
    return t[500];
}

#endif
