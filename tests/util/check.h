/* check.h - a minimal test harness: CHECK macros that count and report
 * failures, skip support (exit 77, which ctest reports as skipped), and
 * helpers to find ../shared data. Each test program runs in its own process. */
#ifndef GS_CHECK_H
#define GS_CHECK_H

#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>

extern int gs__test_failures;
extern int gs__test_checks;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        gs__test_checks++;                                                             \
        if (!(cond)) {                                                                \
            gs__test_failures++;                                                       \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);  \
        }                                                                             \
    } while (0)

#define CHECK_MSG(cond, ...)                                                          \
    do {                                                                              \
        gs__test_checks++;                                                             \
        if (!(cond)) {                                                                \
            gs__test_failures++;                                                       \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);  \
            fprintf(stderr, __VA_ARGS__);                                             \
            fputc('\n', stderr);                                                      \
        }                                                                             \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                         \
    CHECK_MSG(fabs((double)(a) - (double)(b)) <= (tol), "%.17g vs %.17g (tol %g)",     \
              (double)(a), (double)(b), (double)(tol))

/* Print a summary line and return the process exit code: 1 if a check
 * failed, else 77 (ctest: skipped, never passed) if a shared file the test
 * looked for (gs_test_shared_*) was missing, else 0. */
int gs__test_finish(const char *name);

/* Print the reason and exit 77 (ctest: skipped). */
void gs__test_skip(const char *reason);

/* Path of a file under the shared data folder (GEOSEP_SHARED env var, else
 * the CMake default). Returns NULL if the file does not exist, and then
 * gs__test_finish reports the test as skipped. Static buffer. */
const char *gs__test_shared_path(const char *relative);

/* Paths of a shared mesh and its ground truth (meshes/NAME.obj and
 * groundtruth/NAME.gt) into obj and gt (n bytes each); 0 if either is
 * missing. */
int gs__test_shared_pair(const char *name, char *obj, char *gt, size_t n);

/* The names M of the shared groundtruth/M.gt files (M shorter than
 * GS_TEST_NAME_MAX), in name order, into names (at most max of them).
 * Returns how many; -1 if there is no groundtruth/ folder (one that cannot
 * be listed fails a CHECK). */
#define GS_TEST_NAME_MAX 128
int gs__test_shared_names(char (*names)[GS_TEST_NAME_MAX], int max);

/* Section 5's errors of a database's fields from the k vertices src
 * against want (k fields of n values, in the same order), averaged over
 * the sources (max: the largest); CHECKs that every field is answered and
 * valid. */
typedef struct gs__test_errs {
    double me, rmse, max;
} gs__test_errs;
struct gs_db;
gs__test_errs gs__test_db_errors(const struct gs_db *db, const uint32_t *src, uint32_t k, const double *want,
                               uint32_t n);

/* Euclidean distance of two points (x, y, z). */
double gs__test_dist3(const double *a, const double *b);

/* Is x in face f of the mesh: its distance from the triangle (the nearest
 * point of the face, edges included) at most tol times the face's smallest
 * height (and at least 1e-14 of its longest edge: rounding)? Measured by
 * distance, not by least-squares barycentric weights, which cancel on a
 * needle 1e-11 wide. */
struct gs_mesh;
int gs__test_in_face(const struct gs_mesh *m, uint32_t f, const double *x, double tol);

#endif
