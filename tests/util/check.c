/* check.c - the test harness behind check.h. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int gs_test_failures = 0;
int gs_test_checks = 0;

int gs_test_finish(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, gs_test_checks, gs_test_failures);
    return gs_test_failures ? 1 : 0;
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
    return access(buf, R_OK) == 0 ? buf : NULL;
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
