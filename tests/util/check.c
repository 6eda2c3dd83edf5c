/* check.c - the test harness behind check.h. */
#include "check.h"
#include "geosep.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int gs_test_failures = 0;
int gs_test_checks = 0;

/* The first shared file a test looked for and did not find, and how many. */
static char g_missing[4096];
static int g_n_missing;

int gs_test_finish(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, gs_test_checks, gs_test_failures);
    if (gs_test_failures) return 1;
    if (g_n_missing) {
        /* not a pass: the parts that need the data did not run */
        printf("SKIP: %s: shared data not found (%s%s; set GEOSEP_SHARED or the GEOSEP_SHARED_DIR CMake "
               "cache variable): the checks that need it did not run, the %d others passed\n",
               name, g_missing, g_n_missing > 1 ? " and others" : "", gs_test_checks);
        fflush(stdout);
        return 77;
    }
    return 0;
}

void gs_test_skip(const char *reason)
{
    printf("SKIP: %s\n", reason);
    fflush(stdout);
    exit(77);
}

#ifndef GEOSEP_SHARED_DIR
#define GEOSEP_SHARED_DIR "../shared"
#endif

const char *gs_test_shared_path(const char *relative)
{
    static char buf[4096];
    const char *base = getenv("GEOSEP_SHARED");
    if (!base || !*base) base = GEOSEP_SHARED_DIR;
    snprintf(buf, sizeof buf, "%s/%s", base, relative);
    if (access(buf, R_OK) == 0) return buf;
    if (!g_n_missing++) snprintf(g_missing, sizeof g_missing, "%s", buf);
    return NULL;
}

int gs_test_shared_pair(const char *name, char *obj, char *gt, size_t n)
{
    char rel[256];
    snprintf(rel, sizeof rel, "meshes/%.200s.obj", name);
    const char *p = gs_test_shared_path(rel);
    if (!p) return 0;
    snprintf(obj, n, "%s", p);
    snprintf(rel, sizeof rel, "groundtruth/%.200s.gt", name);
    p = gs_test_shared_path(rel);
    if (!p) return 0;
    snprintf(gt, n, "%s", p);
    return 1;
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp(a, b);
}

int gs_test_shared_names(char (*names)[GS_TEST_NAME_MAX], int max)
{
    const char *g = gs_test_shared_path("groundtruth");
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

gs_test_errs gs_test_db_errors(const gs_db *db, const uint32_t *src, uint32_t k, const double *want, uint32_t n)
{
    gs_test_errs e = {0, 0, 0};
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
