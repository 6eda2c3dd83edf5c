/* split.c - the graph cut of one node of the nested bisection (paper sec.
 * 4.1): the vertices owned by a patch are bisected by their connected
 * components or by METIS (edges weighted by the length a cut through them
 * adds to the separator); ghost vertices then join a side by majority. The
 * cut is then smoothed into a level set: of the diffused side indicator, or
 * of d_A^2 - d_B^2 for the two sides' centres A, B (the power bisector:
 * straight wherever the patch is flat). */
#include "partition_internal.h"

#include <math.h>
#include <metis.h>
#include <stdlib.h>
#include <string.h>

/* The graph induced by the owned vertices, in CSR form (METIS layout). */
typedef struct owned_graph {
    idx_t n;
    idx_t *xadj, *adj;
    idx_t *wgt;     /* per adjacency entry: the edge's dual length, scaled */
} owned_graph;

static void graph_free(owned_graph *g)
{
    free(g->xadj);
    free(g->adj);
    free(g->wgt);
}

/* Length of the dual edge of half-edge h: face centroid -> edge midpoint ->
 * centroid of the face across (the piece of a cut curve that crosses it). */
static double dual_length(const gs_mesh *m, uint32_t h)
{
    const gs__topo *t = &m->topo;
    uint32_t a = m->tri[h], b = m->tri[gs__next(h)];
    double mid[3], len = 0;
    for (int d = 0; d < 3; ++d) mid[d] = 0.5 * (m->xyz[3 * (size_t)a + d] + m->xyz[3 * (size_t)b + d]);
    uint32_t hs[2] = {h, t->opp[h]};
    for (int s = 0; s < 2; ++s) {
        if (hs[s] == GS_NONE) continue;
        const uint32_t *c = m->tri + 3 * (size_t)(hs[s] / 3);
        double q = 0;
        for (int d = 0; d < 3; ++d) {
            double cd = (m->xyz[3 * (size_t)c[0] + d] + m->xyz[3 * (size_t)c[1] + d] + m->xyz[3 * (size_t)c[2] + d]) / 3;
            q += (cd - mid[d]) * (cd - mid[d]);
        }
        len += sqrt(q);
    }
    return len;
}

/* Every undirected edge between two owned vertices once in each direction,
 * weighted by its dual length (about 100 per mean edge length) so that the
 * minimum cut is the shortest curve in space, not the fewest edges (on a
 * steep height field the two differ a lot). All faces at an owned vertex
 * are in P(N), so h < opp(h) picks each mesh edge exactly once. */
static int graph_build(const gs__part_node *nd, owned_graph *g, double mean_edge)
{
    const gs__topo *t = &nd->mesh->topo;
    double scale = 100.0 / (mean_edge > 0 ? mean_edge : 1.0); /* ~100 per edge */
    g->n = (idx_t)nd->no;
    g->xadj = calloc((size_t)nd->no + 1, sizeof *g->xadj);
    g->adj = NULL;
    g->wgt = NULL;
    if (!g->xadj) return GS_ENOMEM;
    for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t lf = 0; lf < nd->nf; ++lf)
            for (uint32_t k = 0; k < 3; ++k) {
                uint32_t h = 3 * nd->faces[lf] + k;
                if (t->opp[h] != GS_NONE && t->opp[h] < h) continue;
                uint32_t a = nd->vloc[t->tri[h]], b = nd->vloc[t->tri[gs__next(h)]];
                if (a >= nd->no || b >= nd->no) continue;
                if (pass == 0) {
                    g->xadj[a + 1]++;
                    g->xadj[b + 1]++;
                } else {
                    double dl = dual_length(nd->mesh, h) * scale;
                    idx_t w = dl < 1 ? 1 : (dl > 1e4 ? 10000 : (idx_t)lround(dl));
                    g->wgt[g->xadj[a]] = w;
                    g->adj[g->xadj[a]++] = (idx_t)b;
                    g->wgt[g->xadj[b]] = w;
                    g->adj[g->xadj[b]++] = (idx_t)a;
                }
            }
        if (pass == 0) {
            for (uint32_t v = 0; v < nd->no; ++v) g->xadj[v + 1] += g->xadj[v];
            g->adj = gs__malloc((size_t)g->xadj[nd->no] + 1, sizeof *g->adj);
            g->wgt = gs__malloc((size_t)g->xadj[nd->no] + 1, sizeof *g->wgt);
            if (!g->adj || !g->wgt) return GS_ENOMEM;
        } else { /* the fill advanced xadj[v] to the start of v + 1 */
            memmove(g->xadj + 1, g->xadj, (size_t)nd->no * sizeof *g->xadj);
            g->xadj[0] = 0;
        }
    }
    /* METIS sums the weights in 32 bits: keep the total below 2^30 */
    uint64_t total = 0, ne = (uint64_t)g->xadj[nd->no];
    for (uint64_t k = 0; k < ne; ++k) total += (uint64_t)g->wgt[k];
    if (total > (1u << 30)) {
        double f = (double)(1u << 30) / (double)total;
        for (uint64_t k = 0; k < ne; ++k) {
            idx_t w = (idx_t)(g->wgt[k] * f);
            g->wgt[k] = w < 1 ? 1 : w;
        }
    }
    return GS_OK;
}

/* Connected components: comp[v] in 0..n_comp-1, BFS order in `order`. */
static uint32_t components(const owned_graph *g, uint32_t *comp, uint32_t *order)
{
    uint32_t n = (uint32_t)g->n, nc = 0, tail = 0;
    for (uint32_t v = 0; v < n; ++v) comp[v] = GS_NONE;
    for (uint32_t s = 0; s < n; ++s) {
        if (comp[s] != GS_NONE) continue;
        uint32_t head = tail;
        comp[s] = nc;
        order[tail++] = s;
        while (head < tail) {
            uint32_t v = order[head++];
            for (idx_t e = g->xadj[v]; e < g->xadj[v + 1]; ++e) {
                uint32_t w = (uint32_t)g->adj[e];
                if (comp[w] == GS_NONE) {
                    comp[w] = nc;
                    order[tail++] = w;
                }
            }
        }
        nc++;
    }
    return nc;
}

typedef struct comp_size {
    uint32_t size, id;
} comp_size;

static int cmp_comp(const void *a, const void *b)
{
    const comp_size *x = a, *y = b;
    if (x->size != y->size) return x->size > y->size ? -1 : 1;
    return x->id < y->id ? -1 : (x->id > y->id);
}

/* Group components into two halves, largest first onto the lighter side.
 * Returns 1 (sides set) if the smaller half has at least a quarter. */
static int split_by_components(gs__part_node *nd, const uint32_t *comp, uint32_t nc,
                               int *ok)
{
    comp_size *cs = gs__malloc(nc, sizeof *cs);
    uint8_t *cside = gs__malloc(nc, 1);
    if (!cs || !cside) {
        free(cs);
        free(cside);
        return GS_ENOMEM;
    }
    for (uint32_t c = 0; c < nc; ++c) cs[c] = (comp_size){0, c};
    for (uint32_t v = 0; v < nd->no; ++v) cs[comp[v]].size++;
    qsort(cs, nc, sizeof *cs, cmp_comp);
    uint32_t w[2] = {0, 0};
    for (uint32_t i = 0; i < nc; ++i) {
        int s = w[1] < w[0];
        cside[cs[i].id] = (uint8_t)s;
        w[s] += cs[i].size;
    }
    uint32_t small = w[0] < w[1] ? w[0] : w[1];
    *ok = 4 * (uint64_t)small >= nd->no;
    if (*ok)
        for (uint32_t v = 0; v < nd->no; ++v) nd->side[v] = cside[comp[v]];
    free(cs);
    free(cside);
    return GS_OK;
}

static int split_by_metis(gs__part_node *nd, const owned_graph *g, uint32_t seed,
                          gs_error *err)
{
    idx_t nv = g->n, ncon = 1, nparts = 2, objval = 0;
    idx_t options[METIS_NOPTIONS];
    idx_t *part = gs__malloc(nd->no, sizeof *part);
    if (!part) return gs__fail(err, GS_ENOMEM, "out of memory bisecting a patch");
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = (idx_t)(seed & 0x7fffffff);
    options[METIS_OPTION_NUMBERING] = 0;
    int r;
    /* METIS keeps its random generator in global state (GKlib), seeded at
     * the start of each call: calls from the tree's threads take turns, so
     * each one's result depends on its seed only. */
#pragma omp critical(gs__metis)
    r = METIS_PartGraphRecursive(&nv, &ncon, g->xadj, g->adj, NULL, NULL, g->wgt, &nparts, NULL,
                                 NULL, options, &objval, part);
    if (r != METIS_OK) {
        free(part);
        return gs__fail(err, r == METIS_ERROR_MEMORY ? GS_ENOMEM : GS_EINTERNAL,
                        "METIS failed (%d) bisecting node %u (%u vertices)", r, nd->id,
                        nd->no);
    }
    for (uint32_t v = 0; v < nd->no; ++v) nd->side[v] = part[v] ? 1 : 0;
    free(part);
    return GS_OK;
}

/* Fallback when a cut leaves a side empty: halves of the BFS order. */
static void split_by_order(gs__part_node *nd, const uint32_t *order)
{
    for (uint32_t i = 0; i < nd->no; ++i) nd->side[order[i]] = i >= nd->no / 2;
}

/* Each ghost vertex joins the side of most of its owned neighbours (every
 * face of P(N) has an owned corner, so each ghost has one). Ties: side 0. */
static int ghost_sides(gs__part_node *nd)
{
    uint32_t ng = nd->nl - nd->no;
    if (ng == 0) return GS_OK;
    int32_t *vote = calloc(ng, sizeof *vote);
    if (!vote) return GS_ENOMEM;
    const uint32_t *tri = nd->mesh->tri;
    for (uint32_t lf = 0; lf < nd->nf; ++lf) {
        const uint32_t *c = tri + 3 * (size_t)nd->faces[lf];
        for (int k = 0; k < 3; ++k) {
            uint32_t a = nd->vloc[c[k]], b = nd->vloc[c[(k + 1) % 3]];
            if (a < nd->no && b >= nd->no) vote[b - nd->no] += nd->side[a] ? 1 : -1;
            if (b < nd->no && a >= nd->no) vote[a - nd->no] += nd->side[b] ? 1 : -1;
        }
    }
    for (uint32_t i = 0; i < ng; ++i) nd->side[nd->no + i] = vote[i] > 0;
    free(vote);
    return GS_OK;
}

int gs__part_sides(gs__part_node *nd, uint32_t seed, double mean_edge, gs_error *err)
{
    owned_graph g = {0};
    uint32_t *comp = gs__malloc(nd->no, sizeof *comp);
    uint32_t *order = gs__malloc(nd->no, sizeof *order);
    int rc = (comp && order) ? graph_build(nd, &g, mean_edge) : GS_ENOMEM;
    if (rc) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory bisecting a patch");
        goto done;
    }
    uint32_t nc = components(&g, comp, order);
    int ok = 0;
    if (nc > 1 && (rc = split_by_components(nd, comp, nc, &ok)) != GS_OK) {
        rc = gs__fail(err, rc, "out of memory bisecting a patch");
        goto done;
    }
    if (!ok && (rc = split_by_metis(nd, &g, seed, err)) != GS_OK) goto done;
    uint32_t n1 = 0;
    for (uint32_t v = 0; v < nd->no; ++v) n1 += nd->side[v];
    if (n1 == 0 || n1 == nd->no) split_by_order(nd, order);
    if ((rc = ghost_sides(nd)) != GS_OK) rc = gs__fail(err, rc, "out of memory bisecting a patch");
done:
    graph_free(&g);
    free(comp);
    free(order);
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y);
}

/* Adjacency of the local vertices through the edges of P(N) (an interior
 * edge appears twice, once per face: it counts double), weight 1/length. */
typedef struct local_graph {
    uint32_t *start, *nbr;
    double *w;
} local_graph;

static void local_graph_free(local_graph *g)
{
    free(g->start);
    free(g->nbr);
    free(g->w);
}

static int local_graph_build(const gs__part_node *nd, local_graph *g)
{
    const uint32_t *tri = nd->mesh->tri;
    const gs__topo *t = &nd->mesh->topo;
    size_t ne = 6 * (size_t)nd->nf;
    g->start = gs__calloc((size_t)nd->nl + 1, sizeof *g->start);
    g->nbr = gs__malloc(ne, sizeof *g->nbr);
    g->w = gs__malloc(ne, sizeof *g->w);
    if (!g->start || !g->nbr || !g->w) return GS_ENOMEM;
    for (uint32_t lf = 0; lf < nd->nf; ++lf)
        for (int k = 0; k < 3; ++k) {
            g->start[nd->vloc[tri[3 * (size_t)nd->faces[lf] + k]] + 1] += 2;
        }
    for (uint32_t v = 0; v < nd->nl; ++v) g->start[v + 1] += g->start[v];
    uint32_t *fill = gs__malloc(nd->nl ? nd->nl : 1, sizeof *fill);
    if (!fill) return GS_ENOMEM;
    memcpy(fill, g->start, (size_t)nd->nl * sizeof *fill);
    for (uint32_t lf = 0; lf < nd->nf; ++lf)
        for (int k = 0; k < 3; ++k) {
            uint32_t h = 3 * nd->faces[lf] + (uint32_t)k;
            uint32_t a = nd->vloc[tri[h]], b = nd->vloc[tri[gs__next(h)]];
            double w = t->len[h] > 0 ? 1.0 / t->len[h] : 1.0;
            g->nbr[fill[a]] = b, g->w[fill[a]++] = w;
            g->nbr[fill[b]] = a, g->w[fill[b]++] = w;
        }
    free(fill);
    return GS_OK;
}

/* Cut nd->phi at the level that keeps METIS's share of side-1 owned
 * vertices, or the nearest share (within an eighth of the vertices) whose
 * level is clear of the values by 1e-9 of their range: a level set through
 * (numerically) tied values would zigzag around them. Sets every local side
 * and phi_valid; keeps the sides when there is no such level. */
int gs__part_cut_median(gs__part_node *nd)
{
    double *phi = nd->phi, *sorted = gs__malloc(nd->no, sizeof *sorted);
    if (!sorted) return GS_ENOMEM;
    uint32_t n1 = 0;
    for (uint32_t v = 0; v < nd->no; ++v) {
        sorted[v] = phi[v];
        n1 += nd->side[v];
    }
    qsort(sorted, nd->no, sizeof *sorted, cmp_double);
    uint32_t k0 = nd->no - n1, k = 0; /* side-0 count */
    double gap = 1e-9 * (sorted[nd->no - 1] - sorted[0]);
    for (uint32_t j = 0; j <= nd->no / 8 && k == 0; ++j) {
        if (k0 + j > 0 && k0 + j < nd->no && sorted[k0 + j] - sorted[k0 + j - 1] > gap) k = k0 + j;
        else if (j && k0 > j && sorted[k0 - j] - sorted[k0 - j - 1] > gap) k = k0 - j;
    }
    if (k > 0 && k < nd->no) {
        double level = 0.5 * (sorted[k - 1] + sorted[k]);
        if (sorted[k - 1] < level && level < sorted[k]) {
            for (uint32_t v = 0; v < nd->nl; ++v) {
                phi[v] -= level;
                nd->side[v] = phi[v] > 0;
            }
            nd->phi_valid = 1;
        }
    }
    free(sorted);
    return GS_OK;
}

int gs__part_level_set(gs__part_node *nd, uint32_t iters, gs_error *err)
{
    if (!nd->phi || iters == 0) return GS_OK;
    local_graph g = {0};
    double *tmp = gs__malloc(nd->nl, sizeof *tmp);
    int rc = tmp ? local_graph_build(nd, &g) : GS_ENOMEM;
    if (rc) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory smoothing a separator");
        goto done;
    }
    double *phi = nd->phi;
    for (uint32_t v = 0; v < nd->nl; ++v) phi[v] = nd->side[v] ? 1.0 : -1.0;
    for (uint32_t it = 0; it < iters; ++it) {
        for (uint32_t v = 0; v < nd->nl; ++v) {
            double sw = 0, sx = 0;
            for (uint32_t k = g.start[v]; k < g.start[v + 1]; ++k) {
                sw += g.w[k];
                sx += g.w[k] * phi[g.nbr[k]];
            }
            tmp[v] = sw > 0 ? 0.5 * (phi[v] + sx / sw) : phi[v];
        }
        memcpy(phi, tmp, (size_t)nd->nl * sizeof *phi);
    }
    rc = gs__part_cut_median(nd);
    if (rc) rc = gs__fail(err, rc, "out of memory smoothing a separator");
done:
    local_graph_free(&g);
    free(tmp);
    return rc;
}

/* ---- the power bisector of the two sides' centres ------------------------ */

/* The owned vertex of side s nearest (in space) to the centroid of the
 * owned vertices of side s; GS_NONE if the side is empty. */
static uint32_t side_centre(const gs__part_node *nd, uint8_t s)
{
    double c[3] = {0, 0, 0};
    uint32_t n = 0, best = GS_NONE;
    for (uint32_t v = 0; v < nd->no; ++v) {
        if (nd->side[v] != s) continue;
        const double *p = nd->mesh->xyz + 3 * (size_t)nd->lv[v];
        c[0] += p[0], c[1] += p[1], c[2] += p[2];
        n++;
    }
    if (!n) return GS_NONE;
    c[0] /= n, c[1] /= n, c[2] /= n;
    double bd = INFINITY;
    for (uint32_t v = 0; v < nd->no; ++v) {
        if (nd->side[v] != s) continue;
        const double *p = nd->mesh->xyz + 3 * (size_t)nd->lv[v];
        double d = (p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2]);
        if (d < bd) bd = d, best = v;
    }
    return best;
}

/* Patches with more vertices take the bisector's two fields from fast
 * marching (with its exact start) instead of window propagation: an exact
 * field over a 1M-vertex root costs tens of seconds, and the cut only needs
 * a smooth level set there (flat regions straight to the march's ~1%). */
#define BISECTOR_EXACT_MAX 100000u

int gs__part_bisector(gs__part_node *nd, uint32_t iters, gs_error *err)
{
    if (!nd->phi || iters == 0 || nd->no < 4) return GS_OK;
    gs_patch *p = NULL;
    gs_solver *sv = NULL;
    uint32_t np = 0;
    double *d[2] = {NULL, NULL};
    int rc = gs_patch_create(nd->mesh, nd->faces, nd->nf, &p, err);
    if (rc == GS_OK)
        rc = gs_solver_create(p, gs_patch_num_vertices(p) > BISECTOR_EXACT_MAX ? GS_METHOD_FMM : GS_METHOD_EXACT, &sv,
                              err);
    if (rc) goto done;
    np = gs_patch_num_vertices(p);
    d[0] = gs__malloc(np, sizeof *d[0]);
    d[1] = gs__malloc(np, sizeof *d[1]);
    if (!d[0] || !d[1]) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory smoothing a separator");
        goto done;
    }
    for (uint32_t it = 0; it < iters; ++it) {
        int ok = 1;
        for (uint8_t s = 0; s < 2 && ok; ++s) {
            uint32_t c = side_centre(nd, s);
            if (c == GS_NONE) { ok = 0; break; }
            gs_source src = gs_source_vertex(gs_patch_vertex_from_mesh(p, nd->lv[c]));
            if ((rc = gs_solver_solve(sv, &src, 1, 0, d[s], err)) != GS_OK) goto done;
        }
        if (!ok) break;
        uint32_t bad = 0;
        for (uint32_t v = 0; v < nd->nl; ++v) {
            uint32_t q = gs_patch_vertex_from_mesh(p, nd->lv[v]);
            bad += !(isfinite(d[0][q]) && isfinite(d[1][q]));
        }
        if (bad) break; /* another component: keep the sides */
        for (uint32_t v = 0; v < nd->nl; ++v) {
            uint32_t q = gs_patch_vertex_from_mesh(p, nd->lv[v]);
            nd->phi[v] = d[0][q] * d[0][q] - d[1][q] * d[1][q];
        }
        nd->phi_valid = 0;
        if ((rc = gs__part_cut_median(nd)) != GS_OK) {
            rc = gs__fail(err, rc, "out of memory smoothing a separator");
            goto done;
        }
        if (!nd->phi_valid) break;
    }
done:
    gs_solver_free(sv);
    gs_patch_free(p);
    free(d[0]);
    free(d[1]);
    return rc;
}
