/* graph.c - the trivial baseline: Dijkstra on the edge graph of a patch.
 * Distances are lengths of shortest edge paths: exact only where a shortest
 * path runs along edges, otherwise an upper bound. */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>

typedef struct graph_state {
    const gs__topo *t;
    gs__iheap heap;
} graph_state;

static int graph_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    (void)opt;
    graph_state *g = calloc(1, sizeof *g);
    if (!g || gs__iheap_init(&g->heap, t->nv)) {
        if (g) gs__iheap_free(&g->heap);
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
    gs__iheap_free(&g->heap);
    free(g);
}

static void relax(graph_state *g, double *dist, uint32_t v, double d, double max_d)
{
    if (d < dist[v] && d <= max_d) {
        dist[v] = d;
        gs__iheap_push_or_decrease(&g->heap, v, d);
    }
}

static int graph_solve(void *state, const gs_source *src, uint32_t n_src, double max_d,
                       double *dist, gs__solve_stats *stats, gs_error *err)
{
    (void)err;
    graph_state *g = state;
    const gs__topo *t = g->t;
    for (uint32_t v = 0; v < t->nv; ++v) dist[v] = INFINITY;
    gs__iheap_clear(&g->heap);
    for (uint32_t i = 0; i < n_src; ++i) {
        uint32_t sv[3];
        double sd[3];
        uint32_t ns = gs__source_seeds(t, &src[i], sv, sd);
        for (uint32_t k = 0; k < ns; ++k) relax(g, dist, sv[k], sd[k], max_d);
    }
    while (g->heap.n) {
        double d;
        uint32_t v = gs__iheap_pop(&g->heap, &d);
        stats->windows_propagated++;
        /* neighbours: the far end of every outgoing half-edge, and the tail
         * of every incoming boundary half-edge (reached via prev corner) */
        for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
            uint32_t h = t->vc[k];
            relax(g, dist, t->tri[gs__next(h)], d + t->len[h], max_d);
            uint32_t hp = gs__prev(h); /* runs from tri[hp] to v */
            relax(g, dist, t->tri[hp], d + t->len[hp], max_d);
        }
    }
    return GS_OK;
}

const gs__method_ops gs__graph_ops = {"graph", graph_create, graph_destroy, graph_solve, NULL, NULL};
