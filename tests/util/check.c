/* check.c - the test harness behind check.h. */
#include "check.h"

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
