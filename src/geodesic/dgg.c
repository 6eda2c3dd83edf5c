/* dgg.c - GS_METHOD_DGG: a discrete geodesic graph (after Wang, Fang, Wu,
 * Xin and He 2017) built once per solver from bounded runs of the exact
 * solver; each field is then a Dijkstra over the graph.
 *
 * Construction. For every vertex v of the patch, one exact window
 * propagation from v bounded to the radius R_v = max(R, longest edge at v),
 * R = gs_dgg_radius(eps) mean edge lengths. Every vertex u reached within
 * R_v whose shortest path from v is straight (it leaves v and reaches u
 * without bending at a vertex) becomes an edge v -> u weighted by the exact
 * distance. A vertex whose shortest path bends at a saddle or boundary
 * vertex w is left out: d(v,u) = d(v,w) + d(w,u) with both parts shorter,
 * so by induction on the distance the graph holds a path of exactly
 * d(v,u) for every pair within R_v (the lossless pruning; rounding aside).
 *
 * Guarantee. Every graph path is a real path on the patch, so fields are
 * upper bounds of the exact distances inside the patch (d_P: the local runs
 * are on the patch, so no edge leaves it). Pairs within R are exact. A
 * longer geodesic is followed by a chain of straight pieces between
 * vertices, each of length about R; where it crosses faces (not through
 * vertices) each hop deviates from it by at most about half an edge, which
 * costs a relative (h / R)^2 / 2 or so per hop: this is how eps sets R.
 * That bound is measured (doc/approximate-fields.md), not proven: needle
 * triangles or very uneven edge lengths widen it.
 *
 * Surface-point sources: one bounded exact run from the point seeds the
 * Dijkstra with the exact distances of the vertices it reaches straight.
 *
 * Threads: the local runs are split over OpenMP threads (one exact solver
 * each); every vertex's edge list depends only on its own run, so the graph
 * is the same for any thread count. */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

typedef struct dgg_edge {
    uint32_t to;
    double w;
} dgg_edge;

typedef struct dgg_state {
    const gs__topo *t;
    double radius;       /* R, absolute                                  */
    uint64_t *start;     /* nv + 1: CSR offsets                          */
    dgg_edge *e;         /* edges                                        */
    gs__iheap heap;
    void *ex;            /* exact solver for surface-point sources (lazy) */
    double *exd;         /* its nv scratch distances, all +INFINITY       */
    double build_seconds;
    int shared;          /* start / e belong to the state this was cloned from */
} dgg_state;

double gs_dgg_radius(double eps)
{
    if (!(eps > 0)) eps = GS_DGG_EPS_MIN;
    double r = 0.3 / sqrt(eps);
    if (r < 2) r = 2;
    if (r > 100) r = 100;
    return r;
}

static void dgg_destroy(void *state)
{
    dgg_state *g = state;
    if (!g) return;
    if (!g->shared) {
        free(g->start);
        free(g->e);
    }
    gs__iheap_free(&g->heap);
    if (g->ex) gs__exact_ops.destroy(g->ex);
    free(g->exd);
    free(g);
}

static int cmp_edge(const void *a, const void *b)
{
    const dgg_edge *x = a, *y = b;
    return (x->to > y->to) - (x->to < y->to);
}

/* The straight vertices of the last local run within r (not `self`), sorted
 * by id, into *out (malloc'd) / *n; the touched distances are reset. */
static int collect(const void *ex, uint32_t self, double r, double *dist, const uint32_t *tv, uint32_t ntv,
                   dgg_edge **out, uint32_t *n)
{
    dgg_edge *l = malloc((ntv ? ntv : 1) * sizeof *l);
    uint32_t k = 0;
    for (uint32_t i = 0; i < ntv; ++i) {
        uint32_t u = tv[i];
        double du = dist[u];
        if (l && u != self && du <= r && gs__exact_straight(ex, self, u, du)) l[k++] = (dgg_edge){u, du};
    }
    for (uint32_t i = 0; i < ntv; ++i) dist[tv[i]] = INFINITY;
    if (!l) return GS_ENOMEM;
    qsort(l, k, sizeof *l, cmp_edge);
    *out = l;
    *n = k;
    return GS_OK;
}

/* R_v: R scaled up where the edges at v are longer than the patch's mean
 * hbar (so that coarse regions get as many edges per hop), and at least
 * the longest edge at v (so that every mesh edge's ends are joined). */
static double dgg_vertex_radius(const gs__topo *t, double r, double hbar, uint32_t v)
{
    double sum = 0, mx = 0;
    uint32_t n = 0;
    for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
        uint32_t h = t->vc[k];
        double a = t->len[h], b = t->len[gs__prev(h)];
        sum += a + b, n += 2;
        if (a > mx) mx = a;
        if (b > mx) mx = b;
    }
    double loc = n ? sum / n : 0;
    if (hbar > 0 && loc > hbar) r *= loc / hbar;
    if (mx > r) r = mx;
    return r * (1 + 1e-9);
}

static int dgg_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    double t0 = gs__now();
    dgg_state *g = gs__calloc(1, sizeof *g);
    if (!g) return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg solver");
    g->t = t;
    uint32_t nv = t->nv;
    size_t nh = 3 * (size_t)t->nf;
    double sum = 0;
    for (size_t h = 0; h < nh; ++h) sum += t->len[h];
    double hbar = nh ? sum / (double)nh : 0;
    g->radius = gs_dgg_radius(opt->dgg_eps) * hbar;
    g->start = gs__calloc((size_t)nv + 1, sizeof *g->start);
    dgg_edge **lists = gs__calloc(nv ? nv : 1, sizeof *lists);
    uint32_t *cnt = gs__calloc(nv ? nv : 1, sizeof *cnt);
    if (!g->start || !lists || !cnt || gs__iheap_init(&g->heap, nv)) {
        free(lists);
        free(cnt);
        dgg_destroy(g);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg solver");
    }
    int status = GS_OK;
    uint32_t bad_v = GS_NONE;
    gs_error first = {0};
#pragma omp parallel
    {
        void *ex = NULL;
        gs_error e = {0};
        int rc = gs__exact_ops.create(t, opt, &ex, &e);
        double *dist = rc ? NULL : malloc((nv ? nv : 1) * sizeof *dist);
        if (!rc && !dist) rc = gs__fail(&e, GS_ENOMEM, "out of memory creating a dgg solver");
        if (rc) {
#pragma omp critical(gs__dgg_err)
            {
                status = rc;
                first = e;
                bad_v = 0;
            }
        }
        if (dist)
            for (uint32_t v = 0; v < nv; ++v) dist[v] = INFINITY;
#pragma omp for schedule(dynamic, 64)
        for (int64_t iv = 0; iv < (int64_t)nv; ++iv) {
            uint32_t v = (uint32_t)iv;
            if (rc || t->vc_start[v] == t->vc_start[v + 1]) continue;
            double rv = dgg_vertex_radius(t, g->radius, hbar, v);
            gs_source s = gs_source_vertex(v);
            const uint32_t *tv;
            uint32_t ntv;
            rc = gs__exact_solve_local(ex, &s, rv, dist, &tv, &ntv, &e);
            if (!rc && collect(ex, v, rv, dist, tv, ntv, &lists[v], &cnt[v]))
                rc = gs__fail(&e, GS_ENOMEM, "out of memory building the dgg graph");
            if (rc) {
#pragma omp critical(gs__dgg_err)
                if (bad_v == GS_NONE || v < bad_v) {
                    bad_v = v;
                    status = rc;
                    first = e;
                }
            }
        }
        free(dist);
        if (ex) gs__exact_ops.destroy(ex);
    }
    if (status == GS_OK) {
        for (uint32_t v = 0; v < nv; ++v) g->start[v + 1] = g->start[v] + cnt[v];
        g->e = gs__malloc(g->start[nv] ? g->start[nv] : 1, sizeof *g->e);
        if (!g->e) status = gs__fail(&first, GS_ENOMEM, "out of memory storing the dgg graph (%llu edges)",
                                     (unsigned long long)g->start[nv]);
        else
            for (uint32_t v = 0; v < nv; ++v)
                if (cnt[v]) memcpy(g->e + g->start[v], lists[v], cnt[v] * sizeof *g->e);
    }
    for (uint32_t v = 0; v < nv; ++v) free(lists[v]);
    free(lists);
    free(cnt);
    if (status) {
        dgg_destroy(g);
        if (err) *err = first;
        return status;
    }
    g->build_seconds = gs__now() - t0;
    *state = g;
    return GS_OK;
}

static void relax(dgg_state *g, double *dist, uint32_t v, double d, double max_d)
{
    if (d < dist[v] && d <= max_d) {
        dist[v] = d;
        gs__iheap_push_or_decrease(&g->heap, v, d);
    }
}

static int dgg_solve(void *state, const gs_source *src, uint32_t n_src, double max_d, double *dist,
                     gs__solve_stats *stats, gs_error *err)
{
    dgg_state *g = state;
    const gs__topo *t = g->t;
    for (uint32_t v = 0; v < t->nv; ++v) dist[v] = INFINITY;
    gs__iheap_clear(&g->heap);
    for (uint32_t i = 0; i < n_src; ++i) {
        if (src[i].face == GS_NONE) {
            relax(g, dist, src[i].vertex, 0, max_d);
            continue;
        }
        /* a surface point: exact distances of what it reaches straight */
        if (!g->ex) {
            gs_solver_options o;
            gs_solver_options_default(&o);
            int rc = gs__exact_ops.create(t, &o, &g->ex, err);
            if (rc) return rc;
            g->exd = gs__malloc(t->nv ? t->nv : 1, sizeof *g->exd);
            if (!g->exd) return gs__fail(err, GS_ENOMEM, "out of memory in the dgg solver");
            for (uint32_t v = 0; v < t->nv; ++v) g->exd[v] = INFINITY;
        }
        double r = g->radius;
        for (int k = 0; k < 3; ++k)
            if (t->len[3 * (size_t)src[i].face + k] > r) r = t->len[3 * (size_t)src[i].face + k];
        r *= 1 + 1e-9;
        const uint32_t *tv;
        uint32_t ntv;
        int rc = gs__exact_solve_local(g->ex, &src[i], r, g->exd, &tv, &ntv, err);
        if (rc) {
            for (uint32_t k = 0; k < t->nv; ++k) g->exd[k] = INFINITY;
            return rc;
        }
        for (uint32_t k = 0; k < ntv; ++k) {
            uint32_t u = tv[k];
            double du = g->exd[u];
            if (du <= r && gs__exact_straight(g->ex, GS_NONE, u, du)) relax(g, dist, u, du, max_d);
            g->exd[u] = INFINITY;
        }
    }
    uint64_t pops = 0;
    while (g->heap.n) {
        double d;
        uint32_t v = gs__iheap_pop(&g->heap, &d);
        ++pops;
        for (uint64_t k = g->start[v]; k < g->start[v + 1]; ++k) relax(g, dist, g->e[k].to, d + g->e[k].w, max_d);
    }
    stats->windows_propagated = pops;
    return GS_OK;
}

void gs__dgg_info(const void *state, double *seconds, uint64_t *edges, uint64_t *bytes)
{
    const dgg_state *g = state;
    if (seconds) *seconds = g->build_seconds;
    if (edges) *edges = g->start[g->t->nv];
    if (bytes)
        *bytes = g->start[g->t->nv] * sizeof *g->e + ((uint64_t)g->t->nv + 1) * sizeof *g->start +
                 (uint64_t)g->t->nv * (2 * sizeof(uint32_t) + sizeof(double));
}

/* Another thread's solver: the graph is shared read-only (src outlives it). */
static int dgg_clone(const void *state, void **out, gs_error *err)
{
    const dgg_state *src = state;
    dgg_state *g = gs__calloc(1, sizeof *g);
    if (!g || gs__iheap_init(&g->heap, src->t->nv)) {
        if (g) gs__iheap_free(&g->heap);
        free(g);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg solver");
    }
    g->t = src->t;
    g->radius = src->radius;
    g->start = src->start;
    g->e = src->e;
    g->build_seconds = src->build_seconds;
    g->shared = 1;
    *out = g;
    return GS_OK;
}

const gs__method_ops gs__dgg_ops = {"dgg", dgg_create, dgg_destroy, dgg_solve, NULL, dgg_clone};
