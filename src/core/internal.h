/* internal.h - shared internal helpers: error reporting, checked allocation.
 * Not part of the public API. */
#ifndef GS_INTERNAL_H
#define GS_INTERNAL_H

#include "geosep.h"

#include <stddef.h>
#include <stdint.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#if defined(__GNUC__)
#define GS_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define GS_PRINTF(a, b)
#endif

/* Record a failure in err (may be NULL) and return status. */
int gs__fail(gs_error *err, int status, const char *fmt, ...) GS_PRINTF(3, 4);

/* Allocation with overflow-checked sizes; return NULL on failure or when
 * count*size overflows. gs__calloc zeroes. Free with free(). */
void *gs__malloc(size_t count, size_t size);
void *gs__calloc(size_t count, size_t size);
void *gs__realloc(void *p, size_t count, size_t size);

/* A growable array: make *p hold at least need elements of size bytes,
 * doubling *cap (from 256); GS_OK, or GS_ENOMEM with *p and *cap unchanged. */
int gs__grow(void **p, size_t *cap, size_t need, size_t size);

/* Wall-clock seconds (monotonic). */
double gs__now(void);

#endif
