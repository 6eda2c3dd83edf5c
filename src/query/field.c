/* field.c - distances from one vertex to every vertex (gs_db_field): one
 * query source (query_internal.h) answers every target, so x's functions
 * are decoded and tabulated once per curve instead of once per target; the
 * answers are gs_db_distance's, bit for bit. gs_db_field_threads splits
 * the targets into chunks (in vertex order: the records are read in file
 * order) answered on OpenMP threads, each with its own source: the same
 * answers for any number of threads. */
#include "query_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

/* out[y] for y in [y0, y1) from source s (x's leaf not GS_NONE); top: each
 * leaf's common ancestor with x's leaf, GS_NONE until known */
static void field_range(gs__qsrc *s, const gs_db *db, uint32_t x, uint32_t *top, uint32_t y0, uint32_t y1,
                        double *out)
{
    const uint32_t lx = db->leaf[x];
    for (uint32_t y = y0; y < y1; ++y) {
        uint32_t ly = db->leaf[y];
        if (y == x) out[y] = 0.0;
        else if (ly == GS_NONE) out[y] = INFINITY;
        else if (ly == lx) out[y] = gs__qsrc_distance(s, y);
        else {
            if (top[ly] == GS_NONE) top[ly] = gs__qsrc_ancestor(s, ly);
            out[y] = gs__qsrc_cross(s, y, ly, top[ly]);
        }
    }
}

/* the arguments of both (0: go on; else the status, *err set) */
static int field_args(const gs_db *db, uint32_t x, double *out, const char *fn, gs_error *err)
{
    if (!db || !out) return gs__fail(err, GS_EARG, "%s: NULL argument", fn);
    if (x >= db->nv) return gs__fail(err, GS_EARG, "%s: vertex %u >= n_vertices %u", fn, x, db->nv);
    return GS_OK;
}

/* x used by no face: +inf everywhere but at x */
static int field_unused(const gs_db *db, uint32_t x, double *out)
{
    if (db->leaf[x] != GS_NONE) return 0;
    for (uint32_t y = 0; y < db->nv; ++y) out[y] = y == x ? 0.0 : INFINITY;
    return 1;
}

int gs_db_field(const gs_db *db, uint32_t x, double *out, gs_error *err)
{
    int rc = field_args(db, x, out, "gs_db_field", err);
    if (rc || field_unused(db, x, out)) return rc;
    gs__qsrc *s = gs__qsrc_create(db, x);
    uint32_t *top = gs__malloc(db->n_nodes, sizeof *top);
    if (!s || !top) {
        gs__qsrc_free(s), free(top);
        return gs__fail(err, GS_ENOMEM, "gs_db_field: out of memory for vertex %u's functions", x);
    }
    for (uint32_t n = 0; n < db->n_nodes; ++n) top[n] = GS_NONE;
    field_range(s, db, x, top, 0, db->nv, out);
    gs__qsrc_free(s);
    free(top);
    return GS_OK;
}

/* targets per chunk: eight chunks a thread for balance, at most CHUNK_MAX
 * (a thread's source and its record reads stay warm), at least CHUNK_MIN */
#define CHUNK_MAX 4096u
#define CHUNK_MIN 64u

int gs_db_field_threads(const gs_db *db, uint32_t x, double *out, uint32_t threads, gs_error *err)
{
    int rc = field_args(db, x, out, "gs_db_field_threads", err);
    if (!rc && threads > GS_MAX_THREADS)
        rc = gs__fail(err, GS_EARG, "gs_db_field_threads: threads %u out of range [0, %u]", threads, GS_MAX_THREADS);
    if (rc || field_unused(db, x, out)) return rc;
    int nt = threads ? (int)threads : omp_get_max_threads();
    if (nt <= 1 || db->nv < 2 * CHUNK_MIN) return gs_db_field(db, x, out, err);
    uint32_t chunk = db->nv / (8u * (uint32_t)nt);
    chunk = chunk < CHUNK_MIN ? CHUNK_MIN : (chunk > CHUNK_MAX ? CHUNK_MAX : chunk);
    uint32_t chunks = (db->nv + chunk - 1) / chunk;
    if (nt > (int)chunks) nt = (int)chunks;
    int failed = 0;
#pragma omp parallel num_threads(nt) reduction(| : failed)
    {
        gs__qsrc *s = gs__qsrc_create(db, x);
        uint32_t *top = gs__malloc(db->n_nodes, sizeof *top);
        if (!s || !top) failed = 1;
        else
            for (uint32_t n = 0; n < db->n_nodes; ++n) top[n] = GS_NONE;
#pragma omp for schedule(dynamic, 1)
        for (long c = 0; c < (long)chunks; ++c) {
            if (failed) continue; /* this thread has no source: the call fails */
            uint32_t y0 = (uint32_t)c * chunk, y1 = db->nv - y0 < chunk ? db->nv : y0 + chunk;
            field_range(s, db, x, top, y0, y1, out);
        }
        gs__qsrc_free(s);
        free(top);
    }
    if (failed) return gs__fail(err, GS_ENOMEM, "gs_db_field_threads: out of memory for vertex %u's functions", x);
    return GS_OK;
}
