/* leaves.c - the exact same-leaf distances of gs_db_build (leaf_exact;
 * paper sec. 3.1, matrix D), leaf by leaf in parallel. */
#include "pipeline.h"

#include "../geodesic/geodesic_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* For every leaf L and every pair x, y of its vertices, the exact distance
 * d_M(x, y) on the whole mesh (exact fields, whatever the builder's method). Solving a field
 * on the whole mesh from every vertex would cost O(nv) per solve just to
 * initialise it, so each leaf is solved on a region that provably holds all
 * the shortest paths needed:
 *  1. R_x = max_y d_P(L)(x, y) inside the leaf's own patch bounds d_M(x, y)
 *     from above for every y of L (a path in P(L) is a path in M).
 *  2. A shortest path of length <= R_x stays in the Euclidean ball B(x, R_x),
 *     so it only crosses faces meeting that ball, and consecutive faces along
 *     it share a vertex. The region is the set of faces reached from x's
 *     faces through shared vertices while keeping faces that may meet some
 *     B(x, R_x) (conservative: some corner within R_x + the face's longest
 *     edge of x, since a triangle lies within its longest edge of each corner).
 *  3. d_region(x, .) >= d_M(x, .) (fewer paths) and equals it for y in L (the
 *     shortest path is in the region); the solve is bounded by R_x. Faces
 *     left out do not meet any ball, so the region's artificial boundary lies
 *     outside them. R_x infinite (y unreachable in P(L)) floods x's component.
 * The table is made exactly symmetric with min(d(x,y), d(y,x)). */

void gs__pipe_leaf_tables_free(gs__leaf_tables *lt)
{
    free(lt->vstart);
    free(lt->verts);
    free(lt->dstart);
    free(lt->dist);
    memset(lt, 0, sizeof *lt);
}

/* Per-thread scratch for leaf solves. */
typedef struct leaf_work {
    uint32_t *fstamp;  /* mesh faces: stamp of the last leaf that took it  */
    uint32_t *faces;   /* the region's faces                               */
    size_t cap;
    double *dist;      /* field on the current patch                       */
    size_t dcap;
    double *radius;    /* R_x per leaf vertex (times 1 + 1e-9)             */
    size_t rcap;
} leaf_work;

/* Can face f meet the ball B(x, r) of some leaf vertex x? */
static int face_near_leaf(const gs_mesh *m, uint32_t f, const uint32_t *lv, uint32_t n, const double *r)
{
    const gs__topo *t = &m->topo;
    const double *p[3];
    for (int i = 0; i < 3; ++i) p[i] = m->xyz + 3 * (size_t)m->tri[3 * (size_t)f + i];
    double e = fmax(t->len[3 * (size_t)f], fmax(t->len[3 * (size_t)f + 1], t->len[3 * (size_t)f + 2]));
    for (uint32_t k = 0; k < n; ++k) {
        if (!(r[k] < INFINITY)) return 1;
        const double *q = m->xyz + 3 * (size_t)lv[k];
        double lim = (r[k] + e) * (1 + 1e-12) + 1e-300;
        lim *= lim;
        for (int i = 0; i < 3; ++i) {
            double dx = p[i][0] - q[0], dy = p[i][1] - q[1], dz = p[i][2] - q[2];
            if (dx * dx + dy * dy + dz * dz <= lim) return 1;
        }
    }
    return 0;
}

uint32_t gs__pipe_region(const gs_mesh *m, const uint32_t *lv, uint32_t n, const double *r, uint32_t stamp,
                         uint32_t *fstamp, uint32_t **faces, size_t *cap)
{
    const gs__topo *t = &m->topo;
    size_t nf = 0;
    for (uint32_t k = 0; k < n; ++k)
        for (uint32_t c = t->vc_start[lv[k]]; c < t->vc_start[lv[k] + 1]; ++c) {
            uint32_t f = t->vc[c] / 3;
            if (fstamp[f] == stamp) continue;
            fstamp[f] = stamp;
            if (gs__grow((void **)faces, cap, nf + 1, sizeof **faces)) return GS_NONE;
            (*faces)[nf++] = f;
        }
    for (size_t q = 0; q < nf; ++q) { /* breadth first through shared vertices */
        uint32_t f = (*faces)[q];
        for (int i = 0; i < 3; ++i) {
            uint32_t v = m->tri[3 * (size_t)f + i];
            for (uint32_t c = t->vc_start[v]; c < t->vc_start[v + 1]; ++c) {
                uint32_t g = t->vc[c] / 3;
                if (fstamp[g] == stamp) continue;
                fstamp[g] = stamp;
                if (!face_near_leaf(m, g, lv, n, r)) continue;
                if (gs__grow((void **)faces, cap, nf + 1, sizeof **faces)) return GS_NONE;
                (*faces)[nf++] = g;
            }
        }
    }
    return (uint32_t)nf;
}

/* The faces of the region of a leaf (see above) into w->faces. */
static uint32_t leaf_region(const gs_mesh *m, const uint32_t *lv, uint32_t n, const double *r, uint32_t stamp,
                            leaf_work *w)
{
    return gs__pipe_region(m, lv, n, r, stamp, w->fstamp, &w->faces, &w->cap);
}

/* Fields from every vertex of patch p's subset lv (n vertices); row k of T
 * (n x n) gets source k's distances to all of lv. bound: per-source bound
 * (NULL: none). */
static int leaf_solve(const gs_patch *p, gs_method method, const gs_solver_options *so_opt, const uint32_t *lv, uint32_t n, const double *bound,
                      double *T, leaf_work *w, gs_error *err)
{
    uint32_t nl = gs_patch_num_vertices(p);
    if (gs__grow((void **)&w->dist, &w->dcap, nl, sizeof *w->dist))
        return gs__fail(err, GS_ENOMEM, "out of memory for a leaf field");
    gs_solver *s = NULL;
    int rc = gs_solver_create_ex(p, method, so_opt, &s, err);
    for (uint32_t k = 0; k < n && rc == GS_OK; ++k) {
        uint32_t src = gs_patch_vertex_from_mesh(p, lv[k]);
        if (src == GS_NONE) {
            rc = gs__fail(err, GS_EINTERNAL, "leaf vertex %u is not in its leaf's patch", lv[k]);
            break;
        }
        gs_source so = gs_source_vertex(src);
        rc = gs_solver_solve(s, &so, 1, bound && bound[k] < INFINITY ? bound[k] : 0, w->dist, err);
        for (uint32_t j = 0; j < n && rc == GS_OK; ++j) {
            uint32_t lj = gs_patch_vertex_from_mesh(p, lv[j]);
            T[(size_t)k * n + j] = lj == GS_NONE ? INFINITY : w->dist[lj];
        }
    }
    gs_solver_free(s);
    return rc;
}

static int leaf_table(gs__builder *b, uint32_t node, const uint32_t *lv, double *T, uint32_t stamp, leaf_work *w,
                      gs_error *err)
{
    const gs__tree_node *nd = &b->tree->nodes[node];
    uint32_t n = nd->n_verts;
    /* exact fields whatever the build's method: the region below is bounded
     * by the leaf's own distances, which only exact fields make safe (fmm's
     * overestimates left pairs of a leaf unreached: +inf answers) */
    gs_method method = GS_METHOD_EXACT;
    if (gs__grow((void **)&w->radius, &w->rcap, n, sizeof *w->radius))
        return gs__fail(err, GS_ENOMEM, "out of memory for leaf %u", node);
    gs_patch *p = NULL;
    int rc = gs_patch_create(b->mesh, b->tree->faces + nd->face_start, nd->n_faces, &p, err);
    if (rc == GS_OK) rc = leaf_solve(p, method, &b->opt->solver, lv, n, NULL, T, w, err);
    gs_patch_free(p);
    p = NULL;
    if (rc) return rc;
    for (uint32_t k = 0; k < n; ++k) {
        double r = 0;
        for (uint32_t j = 0; j < n; ++j) r = fmax(r, T[(size_t)k * n + j]); /* INFINITY stays */
        w->radius[k] = r * (1 + 1e-9);
    }
    uint32_t nf = leaf_region(b->mesh, lv, n, w->radius, stamp, w);
    if (nf == GS_NONE) return gs__fail(err, GS_ENOMEM, "out of memory for leaf %u's region", node);
    rc = gs_patch_create(b->mesh, w->faces, nf, &p, err);
    if (rc == GS_OK) rc = leaf_solve(p, method, &b->opt->solver, lv, n, w->radius, T, w, err);
    gs_patch_free(p);
    if (rc) return rc;
    for (uint32_t k = 0; k < n; ++k) {
        T[(size_t)k * n + k] = 0;
        for (uint32_t j = k + 1; j < n; ++j) {
            double d = fmin(T[(size_t)k * n + j], T[(size_t)j * n + k]);
            T[(size_t)k * n + j] = T[(size_t)j * n + k] = d;
        }
    }
    return GS_OK;
}

int gs__pipe_leaf_tables(gs__builder *b, gs__leaf_tables *lt, gs_error *err)
{
    const gs__tree *t = b->tree;
    uint32_t nn = t->n_nodes;
    memset(lt, 0, sizeof *lt);
    lt->vstart = gs__malloc((size_t)nn + 1, sizeof *lt->vstart);
    lt->dstart = gs__malloc((size_t)nn + 1, sizeof *lt->dstart);
    uint32_t *leaves = gs__malloc(nn, sizeof *leaves);
    if (!lt->vstart || !lt->dstart || !leaves) {
        free(leaves);
        return gs__fail(err, GS_ENOMEM, "out of memory for leaf tables");
    }
    uint32_t n_leaves = 0;
    lt->vstart[0] = 0;
    lt->dstart[0] = 0;
    for (uint32_t i = 0; i < nn; ++i) {
        const gs__tree_node *nd = &t->nodes[i];
        uint32_t n = nd->child[0] == GS_NONE ? nd->n_verts : 0;
        if (nd->child[0] == GS_NONE) leaves[n_leaves++] = i;
        lt->vstart[i + 1] = lt->vstart[i] + n;
        lt->dstart[i + 1] = lt->dstart[i] + (uint64_t)n * n;
    }
    lt->verts = gs__malloc(lt->vstart[nn] ? lt->vstart[nn] : 1, sizeof *lt->verts);
    lt->dist = gs__malloc(lt->dstart[nn] ? lt->dstart[nn] : 1, sizeof *lt->dist);
    if (!lt->verts || !lt->dist) {
        free(leaves);
        return gs__fail(err, GS_ENOMEM, "out of memory for %llu leaf distances",
                        (unsigned long long)lt->dstart[nn]);
    }
    for (uint32_t i = 0; i < nn; ++i)
        if (lt->vstart[i + 1] > lt->vstart[i])
            memcpy(lt->verts + lt->vstart[i], t->verts + t->nodes[i].vert_start,
                   (size_t)(lt->vstart[i + 1] - lt->vstart[i]) * sizeof *lt->verts);
    int rc = GS_OK;
    uint32_t done = 0;
    uint64_t n_fields = 0;
#pragma omp parallel num_threads(b->nthreads) reduction(+ : n_fields)
    {
        leaf_work w;
        memset(&w, 0, sizeof w);
        gs_error e;
        w.fstamp = gs__calloc(b->mesh->nf ? b->mesh->nf : 1, sizeof *w.fstamp);
        int my = w.fstamp ? GS_OK : gs__fail(&e, GS_ENOMEM, "out of memory");
#pragma omp for schedule(dynamic, 1)
        for (uint32_t q = 0; q < n_leaves; ++q) {
            if (my) continue;
            uint32_t l = leaves[q];
            my = leaf_table(b, l, lt->verts + lt->vstart[l], lt->dist + lt->dstart[l], q + 1, &w, &e);
            n_fields += 2 * (uint64_t)(lt->vstart[l + 1] - lt->vstart[l]);
            uint32_t d;
#pragma omp atomic capture
            d = ++done;
            if (omp_get_thread_num() == 0) gs__pipe_progress(b, "leaves", (double)d / n_leaves);
        }
#pragma omp critical
        if (my && rc == GS_OK) {
            rc = my;
            if (err) *err = e;
        }
        free(w.fstamp);
        free(w.faces);
        free(w.dist);
        free(w.radius);
    }
    free(leaves);
    b->n_fields += n_fields;
    return rc;
}
