/* split.c - the graph cut of one node of the nested bisection (paper sec.
 * 4.1): the vertices owned by a patch are bisected by their connected
 * components or by METIS; ghost vertices then join a side by majority. */
#include "partition_internal.h"

#include <metis.h>
#include <stdlib.h>
#include <string.h>

/* The graph induced by the owned vertices, in CSR form (METIS layout). */
typedef struct owned_graph {
    idx_t n;
    idx_t *xadj, *adj;
} owned_graph;

static void graph_free(owned_graph *g)
{
    free(g->xadj);
    free(g->adj);
}

/* Every undirected edge between two owned vertices once in each direction.
 * All faces at an owned vertex are in P(N), so h < opp(h) picks each mesh
 * edge exactly once. */
static int graph_build(const gs_part_node *nd, owned_graph *g)
{
    const gs_topo *t = &nd->mesh->topo;
    g->n = (idx_t)nd->no;
    g->xadj = calloc((size_t)nd->no + 1, sizeof *g->xadj);
    g->adj = NULL;
    if (!g->xadj) return GS_ENOMEM;
    for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t lf = 0; lf < nd->nf; ++lf)
            for (uint32_t k = 0; k < 3; ++k) {
                uint32_t h = 3 * nd->faces[lf] + k;
                if (t->opp[h] != GS_NONE && t->opp[h] < h) continue;
                uint32_t a = nd->vloc[t->tri[h]], b = nd->vloc[t->tri[gs_next(h)]];
                if (a >= nd->no || b >= nd->no) continue;
                if (pass == 0) {
                    g->xadj[a + 1]++;
                    g->xadj[b + 1]++;
                } else {
                    g->adj[g->xadj[a]++] = (idx_t)b;
                    g->adj[g->xadj[b]++] = (idx_t)a;
                }
            }
        if (pass == 0) {
            for (uint32_t v = 0; v < nd->no; ++v) g->xadj[v + 1] += g->xadj[v];
            g->adj = gs__malloc((size_t)g->xadj[nd->no] + 1, sizeof *g->adj);
            if (!g->adj) return GS_ENOMEM;
        } else { /* the fill advanced xadj[v] to the start of v + 1 */
            memmove(g->xadj + 1, g->xadj, (size_t)nd->no * sizeof *g->xadj);
            g->xadj[0] = 0;
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
static int split_by_components(gs_part_node *nd, const uint32_t *comp, uint32_t nc,
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

static int split_by_metis(gs_part_node *nd, const owned_graph *g, uint32_t seed,
                          gs_error *err)
{
    idx_t nv = g->n, ncon = 1, nparts = 2, objval = 0;
    idx_t options[METIS_NOPTIONS];
    idx_t *part = gs__malloc(nd->no, sizeof *part);
    if (!part) return gs__fail(err, GS_ENOMEM, "out of memory bisecting a patch");
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = (idx_t)(seed & 0x7fffffff);
    options[METIS_OPTION_NUMBERING] = 0;
    int r = METIS_PartGraphRecursive(&nv, &ncon, g->xadj, g->adj, NULL, NULL, NULL,
                                     &nparts, NULL, NULL, options, &objval, part);
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
static void split_by_order(gs_part_node *nd, const uint32_t *order)
{
    for (uint32_t i = 0; i < nd->no; ++i) nd->side[order[i]] = i >= nd->no / 2;
}

/* Each ghost vertex joins the side of most of its owned neighbours (every
 * face of P(N) has an owned corner, so each ghost has one). Ties: side 0. */
static int ghost_sides(gs_part_node *nd)
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

int gs__part_sides(gs_part_node *nd, uint32_t seed, gs_error *err)
{
    owned_graph g = {0};
    uint32_t *comp = gs__malloc(nd->no, sizeof *comp);
    uint32_t *order = gs__malloc(nd->no, sizeof *order);
    int rc = (comp && order) ? graph_build(nd, &g) : GS_ENOMEM;
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

static int local_graph_build(const gs_part_node *nd, local_graph *g)
{
    const uint32_t *tri = nd->mesh->tri;
    const gs_topo *t = &nd->mesh->topo;
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
            uint32_t a = nd->vloc[tri[h]], b = nd->vloc[tri[gs_next(h)]];
            double w = t->len[h] > 0 ? 1.0 / t->len[h] : 1.0;
            g->nbr[fill[a]] = b, g->w[fill[a]++] = w;
            g->nbr[fill[b]] = a, g->w[fill[b]++] = w;
        }
    free(fill);
    return GS_OK;
}

int gs__part_level_set(gs_part_node *nd, uint32_t iters, gs_error *err)
{
    if (!nd->phi || iters == 0) return GS_OK;
    local_graph g = {0};
    double *tmp = gs__malloc(nd->nl, sizeof *tmp);
    double *sorted = gs__malloc(nd->no, sizeof *sorted);
    int rc = (tmp && sorted) ? local_graph_build(nd, &g) : GS_ENOMEM;
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
    /* cut level: keep METIS's share of side-1 owned vertices */
    uint32_t n1 = 0;
    for (uint32_t v = 0; v < nd->no; ++v) {
        sorted[v] = phi[v];
        n1 += nd->side[v];
    }
    qsort(sorted, nd->no, sizeof *sorted, cmp_double);
    uint32_t k0 = nd->no - n1; /* side-0 count */
    if (k0 == 0 || k0 >= nd->no) goto done;
    double level = 0.5 * (sorted[k0 - 1] + sorted[k0]);
    if (!(sorted[k0 - 1] < level && level < sorted[k0])) goto done; /* ties: keep METIS */
    for (uint32_t v = 0; v < nd->nl; ++v) {
        phi[v] -= level;
        nd->side[v] = phi[v] > 0;
    }
    nd->phi_valid = 1;
done:
    local_graph_free(&g);
    free(tmp);
    free(sorted);
    return rc;
}
