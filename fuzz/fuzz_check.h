/* fuzz_check.h - what the fuzz targets share: a check that aborts (so that
 * libFuzzer saves the input) with the failed condition. */
#ifndef GS_FUZZ_CHECK_H
#define GS_FUZZ_CHECK_H

#include <stdio.h>
#include <stdlib.h>

#define FUZZ_CHECK(cond)                                                              \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: FUZZ_CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                  \
        }                                                                             \
    } while (0)

#endif
