/* graph.c - the trivial baseline: Dijkstra on the edge graph of a patch.
 * Distances are lengths of shortest edge paths: exact only where a shortest
 * path runs along edges, otherwise an upper bound. */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>

typedef struct graph_state {
    const gs_topo *t;
    gs_iheap heap;
} graph_state;

static int graph_create(const gs_topo *t, void **state, gs_error *err)
{
    graph_state *g = calloc(1, sizeof *g);
    if (!g || gs_iheap_init(&g->heap, t->nv)) {
        if (g) gs_iheap_free(&g->heap);
        free(g);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a graph solver");
    }
    g->t = t;
    *state = g;
    return GS_OK;
}

static void graph_destroy(void *state)
{
    graph_state *g = state;
    gs_iheap_free(&g->heap);
    free(g);
}

static void relax(graph_state *g, double *dist, uint32_t v, double d, double max_d)
{
    if (d < dist[v] && d <= max_d) {
        dist[v] = d;
        gs_iheap_push_or_decrease(&g->heap, v, d);
    }
}

static int graph_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                       double *dist, gs_solve_stats *stats, gs_error *err)
{
    (void)err;
    graph_state *g = state;
    const gs_topo *t = g->t;
    for (uint32_t v = 0; v < t->nv; ++v) dist[v] = INFINITY;
    gs_iheap_clear(&g->heap);
    for (uint32_t i = 0; i < n_src; ++i) {
        if (src[i].face == GS_NONE) {
            relax(g, dist, src[i].vertex, 0.0, max_d);
            continue;
        }
        double p[3];
        gs_source_position(t, &src[i], p);
        for (int k = 0; k < 3; ++k) {
            uint32_t v = t->tri[3 * (size_t)src[i].face + k];
            const double *q = t->xyz + 3 * (size_t)v;
            double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
            relax(g, dist, v, sqrt(dx * dx + dy * dy + dz * dz), max_d);
        }
    }
    while (g->heap.n) {
        double d;
        uint32_t v = gs_iheap_pop(&g->heap, &d);
        stats->windows_propagated++;
        /* neighbours: the far end of every outgoing half-edge, and the tail
         * of every incoming boundary half-edge (reached via prev corner) */
        for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
            uint32_t h = t->vc[k];
            relax(g, dist, t->tri[gs_next(h)], d + t->len[h], max_d);
            uint32_t hp = gs_prev(h); /* runs from tri[hp] to v */
            relax(g, dist, t->tri[hp], d + t->len[hp], max_d);
        }
    }
    return GS_OK;
}

const gs_method_ops gs_graph_ops = {"graph", graph_create, graph_destroy, graph_solve};
