/* separators.c - the separator curves of a database, as segments to draw.
 * The database stores per vertex its leaf and the tree's shape, not the
 * curves' geometry: a node's separator lies between the vertices of its
 * two subtrees, so it crosses every edge whose endpoints' lowest common
 * ancestor is that node. Drawn through the edges' midpoints: a face with
 * two corners in one leaf gets one segment between the midpoints of its
 * two cut edges; a face with its corners in three leaves gets a segment
 * from each edge's midpoint to the centroid (a parent's curve passes
 * through it, a child's ends on it). */
#include "render_internal.h"

#include <stdlib.h>

typedef struct tree {
    uint32_t *parent, *depth;
    uint32_t n;
} tree;

/* Lowest common ancestor of two nodes (ids < t->n). */
static uint32_t lca(const tree *t, uint32_t a, uint32_t b)
{
    while (a != b) {
        uint32_t da = t->depth[a], db = t->depth[b];
        if (da >= db) a = t->parent[a];
        if (db >= da) b = t->parent[b];
        if (a == GS_NONE || b == GS_NONE) return GS_NONE; /* not one tree */
    }
    return a;
}

static void mid(const double *xyz, uint32_t u, uint32_t v, double *out)
{
    for (int k = 0; k < 3; ++k) out[k] = 0.5 * (xyz[3 * (size_t)u + k] + xyz[3 * (size_t)v + k]);
}

static int cmp_seg(const void *pa, const void *pb)
{
    const gs_rseg *a = pa, *b = pb;
    if (a->depth != b->depth) return a->depth > b->depth ? -1 : 1;
    return a->order < b->order ? -1 : a->order > b->order;
}

static int load_tree(const gs_db *db, tree *t, gs_error *err)
{
    gs_db_info info;
    int rc = gs_db_get_info(db, &info, err);
    if (rc) return rc;
    t->n = info.n_nodes;
    t->parent = gs__malloc(t->n ? t->n : 1, sizeof *t->parent);
    t->depth = gs__malloc(t->n ? t->n : 1, sizeof *t->depth);
    if (!t->parent || !t->depth) return gs__fail(err, GS_ENOMEM, "render: out of memory for the tree");
    for (uint32_t i = 0; i < t->n; ++i)
        if ((rc = gs_db_tree_node(db, i, &t->parent[i], &t->depth[i], err))) return rc;
    return GS_OK;
}

int gs__render_separators(const gs_mesh *mesh, const gs_db *db, gs_rseg **out, size_t *n, gs_error *err)
{
    *out = NULL;
    *n = 0;
    tree t = {0};
    int rc = load_tree(db, &t, err);
    uint32_t nf = gs_mesh_num_faces(mesh);
    const uint32_t *tri = gs_mesh_faces(mesh);
    const double *xyz = gs_mesh_positions(mesh);
    gs_rseg *s = rc ? NULL : gs__malloc(3 * (size_t)nf + 1, sizeof *s);
    if (!rc && !s) rc = gs__fail(err, GS_ENOMEM, "render: out of memory for the separators");
    size_t k = 0;
    for (uint32_t f = 0; !rc && f < nf; ++f) {
        const uint32_t *c = tri + 3 * (size_t)f;
        uint32_t l[3], cut[3], ncut = 0;
        int ok = 1;
        for (int i = 0; i < 3; ++i) {
            l[i] = gs_db_vertex_leaf(db, c[i]);
            ok &= l[i] < t.n;
        }
        if (!ok || (l[0] == l[1] && l[1] == l[2])) continue;
        for (int i = 0; i < 3; ++i) { /* edge i: corners i, i+1 */
            uint32_t a = l[i], b = l[(i + 1) % 3];
            cut[i] = a == b ? GS_NONE : lca(&t, a, b);
            ncut += cut[i] != GS_NONE;
        }
        if (ncut == 2) { /* one curve across the face */
            int e = cut[0] == GS_NONE ? 1 : 0, e2 = cut[2] == GS_NONE ? 1 : 2;
            gs_rseg *g = &s[k];
            mid(xyz, c[e], c[(e + 1) % 3], g->p[0]);
            mid(xyz, c[e2], c[(e2 + 1) % 3], g->p[1]);
            uint32_t node = cut[e];
            if (t.depth[cut[e2]] < t.depth[node]) node = cut[e2];
            g->depth = t.depth[node];
            g->order = (uint32_t)k++;
        } else if (ncut == 3) { /* curves meet at the centroid */
            double cen[3];
            for (int j = 0; j < 3; ++j)
                cen[j] = (xyz[3 * (size_t)c[0] + j] + xyz[3 * (size_t)c[1] + j] + xyz[3 * (size_t)c[2] + j]) / 3.0;
            for (int i = 0; i < 3; ++i) {
                gs_rseg *g = &s[k];
                mid(xyz, c[i], c[(i + 1) % 3], g->p[0]);
                for (int j = 0; j < 3; ++j) g->p[1][j] = cen[j];
                g->depth = t.depth[cut[i]];
                g->order = (uint32_t)k++;
            }
        }
    }
    free(t.parent);
    free(t.depth);
    if (rc) {
        free(s);
        return rc;
    }
    qsort(s, k, sizeof *s, cmp_seg);
    if (k == 0) {
        free(s);
        s = NULL;
    }
    *out = s;
    *n = k;
    return GS_OK;
}
