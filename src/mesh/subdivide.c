/* subdivide.c - 1-to-4 midpoint subdivision (for scaling benchmarks: the
 * same surface at 4x and 16x the vertices; and the heat method's refined
 * solve). Midpoints are numbered by the first half-edge of each edge in
 * face order; twins share them. */
#include "mesh_internal.h"

#include <stdlib.h>
#include <string.h>

int gs__subdivide_arrays(const gs__topo *t, uint32_t *nv_out, double **xyz_out, uint32_t *nf_out,
                         uint32_t **tri_out, gs_error *err)
{
    *xyz_out = NULL, *tri_out = NULL, *nv_out = *nf_out = 0;
    uint64_t nv = (uint64_t)t->nv + t->n_edges, nf = 4 * (uint64_t)t->nf;
    if (nv >= (1u << 31) || nf >= (1u << 31))
        return gs__fail(err, GS_ELIMIT, "subdivision: %llu vertices, %llu faces is too many",
                        (unsigned long long)nv, (unsigned long long)nf);
    size_t nh = 3 * (size_t)t->nf;
    uint32_t *mid = gs__malloc(nh ? nh : 1, sizeof *mid);
    double *xyz = gs__malloc(3 * (size_t)nv, sizeof *xyz);
    uint32_t *tri = gs__malloc(3 * (size_t)nf + 1, sizeof *tri);
    if (!mid || !xyz || !tri) {
        free(mid);
        free(xyz);
        free(tri);
        return gs__fail(err, GS_ENOMEM, "subdivision: out of memory");
    }
    memcpy(xyz, t->xyz, 3 * (size_t)t->nv * sizeof *xyz);
    uint32_t next = t->nv;
    for (size_t h = 0; h < nh; ++h) mid[h] = GS_NONE;
    for (size_t h = 0; h < nh; ++h) {
        if (mid[h] != GS_NONE) continue;
        const double *a = t->xyz + 3 * (size_t)t->tri[h], *b = t->xyz + 3 * (size_t)t->tri[gs__next((uint32_t)h)];
        for (int k = 0; k < 3; ++k) xyz[3 * (size_t)next + k] = 0.5 * (a[k] + b[k]);
        mid[h] = next;
        if (t->opp[h] != GS_NONE) mid[t->opp[h]] = next;
        next++;
    }
    for (uint32_t f = 0; f < t->nf; ++f) {
        const uint32_t *c = t->tri + 3 * (size_t)f;
        uint32_t m0 = mid[3 * (size_t)f], m1 = mid[3 * (size_t)f + 1], m2 = mid[3 * (size_t)f + 2];
        uint32_t quad[4][3] = {{c[0], m0, m2}, {m0, c[1], m1}, {m2, m1, c[2]}, {m0, m1, m2}};
        memcpy(tri + 12 * (size_t)f, quad, sizeof quad);
    }
    free(mid);
    *xyz_out = xyz, *tri_out = tri, *nv_out = next, *nf_out = (uint32_t)nf;
    return GS_OK;
}

int gs_mesh_subdivide(const gs_mesh *m, gs_mesh **out, gs_error *err)
{
    if (!m || !out) return gs__fail(err, GS_EARG, "gs_mesh_subdivide: NULL argument");
    *out = NULL;
    double *xyz;
    uint32_t *tri, nv, nf;
    int rc = gs__subdivide_arrays(&m->topo, &nv, &xyz, &nf, &tri, err);
    if (rc) return rc;
    return gs__mesh_adopt(xyz, nv, tri, nf, NULL, out, err);
}
