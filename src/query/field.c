/* field.c - distances from one vertex to every vertex (gs_db_field): one
 * query source (query_internal.h) answers every target, so x's functions
 * are decoded and tabulated once per curve instead of once per target; the
 * answers are gs_db_distance's, bit for bit. */
#include "query_internal.h"

#include <math.h>
#include <stdlib.h>

int gs_db_field(const gs_db *db, uint32_t x, double *out, gs_error *err)
{
    if (!db || !out) return gs__fail(err, GS_EARG, "gs_db_field: NULL argument");
    if (x >= db->nv) return gs__fail(err, GS_EARG, "gs_db_field: vertex %u >= n_vertices %u", x, db->nv);
    if (db->leaf[x] == GS_NONE) {
        for (uint32_t y = 0; y < db->nv; ++y) out[y] = y == x ? 0.0 : INFINITY;
        return GS_OK;
    }
    gs__qsrc *s = gs__qsrc_create(db, x);
    uint32_t *top = gs__malloc(db->n_nodes, sizeof *top); /* each leaf's common ancestor with x's */
    if (!s || !top) {
        gs__qsrc_free(s), free(top);
        return gs__fail(err, GS_ENOMEM, "gs_db_field: out of memory for vertex %u's functions", x);
    }
    for (uint32_t n = 0; n < db->n_nodes; ++n) top[n] = GS_NONE;
    const uint32_t lx = db->leaf[x];
    for (uint32_t y = 0; y < db->nv; ++y) {
        uint32_t ly = db->leaf[y];
        if (y == x) out[y] = 0.0;
        else if (ly == GS_NONE) out[y] = INFINITY;
        else if (ly == lx) out[y] = gs__qsrc_distance(s, y);
        else {
            if (top[ly] == GS_NONE) top[ly] = gs__qsrc_ancestor(s, ly);
            out[y] = gs__qsrc_cross(s, y, ly, top[ly]);
        }
    }
    gs__qsrc_free(s);
    free(top);
    return GS_OK;
}
