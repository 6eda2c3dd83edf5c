/* radius.c - a sparse radius matrix for many sources (gs_db_radius_matrix):
 * row i holds every vertex within r of sources[i] (gs_db_within's answer),
 * by increasing vertex id, in compressed sparse rows. Rows are computed in
 * parallel (OpenMP, dynamic schedule: rows differ in cost), each into its
 * own arrays, then concatenated in order: the result does not depend on the
 * number of threads. */
#include "query_internal.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void gs_csr_free(gs_csr *m)
{
    if (!m) return;
    free(m->indptr);
    free(m->indices);
    free(m->data);
    free(m);
}

typedef struct row {
    uint32_t *ids;
    double *dist;
    size_t n;
} row;

int gs_db_radius_matrix(const gs_db *db, const uint32_t *sources, uint32_t n_sources, double r, uint32_t threads,
                        gs_csr **out, gs_error *err)
{
    if (out) *out = NULL;
    if (!db || !out || (n_sources && !sources)) return gs__fail(err, GS_EARG, "gs_db_radius_matrix: NULL argument");
    if (!(r >= 0.0)) return gs__fail(err, GS_EARG, "gs_db_radius_matrix: radius %g is not a number >= 0", r);
    if (threads > GS_MAX_THREADS)
        return gs__fail(err, GS_EARG, "gs_db_radius_matrix: threads %u out of range [0, %u]", threads, GS_MAX_THREADS);
    for (uint32_t i = 0; i < n_sources; ++i)
        if (sources[i] >= db->nv)
            return gs__fail(err, GS_EARG, "gs_db_radius_matrix: source %u is vertex %u >= n_vertices %u", i,
                            sources[i], db->nv);
    row *rows = gs__calloc(n_sources ? n_sources : 1, sizeof *rows);
    gs_csr *m = gs__calloc(1, sizeof *m);
    if (!rows || !m) {
        free(rows), free(m);
        return gs__fail(err, GS_ENOMEM, "gs_db_radius_matrix: out of memory (%u sources)", n_sources);
    }
    int nt = threads ? (int)threads : omp_get_max_threads(), rc = GS_OK;
    if (nt > (int)n_sources) nt = n_sources ? (int)n_sources : 1; /* no thread without a row */
    gs_error first = {0};
    long failed = -1; /* the first row that failed (its message kept) */
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
    for (long i = 0; i < (long)n_sources; ++i) {
        gs_error e = {0};
        int c = gs__db_within_row(db, sources[i], r, &rows[i].ids, &rows[i].dist, &rows[i].n, &e);
        if (c) {
#pragma omp critical(gs_radius_fail)
            if (failed < 0 || i < failed) failed = i, rc = c, first = e;
        }
    }
    if (!rc) {
        uint64_t nnz = 0;
        for (uint32_t i = 0; i < n_sources; ++i) nnz += rows[i].n;
        m->n_rows = n_sources, m->n_cols = db->nv, m->nnz = nnz;
        m->indptr = gs__malloc((size_t)n_sources + 1, sizeof *m->indptr);
        m->indices = gs__malloc(nnz ? nnz : 1, sizeof *m->indices);
        m->data = gs__malloc(nnz ? nnz : 1, sizeof *m->data);
        if (!m->indptr || !m->indices || !m->data) {
            rc = gs__fail(err, GS_ENOMEM, "gs_db_radius_matrix: out of memory (%llu entries)", (unsigned long long)nnz);
        } else {
            uint64_t at = 0;
            for (uint32_t i = 0; i < n_sources; ++i) {
                m->indptr[i] = at;
                if (rows[i].n) {
                    memcpy(m->indices + at, rows[i].ids, rows[i].n * sizeof *m->indices);
                    memcpy(m->data + at, rows[i].dist, rows[i].n * sizeof *m->data);
                }
                at += rows[i].n;
            }
            m->indptr[n_sources] = at;
        }
    } else if (err) {
        *err = first;
    }
    for (uint32_t i = 0; i < n_sources; ++i) free(rows[i].ids), free(rows[i].dist);
    free(rows);
    if (rc) {
        gs_csr_free(m);
        return rc;
    }
    *out = m;
    return GS_OK;
}
