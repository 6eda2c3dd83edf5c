/* cheb.c - Chebyshev series kernels (paper sec. 4.2/4.3): Clenshaw, value and
 * derivatives, and the Chebyshev-Lobatto tables that make the coarse scan of
 * the pair minimiser a sequence of dot products. */
#include "cheb.h"

#include <math.h>
#include <pthread.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

double gs__cheb_eval(const double *c, uint32_t m, double t)
{
    if (m == 0)
        return c[0];
    double b1 = 0.0, b2 = 0.0, t2 = 2.0 * t;
    for (uint32_t k = m; k >= 1; k--) {
        double b0 = c[k] + t2 * b1 - b2;
        b2 = b1;
        b1 = b0;
    }
    return c[0] + t * b1 - b2;
}

void gs__cheb_eval3(const double *c, uint32_t m, double t, double *p, double *p1, double *p2)
{
    double v = c[0], d1 = 0.0, d2 = 0.0;
    if (m >= 1) {
        double t0 = 1.0, t1 = t, e0 = 0.0, e1 = 1.0, f0 = 0.0, f1 = 0.0, t2 = 2.0 * t;
        v += c[1] * t;
        d1 = c[1];
        for (uint32_t k = 2; k <= m; k++) {
            double tn = t2 * t1 - t0;
            double en = 2.0 * t1 + t2 * e1 - e0;
            double fn = 4.0 * e1 + t2 * f1 - f0;
            v += c[k] * tn;
            d1 += c[k] * en;
            d2 += c[k] * fn;
            t0 = t1, t1 = tn, e0 = e1, e1 = en, f0 = f1, f1 = fn;
        }
    }
    *p = v;
    *p1 = d1;
    *p2 = d2;
}

uint32_t gs__cheb_grid_size(uint32_t m)
{
    uint32_t g = 3 * m + 6;
    if (g < 10)
        g = 10;
    return g > GS_CHEB_GRID_MAX ? GS_CHEB_GRID_MAX : g;
}

/* One table per degree m (rows m+1); storage sized for the worst case. */
#define TAB_DOUBLES ((GS_FUN_MAX_DEGREE + 1) * (GS_CHEB_GRID_MAX + 1) * (GS_FUN_MAX_DEGREE + 2))

#define PAD_PTS(g) (((g) + GS_CHEB_PAD) / GS_CHEB_PAD * GS_CHEB_PAD)
#define PAD_DOUBLES ((GS_FUN_MAX_DEGREE + 1) * PAD_PTS(GS_CHEB_GRID_MAX) * (GS_FUN_MAX_DEGREE + 2))

static double g_tab[TAB_DOUBLES];
static double g_tp[PAD_DOUBLES] __attribute__((aligned(64)));
static double g_dp[PAD_DOUBLES] __attribute__((aligned(64)));
static double g_x[(GS_FUN_MAX_DEGREE + 1) * (GS_CHEB_GRID_MAX + 1)];
static gs__cheb_grid g_grids[GS_FUN_MAX_DEGREE + 1];
static double g_fine[GS_CHEB_FINE + 1];
static pthread_once_t g_once = PTHREAD_ONCE_INIT;
/* Each degree's table is built on its first use (a query process touches
 * only the few it needs: all of them take about 450 KB). */
static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static unsigned char g_built[GS_FUN_MAX_DEGREE + 1];

static void build_table(uint32_t mm)
{
    size_t tpos = 0, ppos = 0;
    for (uint32_t m = 0; m < mm; m++) { /* where degree mm's tables start */
        tpos += (size_t)(m + 1) * (gs__cheb_grid_size(m) + 1);
        ppos += (size_t)(m + 1) * PAD_PTS(gs__cheb_grid_size(m));
    }
    uint32_t m = mm, g = gs__cheb_grid_size(m);
    double *x = g_x + (size_t)m * (GS_CHEB_GRID_MAX + 1), *tk = g_tab + tpos;
    for (uint32_t j = 0; j <= g; j++)
        x[j] = -cos(M_PI * j / g);
    x[0] = -1.0, x[g] = 1.0;
    if (g % 2 == 0)
        x[g / 2] = 0.0;
    for (uint32_t k = 0; k <= m; k++)
        for (uint32_t j = 0; j <= g; j++)
            tk[(size_t)k * (g + 1) + j] = cos(k * (M_PI - M_PI * j / g));
    uint32_t np = PAD_PTS(g);
    double *tp = g_tp + ppos, *dp = g_dp + ppos;
    for (uint32_t k = 0; k <= m; k++)
        for (uint32_t j = 0; j < np; j++) {
            /* T_k(cos th) = cos(k th), T_k' = k sin(k th) / sin th; ends: +-k^2 */
            uint32_t jj = j > g ? g : j;
            double th = M_PI - M_PI * jj / g, d;
            if (jj == 0)
                d = (k % 2 ? 1.0 : -1.0) * k * k;
            else if (jj == g)
                d = (double)k * k;
            else
                d = k * sin(k * th) / sin(th);
            tp[(size_t)k * np + j] = tk[(size_t)k * (g + 1) + jj];
            dp[(size_t)k * np + j] = d;
        }
    g_grids[m] = (gs__cheb_grid){g, m + 1, x, tk, np, tp, dp};
}

static void build_fine(void)
{
    for (uint32_t j = 0; j <= GS_CHEB_FINE; j++)
        g_fine[j] = -cos(M_PI * j / GS_CHEB_FINE);
    g_fine[0] = -1.0, g_fine[GS_CHEB_FINE] = 1.0, g_fine[GS_CHEB_FINE / 2] = 0.0;
}

const double *gs__cheb_fine_grid(void)
{
    pthread_once(&g_once, build_fine);
    return g_fine;
}

const gs__cheb_grid *gs__cheb_grid_for(uint32_t m)
{
    m = m > GS_FUN_MAX_DEGREE ? GS_FUN_MAX_DEGREE : m;
    if (!__atomic_load_n(&g_built[m], __ATOMIC_ACQUIRE)) {
        pthread_mutex_lock(&g_lock);
        if (!g_built[m]) {
            build_table(m);
            __atomic_store_n(&g_built[m], 1, __ATOMIC_RELEASE);
        }
        pthread_mutex_unlock(&g_lock);
    }
    return &g_grids[m];
}
