/* sparse.h - a sparse symmetric positive definite factorisation (Cholesky,
 * backed by SuiteSparse CHOLMOD in cholmod_solver.c, the only file that
 * includes cholmod.h). Used by the heat method (src/geodesic/heat_setup.c, heat.c).
 * A factor owns its workspace: one thread at a time per factor. */
#ifndef GS_SPARSE_H
#define GS_SPARSE_H

#include "../core/internal.h"

#include <stddef.h>
#include <stdint.h>

typedef struct gs__sparse_factor gs__sparse_factor;

/* Factor the n x n symmetric matrix given by nnz triplets (ti[k], tj[k],
 * tx[k]) of its lower triangle (ti[k] >= tj[k] < n); duplicates are summed,
 * explicit zeros are kept in the pattern. n may be 0 (solves then do
 * nothing). like: NULL, or a factor of a matrix with the same n and the
 * same set of triplet positions, whose fill-reducing ordering and symbolic
 * analysis are reused (the expensive part for large meshes). Returns NULL
 * on failure with err set: GS_ENOMEM, GS_EARG (bad triplet or like of
 * another size), GS_EINTERNAL (not positive definite). */
gs__sparse_factor *gs__sparse_factor_create(uint32_t n, size_t nnz, const uint32_t *ti,
                                          const uint32_t *tj, const double *tx,
                                          const gs__sparse_factor *like, gs_error *err);

/* A view of f: its factor, shared and read-only, with a workspace of its
 * own, so that several threads can solve with one factorisation at once
 * (one thread per view, or per factor). f must outlive its views; freeing a
 * view leaves f's factor alone. NULL on failure with err set (GS_ENOMEM). */
gs__sparse_factor *gs__sparse_factor_share(const gs__sparse_factor *f, gs_error *err);

/* Solve A x = b (b and x: n doubles; they may alias). Allocation-free after
 * the first call. */
int gs__sparse_factor_solve(gs__sparse_factor *f, const double *b, double *x, gs_error *err);

/* Solve A X = B for k right-hand sides at once (b and x: n x k doubles,
 * column-major, column j at j*n; they may alias). Much faster per column
 * than k single solves (blocked triangular solves). The workspace is kept
 * for the next call with the same k. */
int gs__sparse_factor_solve_many(gs__sparse_factor *f, const double *b, double *x, uint32_t k, gs_error *err);

uint32_t gs__sparse_factor_size(const gs__sparse_factor *f);

/* Free a factor; NULL is allowed. */
void gs__sparse_factor_free(gs__sparse_factor *f);

#endif
