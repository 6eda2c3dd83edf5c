/* input.c - queries by input vertex id on a database of a repaired mesh
 * (format: "Input-id aliases"; doc/repair.md): each input vertex answers
 * by the least distance over the repaired vertices it became. Without the
 * section, input ids are vertex ids. The aliases are read in place: an
 * input vertex with other aliases than itself is found by binary search
 * among the few that have them. */
#include "../db/db_internal.h"

#include <math.h>
#include <stdlib.h>

uint32_t gs_db_num_input_vertices(const gs_db *db)
{
    return db ? db->n_input : 0;
}

/* Input vertex v's (< n_input) alias list: *n entries at the returned
 * pointer, or *one = v itself when v has no other. */
static const uint32_t *aliases(const gs_db *db, uint32_t v, uint32_t *one, uint32_t *n)
{
    *one = v, *n = 1;
    if (!db->alias_index) return one;
    uint32_t lo = 0, hi = db->alias_exceptions; /* first entry with .v >= v */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (db->alias_index[mid].v < v) lo = mid + 1;
        else hi = mid;
    }
    if (lo == db->alias_exceptions || db->alias_index[lo].v != v) return one;
    uint32_t s = db->alias_index[lo].start; /* validated: starts increase, end at alias_entries */
    *n = db->alias_index[lo + 1].start - s;
    return db->alias_list + s;
}

uint32_t gs_db_input_aliases(const gs_db *db, uint32_t v, uint32_t *out, uint32_t cap)
{
    if (!db || v >= db->n_input) return 0;
    uint32_t one, n;
    const uint32_t *a = aliases(db, v, &one, &n);
    for (uint32_t i = 0; i < n && i < cap && out; ++i) out[i] = a[i];
    return n;
}

double gs_db_input_distance(const gs_db *db, uint32_t x, uint32_t y)
{
    if (!db || x >= db->n_input || y >= db->n_input) return NAN;
    if (x == y) return 0.0;
    uint32_t ox, oy, nx, ny;
    const uint32_t *ax = aliases(db, x, &ox, &nx), *ay = aliases(db, y, &oy, &ny);
    double best = INFINITY;
    for (uint32_t i = 0; i < nx; ++i)
        for (uint32_t j = 0; j < ny; ++j) {
            double d = gs_db_distance(db, ax[i], ay[j]);
            if (d != d) return d; /* a corrupt record: say so */
            if (d < best) best = d;
        }
    return best;
}

int gs_db_input_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out, gs_error *err)
{
    if (!db || (n && (!pairs || !out))) return gs__fail(err, GS_EARG, "gs_db_input_distances: NULL argument");
    size_t bad = SIZE_MAX;
    for (size_t i = 0; i < n; ++i) {
        out[i] = gs_db_input_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        if (bad == SIZE_MAX && (pairs[2 * i] >= db->n_input || pairs[2 * i + 1] >= db->n_input)) bad = i;
    }
    if (bad != SIZE_MAX)
        return gs__fail(err, GS_EARG, "gs_db_input_distances: pair %zu (%u, %u) has an input vertex id >= %u", bad,
                        pairs[2 * bad], pairs[2 * bad + 1], db->n_input);
    return GS_OK;
}

int gs_db_input_field(const gs_db *db, uint32_t x, double *out, gs_error *err)
{
    if (!db || !out) return gs__fail(err, GS_EARG, "gs_db_input_field: NULL argument");
    if (x >= db->n_input)
        return gs__fail(err, GS_EARG, "gs_db_input_field: input vertex %u >= n_input_vertices %u", x, db->n_input);
    if (!db->alias_index) return gs_db_field(db, x, out, err); /* input ids are vertex ids */
    uint32_t ox, nx;
    const uint32_t *ax = aliases(db, x, &ox, &nx);
    double *acc = gs__malloc(db->nv, sizeof *acc), *tmp = nx > 1 ? gs__malloc(db->nv, sizeof *tmp) : NULL;
    int rc = acc && (nx == 1 || tmp) ? GS_OK
                                     : gs__fail(err, GS_ENOMEM, "gs_db_input_field: out of memory (%u vertices)", db->nv);
    if (!rc) rc = gs_db_field(db, ax[0], acc, err);
    for (uint32_t i = 1; i < nx && !rc; ++i) { /* the least over x's aliases */
        rc = gs_db_field(db, ax[i], tmp, err);
        for (uint32_t b = 0; b < db->nv && !rc; ++b)
            if (tmp[b] < acc[b] || tmp[b] != tmp[b]) acc[b] = tmp[b];
    }
    for (uint32_t v = 0; v < db->n_input && !rc; ++v) { /* then over each v's */
        uint32_t ov, nvl;
        const uint32_t *av = aliases(db, v, &ov, &nvl);
        double best = INFINITY;
        for (uint32_t j = 0; j < nvl; ++j) {
            double d = acc[av[j]];
            if (d < best || d != d) best = d;
            if (d != d) break;
        }
        out[v] = v == x ? 0.0 : best;
    }
    free(acc);
    free(tmp);
    return rc;
}
