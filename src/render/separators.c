/* separators.c - the separator curves of a database, as segments to draw.
 * The database stores per vertex its leaf and the tree's shape, not the
 * curves' geometry: a node's separator lies between the vertices of its
 * two subtrees, so it crosses every edge whose endpoints' lowest common
 * ancestor is that node. Drawn through the edges' midpoints: a face with
 * two corners in one leaf gets one segment between the midpoints of its
 * two cut edges; a face with its corners in three leaves gets a segment
 * from each edge's midpoint to the centroid (a parent's curve passes
 * through it, a child's ends on it). The segments of each node are then
 * chained at their shared ends and smoothed (Taubin's lambda|mu filter,
 * which does not shrink loops), the curves' ends and junctions fixed: the
 * midpoints zigzag along the mesh's edges, the separators the database was
 * built from do not. */
#include "render_internal.h"

#include <stdlib.h>
#include <string.h>

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

/* An end's key: an edge's midpoint (its vertices, smaller first) or a
 * face's centroid (bit 63). */
static uint64_t edge_key(uint32_t u, uint32_t v)
{
    return u < v ? ((uint64_t)u << 32) | v : ((uint64_t)v << 32) | u;
}
#define CENTROID_KEY(f) ((1ull << 63) | (f))

typedef struct endp {
    uint32_t node;
    uint32_t ref; /* 2 seg + end */
    uint64_t key;
} endp;

static int cmp_endp(const void *pa, const void *pb)
{
    const endp *a = pa, *b = pb;
    if (a->node != b->node) return a->node < b->node ? -1 : 1;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->ref < b->ref ? -1 : a->ref > b->ref;
}

static int cmp_centroid(const void *pa, const void *pb)
{
    const endp *a = pa, *b = pb; /* node holds the depth here */
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    if (a->node != b->node) return a->node < b->node ? -1 : 1;
    return a->ref < b->ref ? -1 : a->ref > b->ref;
}

#define SMOOTH_PAIRS 20
#define SMOOTH_LAMBDA 0.5
#define SMOOTH_MU (-0.53)

/* Chain the segments of each node by their ends' keys and smooth the
 * points where exactly two segments meet. */
static int smooth(gs__rseg *s, size_t k, gs_error *err)
{
    endp *e = gs__malloc(2 * k + 1, sizeof *e);
    uint32_t *pid = gs__malloc(2 * k + 1, sizeof *pid), *deg = NULL;
    double *pos = NULL, *acc = NULL;
    int rc = GS_OK;
    if (!e || !pid) goto oom;
    for (size_t i = 0; i < 2 * k; ++i) {
        e[i].node = s[i / 2].node;
        e[i].key = s[i / 2].key[i % 2];
        e[i].ref = (uint32_t)i;
    }
    qsort(e, 2 * k, sizeof *e, cmp_endp);
    size_t np = 0;
    for (size_t i = 0; i < 2 * k; ++i) {
        if (i > 0 && (e[i].node != e[i - 1].node || e[i].key != e[i - 1].key)) np++;
        pid[e[i].ref] = (uint32_t)np;
    }
    np += k > 0;
    pos = gs__malloc(3 * np + 1, sizeof *pos);
    acc = gs__malloc(3 * np + 1, sizeof *acc);
    deg = gs__calloc(np + 1, sizeof *deg);
    if (!pos || !acc || !deg) goto oom;
    for (size_t i = 0; i < 2 * k; ++i) {
        for (int j = 0; j < 3; ++j) pos[3 * (size_t)pid[i] + j] = s[i / 2].p[i % 2][j];
        deg[pid[i]]++;
    }
    for (int it = 0; it < 2 * SMOOTH_PAIRS; ++it) {
        double lam = it % 2 ? SMOOTH_MU : SMOOTH_LAMBDA;
        memset(acc, 0, 3 * np * sizeof *acc);
        for (size_t i = 0; i < k; ++i) {
            uint32_t a = pid[2 * i], b = pid[2 * i + 1];
            for (int j = 0; j < 3; ++j) {
                acc[3 * (size_t)a + j] += pos[3 * (size_t)b + j];
                acc[3 * (size_t)b + j] += pos[3 * (size_t)a + j];
            }
        }
        for (size_t q = 0; q < np; ++q)
            if (deg[q] == 2)
                for (int j = 0; j < 3; ++j) pos[3 * q + j] += lam * (0.5 * acc[3 * q + j] - pos[3 * q + j]);
    }
    for (size_t i = 0; i < 2 * k; ++i)
        for (int j = 0; j < 3; ++j) s[i / 2].p[i % 2][j] = pos[3 * (size_t)pid[i] + j];
    /* junctions: a child's curve ends where its parent's passes */
    size_t nc = 0;
    for (size_t i = 0; i < 2 * k; ++i)
        if (s[i / 2].key[i % 2] >> 63) {
            e[nc].key = s[i / 2].key[i % 2];
            e[nc].node = s[i / 2].depth;
            e[nc].ref = (uint32_t)i;
            nc++;
        }
    qsort(e, nc, sizeof *e, cmp_centroid);
    for (size_t i = 0, first = 0; i < nc; ++i) {
        if (i > 0 && e[i].key != e[i - 1].key) first = i;
        uint32_t r = e[i].ref, r0 = e[first].ref;
        memcpy(s[r / 2].p[r % 2], s[r0 / 2].p[r0 % 2], sizeof s[r / 2].p[r % 2]);
    }
    goto done;
oom:
    rc = gs__fail(err, GS_ENOMEM, "render: out of memory for the separators");
done:
    free(e);
    free(pid);
    free(deg);
    free(pos);
    free(acc);
    return rc;
}

static int cmp_seg(const void *pa, const void *pb)
{
    const gs__rseg *a = pa, *b = pb;
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

int gs__render_separators(const gs_mesh *mesh, const gs_db *db, gs__rseg **out, size_t *n, gs_error *err)
{
    *out = NULL;
    *n = 0;
    tree t = {0};
    int rc = load_tree(db, &t, err);
    uint32_t nf = gs_mesh_num_faces(mesh);
    const uint32_t *tri = gs_mesh_faces(mesh);
    const double *xyz = gs_mesh_positions(mesh);
    gs__rseg *s = rc ? NULL : gs__malloc(3 * (size_t)nf + 1, sizeof *s);
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
            gs__rseg *g = &s[k];
            mid(xyz, c[e], c[(e + 1) % 3], g->p[0]);
            mid(xyz, c[e2], c[(e2 + 1) % 3], g->p[1]);
            g->key[0] = edge_key(c[e], c[(e + 1) % 3]);
            g->key[1] = edge_key(c[e2], c[(e2 + 1) % 3]);
            uint32_t node = cut[e];
            if (t.depth[cut[e2]] < t.depth[node]) node = cut[e2];
            g->node = node;
            g->depth = t.depth[node];
            g->order = (uint32_t)k++;
        } else if (ncut == 3) { /* curves meet at the centroid */
            double cen[3];
            for (int j = 0; j < 3; ++j)
                cen[j] = (xyz[3 * (size_t)c[0] + j] + xyz[3 * (size_t)c[1] + j] + xyz[3 * (size_t)c[2] + j]) / 3.0;
            for (int i = 0; i < 3; ++i) {
                gs__rseg *g = &s[k];
                mid(xyz, c[i], c[(i + 1) % 3], g->p[0]);
                for (int j = 0; j < 3; ++j) g->p[1][j] = cen[j];
                g->key[0] = edge_key(c[i], c[(i + 1) % 3]);
                g->key[1] = CENTROID_KEY((uint64_t)f);
                g->node = cut[i];
                g->depth = t.depth[cut[i]];
                g->order = (uint32_t)k++;
            }
        }
    }
    free(t.parent);
    free(t.depth);
    if (!rc) rc = smooth(s, k, err);
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
