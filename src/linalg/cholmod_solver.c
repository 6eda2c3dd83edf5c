/* cholmod_solver.c - the sparse SPD factorisation of sparse.h on top of
 * SuiteSparse CHOLMOD (the 64-bit-index "cholmod_l" interface): triplets ->
 * compressed column -> analyse (fill-reducing ordering) -> factorise, and
 * cholmod_l_solve2 with reused dense buffers for repeated solves; a factor
 * can reuse the symbolic analysis of another one. The only
 * file of geosep that includes cholmod.h. */
#include "sparse.h"

#include <cholmod.h>
#include <stdlib.h>
#include <string.h>

struct gs__sparse_factor {
    uint32_t n;
    int started;         /* cholmod_l_start was called on c              */
    cholmod_common c;    /* one common per factor or view: its workspace */
    cholmod_factor *L;   /* a view's is its owner's (solves only read it) */
    int view;            /* 1: L belongs to another factor               */
    cholmod_dense *B;    /* right-hand side, allocated once              */
    cholmod_dense *Bk;   /* k right-hand sides (solve_many), grown once  */
    cholmod_dense *X, *Y, *E; /* solve2 workspace, reused across solves */
};

void gs__sparse_factor_free(gs__sparse_factor *f)
{
    if (!f) return;
    if (f->started) {
        if (!f->view) cholmod_l_free_factor(&f->L, &f->c);
        cholmod_l_free_dense(&f->B, &f->c);
        cholmod_l_free_dense(&f->Bk, &f->c);
        cholmod_l_free_dense(&f->X, &f->c);
        cholmod_l_free_dense(&f->Y, &f->c);
        cholmod_l_free_dense(&f->E, &f->c);
        cholmod_l_finish(&f->c);
    }
    free(f);
}

uint32_t gs__sparse_factor_size(const gs__sparse_factor *f) { return f ? f->n : 0; }

static gs__sparse_factor *fail(gs__sparse_factor *f, gs_error *err, int status, const char *what)
{
    gs__fail(err, status, "sparse factorisation: %s", what);
    gs__sparse_factor_free(f);
    return NULL;
}

gs__sparse_factor *gs__sparse_factor_create(uint32_t n, size_t nnz, const uint32_t *ti,
                                          const uint32_t *tj, const double *tx,
                                          const gs__sparse_factor *like, gs_error *err)
{
    gs__sparse_factor *f = calloc(1, sizeof *f);
    if (!f) return fail(NULL, err, GS_ENOMEM, "out of memory");
    f->n = n;
    if (like && like->n != n) return fail(f, err, GS_EARG, "pattern of another size");
    if (n == 0) return f;
    for (size_t k = 0; k < nnz; ++k)
        if (ti[k] >= n || tj[k] > ti[k])
            return fail(f, err, GS_EARG, "triplet outside the lower triangle");
    if (!cholmod_l_start(&f->c)) return fail(f, err, GS_ENOMEM, "cholmod_l_start failed");
    f->started = 1;
    f->c.print = 0; /* report through gs_error, never on stdout/stderr */

    /* stype -1: the lower triangle is stored and the upper one implied */
    cholmod_triplet *T = cholmod_l_allocate_triplet(n, n, nnz, -1, CHOLMOD_REAL, &f->c);
    if (!T) return fail(f, err, GS_ENOMEM, "out of memory (triplets)");
    SuiteSparse_long *Ti = T->i, *Tj = T->j;
    double *Tx = T->x;
    for (size_t k = 0; k < nnz; ++k) {
        Ti[k] = (SuiteSparse_long)ti[k];
        Tj[k] = (SuiteSparse_long)tj[k];
        Tx[k] = tx[k];
    }
    T->nnz = nnz;
    cholmod_sparse *A = cholmod_l_triplet_to_sparse(T, nnz, &f->c); /* sums duplicates */
    cholmod_l_free_triplet(&T, &f->c);
    if (!A) return fail(f, err, GS_ENOMEM, "out of memory (sparse matrix)");

    /* a copy of like's factor carries its ordering and symbolic structure;
     * cholmod_l_factorize overwrites the numeric part */
    if (like)
        f->L = cholmod_l_copy_factor(like->L, &f->c);
    else {
        /* The analysis tries METIS when AMD's fill is large (homer-960k's
         * whole mesh: METIS chosen; homer-240k's: AMD). METIS keeps its
         * random generator in global state (GKlib), seeded at the start of
         * each call, so two threads analysing at once race on it and get
         * orderings that differ from run to run, and with them factors
         * that differ in the last bits: 960k builds whose threads each
         * factored their patch moved 26-63 functions per build. Analyses
         * take turns with the partitioner's METIS calls (src/partition/
         * split.c, the same critical section). */
#pragma omp critical(gs__metis)
        f->L = cholmod_l_analyze(A, &f->c);
    }
    if (!f->L) {
        cholmod_l_free_sparse(&A, &f->c);
        return fail(f, err, GS_ENOMEM, "analysis failed");
    }
    int ok = cholmod_l_factorize(A, f->L, &f->c);
    cholmod_l_free_sparse(&A, &f->c);
    if (!ok || f->c.status == CHOLMOD_OUT_OF_MEMORY)
        return fail(f, err, GS_ENOMEM, "out of memory (factor)");
    if (f->c.status == CHOLMOD_NOT_POSDEF || f->L->minor < f->L->n)
        return fail(f, err, GS_EINTERNAL, "matrix is not positive definite");
    if (f->c.status < 0) return fail(f, err, GS_EINTERNAL, "CHOLMOD factorisation failed");

    f->B = cholmod_l_zeros(n, 1, CHOLMOD_REAL, &f->c);
    if (!f->B) return fail(f, err, GS_ENOMEM, "out of memory (dense buffer)");
    return f;
}

gs__sparse_factor *gs__sparse_factor_share(const gs__sparse_factor *f, gs_error *err)
{
    gs__sparse_factor *v = calloc(1, sizeof *v);
    if (!v) return fail(NULL, err, GS_ENOMEM, "out of memory");
    v->n = f->n;
    v->view = 1;
    if (v->n == 0) return v;
    if (!cholmod_l_start(&v->c)) return fail(v, err, GS_ENOMEM, "cholmod_l_start failed");
    v->started = 1;
    v->c.print = 0;
    v->L = f->L;
    v->B = cholmod_l_zeros(v->n, 1, CHOLMOD_REAL, &v->c);
    if (!v->B) return fail(v, err, GS_ENOMEM, "out of memory (dense buffer)");
    return v;
}

int gs__sparse_factor_solve(gs__sparse_factor *f, const double *b, double *x, gs_error *err)
{
    if (f->n == 0) return GS_OK;
    memcpy(f->B->x, b, sizeof(double) * f->n);
    if (!cholmod_l_solve2(CHOLMOD_A, f->L, f->B, NULL, &f->X, NULL, &f->Y, &f->E, &f->c) ||
        !f->X)
        return gs__fail(err, f->c.status == CHOLMOD_OUT_OF_MEMORY ? GS_ENOMEM : GS_EINTERNAL,
                        "sparse solve failed (CHOLMOD status %d)", f->c.status);
    memcpy(x, f->X->x, sizeof(double) * f->n);
    return GS_OK;
}

int gs__sparse_factor_solve_many(gs__sparse_factor *f, const double *b, double *x, uint32_t k, gs_error *err)
{
    if (f->n == 0 || k == 0) return GS_OK;
    if (k == 1) return gs__sparse_factor_solve(f, b, x, err);
    if (!f->Bk || f->Bk->ncol != k) {
        cholmod_l_free_dense(&f->Bk, &f->c);
        f->Bk = cholmod_l_allocate_dense(f->n, k, f->n, CHOLMOD_REAL, &f->c);
        if (!f->Bk) return gs__fail(err, GS_ENOMEM, "sparse solve: out of memory for %u right-hand sides", k);
    }
    memcpy(f->Bk->x, b, sizeof(double) * f->n * (size_t)k);
    if (!cholmod_l_solve2(CHOLMOD_A, f->L, f->Bk, NULL, &f->X, NULL, &f->Y, &f->E, &f->c) || !f->X)
        return gs__fail(err, f->c.status == CHOLMOD_OUT_OF_MEMORY ? GS_ENOMEM : GS_EINTERNAL,
                        "sparse solve failed (CHOLMOD status %d)", f->c.status);
    memcpy(x, f->X->x, sizeof(double) * f->n * (size_t)k);
    return GS_OK;
}
