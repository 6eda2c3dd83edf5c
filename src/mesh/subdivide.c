/* subdivide.c - 1-to-4 midpoint subdivision (for scaling benchmarks: the
 * same surface at 4x and 16x the vertices). Midpoints are numbered by the
 * first half-edge of each edge in face order; twins share them. */
#include "mesh_internal.h"

#include <stdlib.h>
#include <string.h>

int gs_mesh_subdivide(const gs_mesh *m, gs_mesh **out, gs_error *err)
{
    if (!m || !out) return gs__fail(err, GS_EARG, "gs_mesh_subdivide: NULL argument");
    *out = NULL;
    const gs_topo *t = &m->topo;
    uint64_t nv = (uint64_t)m->nv + t->n_edges, nf = 4 * (uint64_t)m->nf;
    if (nv >= (1u << 31) || nf >= (1u << 31))
        return gs__fail(err, GS_ELIMIT, "gs_mesh_subdivide: %llu vertices, %llu faces is too many",
                        (unsigned long long)nv, (unsigned long long)nf);
    size_t nh = 3 * (size_t)m->nf;
    uint32_t *mid = gs__malloc(nh ? nh : 1, sizeof *mid);
    double *xyz = gs__malloc(3 * (size_t)nv, sizeof *xyz);
    uint32_t *tri = gs__malloc(3 * (size_t)nf, sizeof *tri);
    if (!mid || !xyz || !tri) {
        free(mid);
        free(xyz);
        free(tri);
        return gs__fail(err, GS_ENOMEM, "gs_mesh_subdivide: out of memory");
    }
    memcpy(xyz, m->xyz, 3 * (size_t)m->nv * sizeof *xyz);
    uint32_t next = m->nv;
    for (size_t h = 0; h < nh; ++h) mid[h] = GS_NONE;
    for (size_t h = 0; h < nh; ++h) {
        if (mid[h] != GS_NONE) continue;
        const double *a = m->xyz + 3 * (size_t)m->tri[h], *b = m->xyz + 3 * (size_t)m->tri[gs_next((uint32_t)h)];
        for (int k = 0; k < 3; ++k) xyz[3 * (size_t)next + k] = 0.5 * (a[k] + b[k]);
        mid[h] = next;
        if (t->opp[h] != GS_NONE) mid[t->opp[h]] = next;
        next++;
    }
    for (uint32_t f = 0; f < m->nf; ++f) {
        const uint32_t *c = m->tri + 3 * (size_t)f;
        uint32_t m0 = mid[3 * (size_t)f], m1 = mid[3 * (size_t)f + 1], m2 = mid[3 * (size_t)f + 2];
        uint32_t quad[4][3] = {{c[0], m0, m2}, {m0, c[1], m1}, {m2, m1, c[2]}, {m0, m1, m2}};
        memcpy(tri + 12 * (size_t)f, quad, sizeof quad);
    }
    free(mid);
    return gs_mesh_adopt(xyz, next, tri, (uint32_t)nf, NULL, out, err);
}
