/* core.c - version, status strings, error messages, checked allocation. */
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

const char *gs_version_string(void)
{
    return GEOSEP_VERSION_STRING;
}

const char *gs_status_string(int status)
{
    switch (status) {
    case GS_OK: return "ok";
    case GS_EIO: return "i/o error";
    case GS_EPARSE: return "malformed file";
    case GS_EMESH: return "invalid mesh";
    case GS_ENOMEM: return "out of memory";
    case GS_EARG: return "invalid argument";
    case GS_EFORMAT: return "unsupported format";
    case GS_ELIMIT: return "size limit exceeded";
    case GS_EINTERNAL: return "internal error";
    default: return "unknown status";
    }
}

int gs__fail(gs_error *err, int status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->status = status;
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return status;
}

void *gs__malloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) return NULL;
    size_t n = count * size;
    return malloc(n ? n : 1);
}

void *gs__calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) return NULL;
    return calloc(count ? count : 1, size ? size : 1);
}

void *gs__realloc(void *p, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size) return NULL;
    size_t n = count * size;
    return realloc(p, n ? n : 1);
}

int gs__grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap) return GS_OK;
    size_t c = *cap ? *cap : 256;
    while (c < need) c *= 2;
    void *q = gs__realloc(*p, c, size);
    if (!q) return GS_ENOMEM;
    *p = q, *cap = c;
    return GS_OK;
}

double gs__now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
