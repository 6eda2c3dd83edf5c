/* idmap.h - a map of uint32 ids to uint32 values (UINT32_MAX: absent), for
 * the sparse subsets of a mesh's ids that patches and database paths
 * visit: an array over every id when the subset is a large share of them,
 * else an open-addressing table (linear probing, at most half full, grown
 * by doubling), so that its cost follows the subset, not the mesh.
 * Header-only, internal. A zeroed gs__idmap is an empty table. Not
 * thread-safe; one owner. */
#ifndef GS_IDMAP_H
#define GS_IDMAP_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct gs__idmap {
    uint32_t *key, *val; /* dense: key NULL, val[id] for every id < cap */
    uint32_t cap, n;     /* table: cap a power of two, n keys            */
    int dense;
} gs__idmap;

#define GS__IDMAP_NONE UINT32_MAX

static inline uint32_t gs__idmap_hash(uint32_t k, uint32_t cap)
{
    return (uint32_t)((k * 2654435761u) & (cap - 1));
}

/* A map for ids < n_ids expected to hold about `keys` of them: dense when
 * they are at least an eighth of the ids, else a table of twice the keys.
 * Returns 0, or -1 when out of memory (the map is then freeable). */
static inline int gs__idmap_init(gs__idmap *m, uint32_t n_ids, size_t keys)
{
    memset(m, 0, sizeof *m);
    if (8 * keys >= n_ids) {
        m->dense = 1, m->cap = n_ids;
        m->val = malloc((n_ids ? n_ids : 1) * sizeof *m->val);
        if (!m->val) return -1;
        memset(m->val, 0xff, (size_t)n_ids * sizeof *m->val);
        return 0;
    }
    size_t cap = 16;
    while (cap < 2 * keys) cap *= 2;
    m->key = malloc(cap * sizeof *m->key), m->val = malloc(cap * sizeof *m->val);
    if (!m->key || !m->val) return -1;
    memset(m->key, 0xff, cap * sizeof *m->key);
    m->cap = (uint32_t)cap;
    return 0;
}

static inline void gs__idmap_free(gs__idmap *m)
{
    free(m->key), free(m->val);
    memset(m, 0, sizeof *m);
}

/* k's value, GS__IDMAP_NONE when absent (k < n_ids for a dense map). */
static inline uint32_t gs__idmap_get(const gs__idmap *m, uint32_t k)
{
    if (m->dense) return m->val[k];
    if (!m->cap) return GS__IDMAP_NONE;
    for (uint32_t i = gs__idmap_hash(k, m->cap);; i = (i + 1) & (m->cap - 1)) {
        if (m->key[i] == GS__IDMAP_NONE) return GS__IDMAP_NONE;
        if (m->key[i] == k) return m->val[i];
    }
}

/* Sets k's value (k != GS__IDMAP_NONE); a table grows to stay at most half
 * full (first size 1024). Returns 0, or -1 when out of memory (the map is
 * unchanged). */
static inline int gs__idmap_put(gs__idmap *m, uint32_t k, uint32_t v)
{
    if (m->dense) return m->val[k] = v, 0;
    if (2 * ((size_t)m->n + 1) > m->cap) {
        uint32_t nc = m->cap ? 2 * m->cap : 1024;
        uint32_t *nk = malloc((size_t)nc * sizeof *nk), *nv = malloc((size_t)nc * sizeof *nv);
        if (!nk || !nv) {
            free(nk), free(nv);
            return -1;
        }
        memset(nk, 0xff, (size_t)nc * sizeof *nk);
        for (uint32_t i = 0; i < m->cap; ++i)
            if (m->key[i] != GS__IDMAP_NONE) {
                uint32_t j = gs__idmap_hash(m->key[i], nc);
                while (nk[j] != GS__IDMAP_NONE) j = (j + 1) & (nc - 1);
                nk[j] = m->key[i], nv[j] = m->val[i];
            }
        free(m->key), free(m->val);
        m->key = nk, m->val = nv, m->cap = nc;
    }
    uint32_t i = gs__idmap_hash(k, m->cap);
    while (m->key[i] != GS__IDMAP_NONE && m->key[i] != k) i = (i + 1) & (m->cap - 1);
    if (m->key[i] == GS__IDMAP_NONE) m->n++;
    m->key[i] = k, m->val[i] = v;
    return 0;
}

#endif
