/* patch.c - gs_patch: a subset of a mesh's faces with its own vertex
 * numbering and connectivity (the surface patches P(N) of the paper, sec. 2.2). */
#include "../core/idmap.h"
#include "mesh_internal.h"

#include <stdlib.h>
#include <string.h>

void gs_patch_free(gs_patch *p)
{
    if (!p) return;
    if (!p->identity) gs__topo_free(&p->topo_own);
    free(p->xyz);
    free(p->tri);
    free(p->vmap);
    free(p->fmap);
    free(p);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : (x > y);
}

int gs_patch_create(const gs_mesh *mesh, const uint32_t *faces, uint32_t n_faces,
                    gs_patch **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_patch_create: out is NULL");
    *out = NULL;
    if (!mesh) return gs__fail(err, GS_EARG, "gs_patch_create: mesh is NULL");
    gs_patch *p = gs__calloc(1, sizeof *p);
    if (!p) return gs__fail(err, GS_ENOMEM, "out of memory");
    p->mesh = mesh;
    if (!faces) {
        p->identity = 1;
        p->nv = mesh->nv;
        p->nf = mesh->nf;
        p->topo = &mesh->topo;
        *out = p;
        return GS_OK;
    }
    /* Everything below costs O(k) for k faces (and sorting the vertices),
     * independent of the mesh size: the nested bisection creates many
     * small patches, and a database path one per corridor. The mesh's
     * connectivity is reused: its twins where both faces are in the patch,
     * its lengths and angles. */
    int rc = GS_OK;
    size_t nc = 3 * (size_t)n_faces;
    gs__idmap fm = {0}, vm = {0};
    uint32_t *verts = gs__malloc(nc ? nc : 1, sizeof *verts), *opp = NULL;
    p->fmap = gs__malloc(n_faces ? n_faces : 1, sizeof *p->fmap);
    p->tri = gs__malloc(nc ? nc : 1, sizeof *p->tri);
    if (!verts || !p->fmap || !p->tri || gs__idmap_init(&fm, mesh->nf, n_faces) ||
        gs__idmap_init(&vm, mesh->nv, nc < mesh->nv ? nc : mesh->nv)) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory creating a patch");
        goto done;
    }
    uint32_t nv = 0;
    for (uint32_t i = 0; i < n_faces; ++i) {
        if (faces[i] >= mesh->nf) {
            rc = gs__fail(err, GS_EARG, "gs_patch_create: face %u (entry %u) out of range (%u faces)",
                          faces[i], i, mesh->nf);
            goto done;
        }
        if (gs__idmap_get(&fm, faces[i]) != GS_NONE) {
            rc = gs__fail(err, GS_EARG, "gs_patch_create: face %u listed twice", faces[i]);
            goto done;
        }
        p->fmap[i] = faces[i];
        int oom = gs__idmap_put(&fm, faces[i], i); /* sized for every key: no growth */
        for (int k = 0; k < 3 && !oom; ++k) {
            uint32_t v = mesh->tri[3 * (size_t)faces[i] + k];
            if (gs__idmap_get(&vm, v) == GS_NONE) oom = gs__idmap_put(&vm, v, 0), verts[nv++] = v;
        }
        if (oom) {
            rc = gs__fail(err, GS_ENOMEM, "out of memory creating a patch");
            goto done;
        }
    }
    qsort(verts, nv, sizeof *verts, cmp_u32); /* vmap increasing: gs_patch_vertex_from_mesh */
    for (uint32_t v = 0; v < nv; ++v) gs__idmap_put(&vm, verts[v], v); /* present: no growth */
    p->nv = nv;
    p->nf = n_faces;
    p->vmap = gs__malloc(nv ? nv : 1, sizeof *p->vmap);
    p->xyz = gs__malloc(3 * (size_t)(nv ? nv : 1), sizeof *p->xyz);
    opp = gs__malloc(nc ? nc : 1, sizeof *opp);
    if (!p->vmap || !p->xyz || !opp) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory creating a patch");
        goto done;
    }
    memcpy(p->vmap, verts, (size_t)nv * sizeof *p->vmap);
    for (uint32_t v = 0; v < nv; ++v)
        memcpy(p->xyz + 3 * (size_t)v, mesh->xyz + 3 * (size_t)p->vmap[v], 3 * sizeof(double));
    const gs__topo *mt = &mesh->topo;
    for (size_t i = 0; i < nc; ++i) {
        size_t H = 3 * (size_t)faces[i / 3] + i % 3;
        p->tri[i] = gs__idmap_get(&vm, mesh->tri[H]);
        uint32_t tw = mt->opp[H], g = tw == GS_NONE ? GS_NONE : gs__idmap_get(&fm, tw / 3);
        opp[i] = g == GS_NONE ? GS_NONE : 3 * g + tw % 3;
    }
    rc = gs__topo_build_sub(&p->topo_own, mt, p->fmap, opp, nv, p->xyz, n_faces, p->tri, err);
    opp = NULL;
    p->topo = &p->topo_own;
done:
    free(verts);
    free(opp);
    gs__idmap_free(&fm);
    gs__idmap_free(&vm);
    if (rc) {
        gs_patch_free(p);
        return rc;
    }
    *out = p;
    return GS_OK;
}

uint32_t gs_patch_num_vertices(const gs_patch *p) { return p ? p->nv : 0; }
uint32_t gs_patch_num_faces(const gs_patch *p) { return p ? p->nf : 0; }

uint32_t gs_patch_vertex_to_mesh(const gs_patch *p, uint32_t local)
{
    if (!p || local >= p->nv) return GS_NONE;
    return p->identity ? local : p->vmap[local];
}

uint32_t gs_patch_face_to_mesh(const gs_patch *p, uint32_t local)
{
    if (!p || local >= p->nf) return GS_NONE;
    return p->identity ? local : p->fmap[local];
}

uint32_t gs_patch_vertex_from_mesh(const gs_patch *p, uint32_t v)
{
    if (!p) return GS_NONE;
    if (p->identity) return v < p->nv ? v : GS_NONE;
    uint32_t lo = 0, hi = p->nv; /* vmap is increasing: binary search */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (p->vmap[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return (lo < p->nv && p->vmap[lo] == v) ? lo : GS_NONE;
}
