/* check.c - the test harness behind check.h. */
#include "check.h"
#include "geosep.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int gs__test_failures = 0;
int gs__test_checks = 0;

/* The first shared file a test looked for and did not find, and how many. */
static char g_missing[4096];
static int g_n_missing;

int gs__test_finish(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, gs__test_checks, gs__test_failures);
    if (gs__test_failures) return 1;
    if (g_n_missing) {
        /* not a pass: the parts that need the data did not run */
        printf("SKIP: %s: shared data not found (%s%s; set GEOSEP_SHARED or the GEOSEP_SHARED_DIR CMake "
               "cache variable): the checks that need it did not run, the %d others passed\n",
               name, g_missing, g_n_missing > 1 ? " and others" : "", gs__test_checks);
        fflush(stdout);
        return 77;
    }
    return 0;
}

void gs__test_skip(const char *reason)
{
    printf("SKIP: %s\n", reason);
    fflush(stdout);
    exit(77);
}

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

const char *gs__test_shared_path(const char *relative)
{
    static char buf[4096];
    const char *base = getenv("GEOSEP_SHARED");
    if (!base || !*base) base = GEOSEP_SHARED_DIR;
    snprintf(buf, sizeof buf, "%s/%s", base, relative);
    if (access(buf, R_OK) == 0) return buf;
    if (!g_n_missing++) snprintf(g_missing, sizeof g_missing, "%s", buf);
    return NULL;
}

int gs__test_shared_pair(const char *name, char *obj, char *gt, size_t n)
{
    char rel[256];
    snprintf(rel, sizeof rel, "meshes/%.200s.obj", name);
    const char *p = gs__test_shared_path(rel);
    if (!p) return 0;
    snprintf(obj, n, "%s", p);
    snprintf(rel, sizeof rel, "groundtruth/%.200s.gt", name);
    p = gs__test_shared_path(rel);
    if (!p) return 0;
    snprintf(gt, n, "%s", p);
    return 1;
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp(a, b);
}

int gs__test_shared_names(char (*names)[GS_TEST_NAME_MAX], int max)
{
    const char *g = gs__test_shared_path("groundtruth");
    if (!g) return -1;
    DIR *dh = opendir(g);
    CHECK_MSG(dh != NULL, "cannot list %s", g);
    int n = 0;
    for (struct dirent *e; dh && n < max && (e = readdir(dh)) != NULL;) {
        size_t l = strlen(e->d_name);
        if (l > 3 && l < GS_TEST_NAME_MAX + 3 && strcmp(e->d_name + l - 3, ".gt") == 0) {
            memcpy(names[n], e->d_name, l - 3);
            names[n++][l - 3] = 0;
        }
    }
    if (dh) closedir(dh);
    qsort(names, (size_t)n, sizeof names[0], cmp_name);
    return n;
}

gs__test_errs gs__test_db_errors(const gs_db *db, const uint32_t *src, uint32_t k, const double *want, uint32_t n)
{
    gs__test_errs e = {0, 0, 0};
    double *d = malloc((n ? n : 1) * sizeof *d);
    gs_error err;
    CHECK(d != NULL);
    for (uint32_t j = 0; d && j < k; ++j) {
        CHECK(gs_db_field(db, src[j], d, &err) == GS_OK);
        gs_field_errors fe;
        CHECK(gs_field_errors_compute(want + (size_t)j * n, d, n, src[j], &fe, &err) == GS_OK);
        CHECK_MSG(fe.n_invalid == 0, "%llu invalid values", (unsigned long long)fe.n_invalid);
        e.me += fe.me / k;
        e.rmse += fe.rmse / k;
        e.max = fmax(e.max, fe.max);
    }
    free(d);
    return e;
}

double gs__test_dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}

/* distance from x to the segment a b */
static double segment_distance(const double *a, const double *b, const double *x)
{
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, r[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
    double ee = dot3(e, e), t = ee > 0 ? dot3(r, e) / ee : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double q[3] = {a[0] + t * e[0], a[1] + t * e[1], a[2] + t * e[2]};
    return gs__test_dist3(q, x);
}

int gs__test_in_face(const gs_mesh *m, uint32_t f, const double *x, double tol)
{
    const double *P = gs_mesh_positions(m);
    const uint32_t *T = gs_mesh_faces(m) + 3 * (size_t)f;
    const double *a = P + 3 * T[0], *b = P + 3 * T[1], *c = P + 3 * T[2];
    double e1[3], e2[3], r[3], n[3], t[3];
    for (int k = 0; k < 3; ++k) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], r[k] = x[k] - a[k];
    double scale = fmax(sqrt(dot3(e1, e1)), fmax(sqrt(dot3(e2, e2)), gs__test_dist3(b, c)));
    cross3(e1, e2, n);
    double nn = dot3(n, n), d;
    /* weights from cross products (no Gram determinant: it cancels on needles) */
    cross3(r, e2, t);
    double u = nn > 0 ? dot3(t, n) / nn : -1;
    cross3(e1, r, t);
    double v = nn > 0 ? dot3(t, n) / nn : -1;
    if (u >= 0 && v >= 0 && u + v <= 1) d = fabs(dot3(r, n)) / sqrt(nn); /* over the inside: off the plane */
    else d = fmin(segment_distance(a, b, x), fmin(segment_distance(b, c, x), segment_distance(c, a, x)));
    /* tol of the face's smallest height, but at least 1e-14 of its size
     * (rounding): a needle's neighbour across is off by its width */
    return d <= fmax(tol * sqrt(nn) / scale, 1e-14 * scale);
}
