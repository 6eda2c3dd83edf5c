/* near.c - the near pairs of gs_db_build (near_radius; issue 17): every
 * cross-leaf pair of vertices nearer than the radius whose answer through
 * the separators is off by more than GS_PIPE_NEAR_TOL gets its exact
 * distance stored (section 'near_pairs', src/db/db_near.h).
 *
 * Why: a vertex a few edges from a separator curve sees the curve's kinks
 * (the level set that decides the sides bends at every edge it crosses),
 * and two neighbours on either side of it are answered through samples
 * half an edge apart: the bound of doc/accuracy.md (|error| <= eps d +
 * 2.04 h) is then tens of percent of d. Few pairs are off (bunny-5k: ~0.06
 * per vertex beyond 2%), so only those are stored.
 *
 * How: leaf by leaf (in parallel), the exact field from each vertex x of
 * the leaf bounded by the radius R, on the region of faces a path of
 * length < R from a leaf vertex may cross (gs__pipe_region, the argument of
 * leaves.c): d(x, y) is exact for every y with d < R. Each pair is taken
 * at its smaller vertex and compared with the answer of the database built
 * without the section (db0: the same records, so the same answer). */
#include "pipeline.h"

#include "../db/db_internal.h"
#include "../geodesic/geodesic_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

typedef struct near_work {
    uint32_t *fstamp;
    uint32_t *faces;
    size_t cap;
    double *dist, *radius;
    size_t dcap, rcap;
    gs__near_pair *pairs;
    size_t n, pcap;
} near_work;

/* The pairs of leaf `node` (its n vertices lv) into w->pairs; radius:
 * each vertex's (near_radius). */
static int near_leaf(const gs__builder *b, const gs_db *db0, uint32_t node, const uint32_t *lv, uint32_t n,
                     const double *radius, double tol, uint32_t stamp, near_work *w, gs_error *err)
{
    const uint32_t *leaf = b->tree->leaf_of_vertex;
    if (gs__grow((void **)&w->radius, &w->rcap, n, sizeof *w->radius))
        return gs__fail(err, GS_ENOMEM, "out of memory for leaf %u's near pairs", node);
    for (uint32_t k = 0; k < n; ++k) w->radius[k] = radius[lv[k]];
    uint32_t nf = gs__pipe_region(b->mesh, lv, n, w->radius, stamp, w->fstamp, &w->faces, &w->cap);
    if (nf == GS_NONE) return gs__fail(err, GS_ENOMEM, "out of memory for leaf %u's near region", node);
    gs_patch *p = NULL;
    gs_solver *s = NULL;
    int rc = gs_patch_create(b->mesh, w->faces, nf, &p, err);
    if (rc == GS_OK) rc = gs_solver_create_ex(p, GS_METHOD_EXACT, &b->opt->solver, &s, err);
    uint32_t np = rc == GS_OK ? gs_patch_num_vertices(p) : 0;
    if (rc == GS_OK && gs__grow((void **)&w->dist, &w->dcap, np, sizeof *w->dist))
        rc = gs__fail(err, GS_ENOMEM, "out of memory for a near field");
    for (uint32_t k = 0; k < n && rc == GS_OK; ++k) {
        uint32_t x = lv[k], src = gs_patch_vertex_from_mesh(p, x);
        if (src == GS_NONE) {
            rc = gs__fail(err, GS_EINTERNAL, "leaf vertex %u is not in its near region", x);
            break;
        }
        gs_source so = gs_source_vertex(src);
        double R = w->radius[k];
        rc = gs_solver_solve(s, &so, 1, R, w->dist, err);
        for (uint32_t v = 0; v < np && rc == GS_OK; ++v) {
            double d = w->dist[v];
            if (!(d < R && d > 0)) continue;
            uint32_t y = gs_patch_vertex_to_mesh(p, v);
            if (leaf[y] == node || leaf[y] == GS_NONE) continue;
            double a = gs_db_distance(db0, x, y);
            if (fabs(a - d) <= tol * d) continue; /* NaN or inf: stored */
            if (gs__grow((void **)&w->pairs, &w->pcap, w->n + 1, sizeof *w->pairs))
                rc = gs__fail(err, GS_ENOMEM, "out of memory for near pairs");
            else w->pairs[w->n++] = x < y ? (gs__near_pair){x, y, d} : (gs__near_pair){y, x, d};
        }
    }
    gs_solver_free(s);
    gs_patch_free(p);
    return rc;
}

static int pair_cmp(const void *a, const void *b)
{
    const gs__near_pair *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    return p->y < q->y ? -1 : (p->y > q->y);
}

int gs__pipe_near_pairs(gs__builder *b, const gs_db *db0, const double *radius, double tol, gs__near_pair **out,
                        uint64_t *n_out, gs_error *err)
{
    const gs__tree *t = b->tree;
    *out = NULL;
    *n_out = 0;
    uint32_t *leaves = gs__malloc(t->n_nodes ? t->n_nodes : 1, sizeof *leaves), n_leaves = 0;
    if (!leaves) return gs__fail(err, GS_ENOMEM, "out of memory for near pairs");
    for (uint32_t i = 0; i < t->n_nodes; ++i)
        if (t->nodes[i].child[0] == GS_NONE && t->nodes[i].n_verts) leaves[n_leaves++] = i;
    int rc = GS_OK;
    uint32_t done = 0;
    gs__near_pair *all = NULL;
    size_t n_all = 0;
#pragma omp parallel num_threads(b->nthreads)
    {
        near_work w;
        memset(&w, 0, sizeof w);
        gs_error e;
        w.fstamp = gs__calloc(b->mesh->nf ? b->mesh->nf : 1, sizeof *w.fstamp);
        int my = w.fstamp ? GS_OK : gs__fail(&e, GS_ENOMEM, "out of memory");
#pragma omp for schedule(dynamic, 1)
        for (uint32_t q = 0; q < n_leaves; ++q) {
            if (my) continue;
            const gs__tree_node *nd = &t->nodes[leaves[q]];
            my = near_leaf(b, db0, leaves[q], t->verts + nd->vert_start, nd->n_verts, radius, tol, q + 1, &w, &e);
            uint32_t d;
#pragma omp atomic capture
            d = ++done;
            if (omp_get_thread_num() == 0) gs__pipe_progress(b, "near", (double)d / n_leaves);
        }
#pragma omp critical
        {
            if (!my && w.n) {
                gs__near_pair *m = gs__realloc(all, n_all + w.n, sizeof *all);
                if (!m) my = gs__fail(&e, GS_ENOMEM, "out of memory for near pairs");
                else memcpy(m + n_all, w.pairs, w.n * sizeof *m), all = m, n_all += w.n;
            }
            if (my && rc == GS_OK) {
                rc = my;
                if (err) *err = e;
            }
        }
        free(w.fstamp);
        free(w.faces);
        free(w.dist);
        free(w.radius);
        free(w.pairs);
    }
    free(leaves);
    if (rc) {
        free(all);
        return rc;
    }
    if (n_all) qsort(all, n_all, sizeof *all, pair_cmp); /* all may be NULL: none */
    size_t m = 0; /* a pair found from both ends once, its smaller distance */
    for (size_t i = 0; i < n_all; ++i) {
        if (m && all[m - 1].x == all[i].x && all[m - 1].y == all[i].y) all[m - 1].d = fmin(all[m - 1].d, all[i].d);
        else all[m++] = all[i];
    }
    *out = all;
    *n_out = m;
    return GS_OK;
}
