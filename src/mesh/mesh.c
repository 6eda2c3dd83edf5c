/* mesh.c - gs_mesh: creation from arrays, accessors and the health report
 * (components, boundary loops, genus, angles). */
#include "mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void gs_mesh_free(gs_mesh *m)
{
    if (!m) return;
    gs__topo_free(&m->topo);
    free(m->xyz);
    free(m->tri);
    free(m);
}

uint32_t gs_mesh_num_vertices(const gs_mesh *m) { return m ? m->nv : 0; }
uint32_t gs_mesh_num_faces(const gs_mesh *m) { return m ? m->nf : 0; }
const double *gs_mesh_positions(const gs_mesh *m) { return m ? m->xyz : NULL; }
const uint32_t *gs_mesh_faces(const gs_mesh *m) { return m ? m->tri : NULL; }

static uint32_t uf_find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* Components, boundary loops and genus, from the connectivity. */
static int compute_report(gs_mesh *m, gs_error *err)
{
    const gs__topo *t = &m->topo;
    gs_mesh_report *r = &m->report;
    memset(r, 0, sizeof *r);
    r->n_vertices = m->nv;
    r->n_faces = m->nf;
    r->n_edges = t->n_edges;
    size_t nh = 3 * (size_t)m->nf;

    uint32_t *parent = gs__malloc(m->nf ? m->nf : 1, sizeof *parent);
    uint8_t *seen = gs__calloc(nh ? nh : 1, 1);
    if (!parent || !seen) {
        free(parent);
        free(seen);
        return gs__fail(err, GS_ENOMEM, "out of memory computing the mesh report");
    }
    for (uint32_t f = 0; f < m->nf; ++f) parent[f] = f;
    for (size_t h = 0; h < nh; ++h)
        if (t->opp[h] != GS_NONE) {
            uint32_t a = uf_find(parent, (uint32_t)(h / 3)), b = uf_find(parent, t->opp[h] / 3);
            if (a != b) parent[a < b ? b : a] = a < b ? a : b;
        }
    for (uint32_t f = 0; f < m->nf; ++f)
        if (uf_find(parent, f) == f) r->n_components++;

    /* boundary loops: follow boundary half-edges head to tail */
    for (size_t h = 0; h < nh; ++h) {
        if (t->opp[h] != GS_NONE) continue;
        r->n_boundary_edges++;
        if (seen[h]) continue;
        r->n_boundary_loops++;
        uint32_t x = (uint32_t)h;
        while (!seen[x]) {
            seen[x] = 1;
            uint32_t v = m->tri[gs__next(x)], nx = GS_NONE;
            for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
                uint32_t c = t->vc[k];
                if (t->opp[c] == GS_NONE && !seen[c]) {
                    nx = c;
                    break;
                }
            }
            if (nx == GS_NONE) break;
            x = nx;
        }
    }
    uint32_t used = 0;
    for (uint32_t v = 0; v < m->nv; ++v) {
        if (t->vflag[v] & GS_V_UNUSED)
            r->n_unreferenced++;
        else
            used++;
    }
    r->euler = (int32_t)((int64_t)used - (int64_t)t->n_edges + (int64_t)m->nf);
    /* sum over components of (2 - b_c - chi_c) / 2 = (2C - B - chi) / 2 */
    r->genus = (int32_t)((2 * (int64_t)r->n_components - r->n_boundary_loops - r->euler) / 2);

    r->min_angle_deg = m->nf ? 180.0 : 0;
    r->max_angle_deg = 0;
    r->min_edge = m->nf ? INFINITY : 0;
    r->max_edge = 0;
    double sum = 0;
    for (size_t h = 0; h < nh; ++h) {
        double a = t->angle[h] * 180.0 / M_PI;
        if (a < r->min_angle_deg) r->min_angle_deg = a;
        if (a > r->max_angle_deg) r->max_angle_deg = a;
        double l = t->len[h];
        if (l < r->min_edge) r->min_edge = l;
        if (l > r->max_edge) r->max_edge = l;
        sum += l;
    }
    r->mean_edge = nh ? sum / (double)nh : 0;
    for (int k = 0; k < 3; ++k) {
        r->bbox_min[k] = m->nv ? INFINITY : 0;
        r->bbox_max[k] = m->nv ? -INFINITY : 0;
    }
    for (uint32_t v = 0; v < m->nv; ++v)
        for (int k = 0; k < 3; ++k) {
            double c = m->xyz[3 * (size_t)v + k];
            if (c < r->bbox_min[k]) r->bbox_min[k] = c;
            if (c > r->bbox_max[k]) r->bbox_max[k] = c;
        }
    free(parent);
    free(seen);
    return GS_OK;
}

int gs__mesh_adopt(double *xyz, uint32_t nv, uint32_t *tri, uint32_t nf,
                  const gs__origin *origin, gs_mesh **out, gs_error *err)
{
    *out = NULL;
    gs_mesh *m = gs__calloc(1, sizeof *m);
    if (!m) {
        free(xyz);
        free(tri);
        return gs__fail(err, GS_ENOMEM, "out of memory");
    }
    m->xyz = xyz;
    m->tri = tri;
    m->nv = nv;
    m->nf = nf;
    int rc = gs__topo_build(&m->topo, nv, xyz, nf, tri, 0, origin, err);
    if (rc == GS_OK) rc = compute_report(m, err);
    if (rc) {
        gs_mesh_free(m);
        return rc;
    }
    *out = m;
    return GS_OK;
}

int gs_mesh_create(const double *xyz, uint32_t nv, const uint32_t *tri, uint32_t nf,
                   gs_mesh **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_mesh_create: out is NULL");
    *out = NULL;
    if ((nv && !xyz) || (nf && !tri))
        return gs__fail(err, GS_EARG, "gs_mesh_create: NULL array with a non-zero count");
    /* as gs_mesh_load: without a face there is no surface to measure on (a
     * database of such a mesh answered +inf for every pair, or failed with
     * 0 vertices) */
    if (nf == 0)
        return gs__fail(err, GS_EMESH, "gs_mesh_create: no faces (%u vertices given); a mesh needs "
                        "at least one triangle", nv);
    double *x = gs__malloc(3 * (size_t)nv, sizeof *x);
    uint32_t *f = gs__malloc(3 * (size_t)nf, sizeof *f);
    if (!x || !f) {
        free(x);
        free(f);
        return gs__fail(err, GS_ENOMEM, "out of memory copying the mesh");
    }
    if (nv) memcpy(x, xyz, 3 * (size_t)nv * sizeof *x);
    if (nf) memcpy(f, tri, 3 * (size_t)nf * sizeof *f);
    return gs__mesh_adopt(x, nv, f, nf, NULL, out, err);
}

int gs_mesh_get_report(const gs_mesh *m, gs_mesh_report *report, gs_error *err)
{
    if (!m || !report) return gs__fail(err, GS_EARG, "gs_mesh_get_report: NULL argument");
    *report = m->report;
    return GS_OK;
}
