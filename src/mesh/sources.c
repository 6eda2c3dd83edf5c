/* sources.c - deterministic random choice of source vertices (splitmix64),
 * identical to the procedure that made the shared ground-truth files, so a
 * list of sources can be recomputed from (mesh, k, seed). */
#include "mesh_internal.h"

#include <stdlib.h>

static uint64_t splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

int gs_mesh_random_vertices(const gs_mesh *m, uint32_t k, uint64_t seed, uint32_t *out, gs_error *err)
{
    if (!m || (k && !out)) return gs__fail(err, GS_EARG, "gs_mesh_random_vertices: NULL argument");
    uint32_t *cand = gs__malloc(m->nv, sizeof *cand);
    uint8_t *taken = gs__calloc(m->nv, 1);
    if (!cand || !taken) {
        free(cand);
        free(taken);
        return gs__fail(err, GS_ENOMEM, "out of memory");
    }
    uint32_t n = 0;
    for (uint32_t v = 0; v < m->nv; ++v)
        if (!(m->topo.vflag[v] & GS_V_UNUSED)) cand[n++] = v;
    int rc = GS_OK;
    if (k > n)
        rc = gs__fail(err, GS_EARG, "cannot choose %u distinct vertices: only %u are used by faces", k, n);
    uint64_t state = seed;
    for (uint32_t i = 0; rc == GS_OK && i < k;) {
        uint32_t v = cand[splitmix64(&state) % n];
        if (taken[v]) continue;
        taken[v] = 1;
        out[i++] = v;
    }
    free(cand);
    free(taken);
    return rc;
}
