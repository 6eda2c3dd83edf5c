/* dgg.c - GS_METHOD_DGG: a discrete geodesic graph (after Wang, Fang, Wu,
 * Xin and He 2017, pruned as in Adikusuma, Fang and He 2020) built once
 * from bounded runs of the exact solver; each field is then a Dijkstra
 * over the graph.
 *
 * Candidates. For every vertex v, one exact window propagation from v
 * bounded to the radius R_v = max(R, longest edge at v), R =
 * gs_dgg_radius(eps) mean edge lengths (scaled up where v's edges are
 * longer than the mean), with the rays straight from v only (no windows
 * from saddle or boundary vertices: gs__exact_solve_local_ex, direct_only;
 * 1.6 times faster). Every vertex u it reaches within R_v by a straight
 * path becomes a candidate edge v -> u of that path's length: exact when
 * the shortest path from v to u is straight; otherwise the length of a
 * longer straight path, a real path all the same. A pair whose shortest
 * path bends at a vertex w has d(v,u) = d(v,w) + d(w,u) with both parts
 * shorter, so by induction on the distance the candidate graph C holds a
 * path of exactly d(v,u) for every pair within R_v (lossless; rounding
 * aside).
 *
 * Pruning (eps). Each vertex v then keeps a subset K_v of its candidates,
 * taken in order of increasing length: u is dropped when some x already
 * kept gives d(v,x) + (1 + eps) c(x,u) <= (1 + eps) d(v,u), c(x,u) the
 * candidate x -> u; mesh edges are always kept. By induction on d(v,u)
 * (c(x,u) < d(v,u)) the pruned graph G then joins every candidate pair by
 * a path of at most (1 + eps) times its length, and so every pair of
 * vertices by at most (1 + eps) times its distance in C: G(a,b) <= (1 + eps)
 * C(a,b). Each vertex's choice reads only candidate lists, so the graph does
 * not depend on the thread count or the order of the vertices.
 *
 * Guarantee. Every graph path is a real path on the surface, so fields are
 * upper bounds of the exact distances. Pairs within R are within (1 + eps)
 * of exact (C is exact there). A longer geodesic is followed in C by a
 * chain of straight pieces between vertices, each about R long; where it
 * crosses faces (not through vertices) each piece deviates from it by up
 * to about half an edge, which costs a relative (h / R)^2 / 2 or so per
 * piece: this part is measured (doc/approximate-fields.md), not proven.
 *
 * Patches. A solver created on a patch builds the patch's own graph (its
 * local runs stay in the patch: fields are upper bounds of d_P). A view
 * (gs__dgg_view) runs the Dijkstra of a larger patch's graph restricted to
 * a sub-patch's vertices: the database builder makes one graph for the
 * whole mesh and a view per tree node; an edge between two vertices of the
 * node may then follow a geodesic that leaves the node's patch, so a
 * view's fields lie between d_M and (about) d_P, never below d_M.
 *
 * Surface-point sources: one bounded exact run from the point (on the
 * solver's patch) seeds the Dijkstra with the exact distances of the
 * vertices it reaches straight. */
#include "../core/heap.h"
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* Fields are exact within this many R of each source (dgg_solve): one
 * bounded exact run per source; the largest relative errors of graph paths
 * are within a few hops of the source and go with it (6 R is about 28 mean
 * edge lengths at the default eps). */
#define DGG_START 6.0

#ifndef DGG_DIRECT
#define DGG_DIRECT 1
#endif

/* The pruned graph of a patch, on internal ids 0..nv-1 numbered in
 * breadth-first order (bfs_order: neighbours get near ids, so that the
 * Dijkstra's accesses stay in the cache); perm and inv translate to and
 * from the patch's vertex ids. A view's graph is the same for a sub-patch. */
typedef struct dgg_graph {
    uint32_t nv;
    uint64_t *start; /* nv + 1: CSR offsets (internal ids) */
    uint32_t *to;    /* kept edges: target (internal id)    */
    double *w;       /*             length                  */
    uint32_t *perm;  /* nv: internal -> patch vertex        */
    uint32_t *inv;   /* nv: patch vertex -> internal        */
    uint64_t n_cand; /* candidate edges                     */
    double radius;   /* R, absolute                          */
    double eps;
    double seconds;  /* construction, wall                  */
} dgg_graph;

typedef struct dgg_state {
    const gs__topo *t;     /* the solver's patch (local ids)                  */
    const dgg_graph *g;    /* the graph of this patch (its own or a view's)   */
    dgg_graph *own;        /* g, when this state owns it                      */
    int view;              /* g is a sub-graph of a larger patch's graph      */
    double start;          /* exact start radius of vertex sources, in R:   */
                           /*   <= 1: none (the graph is exact within R)    */
    gs__iheap heap;        /* over internal ids                               */
    double *id;            /* nv: distances by internal id (scratch)          */
    void *ex;              /* exact solver for surface-point sources (lazy)   */
    double *exd;           /* its nv scratch distances, all +INFINITY         */
} dgg_state;

double gs_dgg_radius(double eps)
{
    if (!(eps > 0)) eps = GS_DGG_EPS_MIN;
    double r = 0.15 / sqrt(eps);
    if (r < 2) r = 2;
    if (r > 100) r = 100;
    return r;
}

static void graph_free(dgg_graph *g)
{
    if (!g) return;
    free(g->start);
    free(g->to);
    free(g->w);
    free(g->perm);
    free(g->inv);
    free(g);
}

static void dgg_destroy(void *state)
{
    dgg_state *s = state;
    if (!s) return;
    graph_free(s->own);
    gs__iheap_free(&s->heap);
    free(s->id);
    if (s->ex) gs__exact_ops.destroy(s->ex);
    free(s->exd);
    free(s);
}

typedef struct cand {
    uint32_t to;
    double w;
} cand;

static int cmp_w(const void *a, const void *b)
{
    const cand *x = a, *y = b;
    if (x->w != y->w) return x->w < y->w ? -1 : 1;
    return (x->to > y->to) - (x->to < y->to);
}

/* The straight vertices of the last local run within r (not `self`), sorted
 * by length, into *out (malloc'd) / *n; the touched distances are reset. */
static int collect(const void *ex, uint32_t self, double r, double *dist, const uint32_t *tv, uint32_t ntv,
                   cand **out, uint32_t *n)
{
    cand *l = malloc((ntv ? ntv : 1) * sizeof *l);
    uint32_t k = 0;
    for (uint32_t i = 0; i < ntv; ++i) {
        uint32_t u = tv[i];
        double du = dist[u];
        if (l && u != self && du <= r && gs__exact_straight(ex, self, u, du)) l[k++] = (cand){u, du};
    }
    for (uint32_t i = 0; i < ntv; ++i) dist[tv[i]] = INFINITY;
    if (!l) return GS_ENOMEM;
    qsort(l, k, sizeof *l, cmp_w);
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

/* Keep K_v (header comment) from v's candidates lists[v] (sorted by
 * length, all within rv): into *out (malloc'd) / *nk. best: nv doubles, all
 * +INFINITY (restored); nbr: nv bytes, all 0 (restored); touched: nv. */
static int prune_vertex(const gs__topo *t, uint32_t v, double rv, double eps, cand *const *lists,
                        const uint32_t *cnt, double *best, uint8_t *nbr, uint32_t *touched, cand **out,
                        uint32_t *nk)
{
    const cand *c = lists[v];
    uint32_t n = cnt[v];
    cand *kept = malloc((n ? n : 1) * sizeof *kept);
    if (!kept) return GS_ENOMEM;
    for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
        uint32_t h = t->vc[k];
        nbr[t->tri[gs__next(h)]] = 1;
        nbr[t->tri[gs__prev(h)]] = 1;
    }
    uint32_t k = 0, ntouched = 0;
    const double f = 1 + eps, lim = f * rv;
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t u = c[i].to;
        double du = c[i].w;
        if (!nbr[u] && best[u] <= f * du) continue; /* covered through a kept vertex */
        kept[k++] = c[i];
        /* what u offers v's farther candidates (lists[u] by length; only
         * values <= (1 + eps) rv can cover one) */
        const cand *cu = lists[u];
        for (uint32_t j = 0; j < cnt[u]; ++j) {
            double val = du + f * cu[j].w;
            if (val > lim) break;
            uint32_t y = cu[j].to;
            if (val < best[y]) {
                if (best[y] == INFINITY) touched[ntouched++] = y;
                best[y] = val;
            }
        }
    }
    for (uint32_t i = 0; i < ntouched; ++i) best[touched[i]] = INFINITY;
    for (uint32_t kk = t->vc_start[v]; kk < t->vc_start[v + 1]; ++kk) {
        uint32_t h = t->vc[kk];
        nbr[t->tri[gs__next(h)]] = 0;
        nbr[t->tri[gs__prev(h)]] = 0;
    }
    cand *sh = realloc(kept, (k ? k : 1) * sizeof *sh);
    *out = sh ? sh : kept;
    *nk = k;
    return GS_OK;
}

/* The vertices in breadth-first order over the mesh edges (each component
 * from its lowest vertex): consecutive local runs then cover overlapping
 * balls and find their half-edge data in the cache (in the meshes' own
 * order most of a run's time was cache misses). Into order (nv). */
static void bfs_order(const gs__topo *t, uint32_t *order, uint8_t *seen)
{
    uint32_t nv = t->nv, head = 0, tail = 0;
    for (uint32_t r = 0; r < nv; ++r) {
        if (seen[r]) continue;
        seen[r] = 1;
        order[tail++] = r;
        while (head < tail) {
            uint32_t v = order[head++];
            for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) {
                uint32_t h = t->vc[k];
                uint32_t a = t->tri[gs__next(h)], b = t->tri[gs__prev(h)];
                if (!seen[a]) seen[a] = 1, order[tail++] = a;
                if (!seen[b]) seen[b] = 1, order[tail++] = b;
            }
        }
    }
}

/* Progress: phase 1 (local runs) is 90% of the work, phase 2 (pruning) 10%. */
static void report(const gs__dgg_progress *p, double frac)
{
    if (p && p->fn) p->fn(p->user, frac);
}

int gs__dgg_build(const gs__topo *t, double eps, int prune, uint32_t nthreads, const gs__dgg_progress *progress,
                  void **graph_out, gs_error *err)
{
    double t0 = gs__now();
    *graph_out = NULL;
    dgg_graph *g = gs__calloc(1, sizeof *g);
    if (!g) return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg graph");
    uint32_t nv = t->nv;
    size_t nh = 3 * (size_t)t->nf;
    double sum = 0;
    for (size_t h = 0; h < nh; ++h) sum += t->len[h];
    double hbar = nh ? sum / (double)nh : 0;
    g->nv = nv;
    g->eps = eps;
    g->radius = gs_dgg_radius(eps) * hbar;
    g->start = gs__calloc((size_t)nv + 1, sizeof *g->start);
    cand **lists = gs__calloc(nv ? nv : 1, sizeof *lists);
    uint32_t *cnt = gs__calloc(nv ? nv : 1, sizeof *cnt);
    cand **kept = gs__calloc(nv ? nv : 1, sizeof *kept);
    uint32_t *kcnt = gs__calloc(nv ? nv : 1, sizeof *kcnt);
    uint32_t *order = gs__malloc(nv ? nv : 1, sizeof *order);
    uint8_t *seen = gs__calloc(nv ? nv : 1, 1);
    if (!g->start || !lists || !cnt || !kept || !kcnt || !order || !seen) {
        free(lists), free(cnt), free(kept), free(kcnt), free(order), free(seen);
        graph_free(g);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg graph");
    }
    bfs_order(t, order, seen);
    free(seen);
    int status = GS_OK;
    uint32_t bad_v = GS_NONE;
    gs_error first = {0};
    uint64_t done = 0;
    int nthr = nthreads ? (int)nthreads : 0;
#ifdef _OPENMP
    if (!nthr) nthr = omp_get_max_threads();
#else
    nthr = 1;
#endif
    report(progress, 0);
#pragma omp parallel num_threads(nthr)
    {
        void *ex = NULL;
        gs_error e = {0};
        gs_solver_options eo;
        gs_solver_options_default(&eo);
        int rc = gs__exact_ops.create(t, &eo, &ex, &e);
        double *dist = rc ? NULL : malloc((nv ? nv : 1) * sizeof *dist);
        uint8_t *nbr = rc ? NULL : calloc(nv ? nv : 1, 1);
        uint32_t *touched = rc ? NULL : malloc((nv ? nv : 1) * sizeof *touched);
        if (!rc && (!dist || !nbr || !touched)) rc = gs__fail(&e, GS_ENOMEM, "out of memory creating a dgg graph");
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
        int tid = 0;
#ifdef _OPENMP
        tid = omp_get_thread_num();
#endif
        /* phase 1: candidates */
#pragma omp for schedule(dynamic, 64)
        for (int64_t iv = 0; iv < (int64_t)nv; ++iv) {
            uint32_t v = order[iv];
            if (!rc && t->vc_start[v] < t->vc_start[v + 1]) {
                double rv = dgg_vertex_radius(t, g->radius, hbar, v);
                gs_source s = gs_source_vertex(v);
                const uint32_t *tv;
                uint32_t ntv;
                rc = gs__exact_solve_local_ex(ex, &s, rv, DGG_DIRECT, dist, &tv, &ntv, &e);
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
            if ((iv & 63) == 63) {
                uint64_t d;
#pragma omp atomic capture
                d = done += 64;
                if (tid == 0) report(progress, 0.9 * (double)d / (nv ? nv : 1));
            }
        }
        if (ex) gs__exact_ops.destroy(ex);
        ex = NULL;
        free(dist);
        dist = NULL;
        /* phase 2: pruning (reads every candidate list; the barrier of the
         * loop above makes them complete) */
        double *best = NULL;
        if (!rc && prune) {
            best = malloc((nv ? nv : 1) * sizeof *best);
            if (!best) rc = gs__fail(&e, GS_ENOMEM, "out of memory pruning the dgg graph");
            else
                for (uint32_t v = 0; v < nv; ++v) best[v] = INFINITY;
            if (rc) {
#pragma omp critical(gs__dgg_err)
                {
                    status = rc;
                    first = e;
                    bad_v = 0;
                }
            }
        }
#pragma omp for schedule(dynamic, 64)
        for (int64_t iv = 0; iv < (int64_t)nv; ++iv) {
            uint32_t v = order[iv];
            if (rc || !prune) continue;
            double rv = dgg_vertex_radius(t, g->radius, hbar, v);
            if (prune_vertex(t, v, rv, eps, lists, cnt, best, nbr, touched, &kept[v], &kcnt[v])) {
                rc = gs__fail(&e, GS_ENOMEM, "out of memory pruning the dgg graph");
#pragma omp critical(gs__dgg_err)
                {
                    status = rc;
                    first = e;
                    bad_v = 0;
                }
            }
            if (tid == 0 && (iv & 1023) == 0) report(progress, 0.9 + 0.1 * (double)iv / (nv ? nv : 1));
        }
        free(best);
        free(nbr);
        free(touched);
    }
    cand **fin = prune ? kept : lists;
    uint32_t *fcnt = prune ? kcnt : cnt;
    if (status == GS_OK) {
        /* internal id i is vertex order[i] */
        g->perm = order;
        order = NULL;
        g->inv = gs__malloc(nv ? nv : 1, sizeof *g->inv);
        if (!g->inv) status = gs__fail(&first, GS_ENOMEM, "out of memory storing the dgg graph");
    }
    if (status == GS_OK) {
        for (uint32_t i = 0; i < nv; ++i) {
            uint32_t v = g->perm[i];
            g->inv[v] = i;
            g->start[i + 1] = g->start[i] + fcnt[v];
            g->n_cand += cnt[v];
        }
        uint64_t ne = g->start[nv];
        g->to = gs__malloc(ne ? ne : 1, sizeof *g->to);
        g->w = gs__malloc(ne ? ne : 1, sizeof *g->w);
        if (!g->to || !g->w)
            status = gs__fail(&first, GS_ENOMEM, "out of memory storing the dgg graph (%llu edges)",
                              (unsigned long long)ne);
        else
            for (uint32_t i = 0; i < nv; ++i) {
                uint32_t v = g->perm[i];
                for (uint32_t k = 0; k < fcnt[v]; ++k) {
                    g->to[g->start[i] + k] = g->inv[fin[v][k].to];
                    g->w[g->start[i] + k] = fin[v][k].w;
                }
            }
    }
    for (uint32_t v = 0; v < nv; ++v) free(lists[v]), free(kept[v]);
    free(lists), free(cnt), free(kept), free(kcnt), free(order);
    if (status) {
        graph_free(g);
        if (err) *err = first;
        return status;
    }
    g->seconds = gs__now() - t0;
    report(progress, 1);
    *graph_out = g;
    return GS_OK;
}

void gs__dgg_free(void *graph)
{
    graph_free(graph);
}

static int state_new(const gs__topo *t, dgg_state **out, gs_error *err)
{
    dgg_state *s = gs__calloc(1, sizeof *s);
    if (!s || gs__iheap_init(&s->heap, t->nv) || !(s->id = gs__malloc(t->nv ? t->nv : 1, sizeof *s->id))) {
        if (s) gs__iheap_free(&s->heap), free(s->id);
        free(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg solver");
    }
    s->t = t;
    s->start = DGG_START;
    *out = s;
    return GS_OK;
}

int gs__dgg_state_from_graph(const gs__topo *t, void *graph, void **state, gs_error *err)
{
    dgg_state *s;
    int rc = state_new(t, &s, err);
    if (rc) {
        graph_free(graph);
        return rc;
    }
    s->g = s->own = graph;
    *state = s;
    return GS_OK;
}

static int dgg_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    void *g;
    int rc = gs__dgg_build(t, opt->dgg_eps, 1, 0, NULL, &g, err);
    if (rc) return rc;
    return gs__dgg_state_from_graph(t, g, state, err);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The sub-graph of g on the vertices of patch t (t's vertex v is g's patch
 * vertex vmap[v], NULL: the same), its internal order g's restricted to
 * them; edges leaving t are dropped. Built once per view: its fields are
 * then Dijkstras on a graph of the patch's own size. */
static int sub_graph(const dgg_graph *g, const gs__topo *t, const uint32_t *vmap, dgg_graph **out, gs_error *err)
{
    uint32_t n = t->nv;
    dgg_graph *h = gs__calloc(1, sizeof *h);
    uint64_t *key = gs__malloc(n ? n : 1, sizeof *key);
    if (!h || !key) goto oom;
    h->nv = n;
    h->radius = g->radius;
    h->eps = g->eps;
    h->n_cand = 0;
    for (uint32_t v = 0; v < n; ++v) {
        uint32_t m = vmap ? vmap[v] : v;
        if (m >= g->nv) {
            free(key), graph_free(h);
            return gs__fail(err, GS_EINTERNAL, "gs__dgg_view: patch vertex %u is not in the graph", v);
        }
        key[v] = (uint64_t)g->inv[m] << 32 | v; /* g's internal id, then v */
    }
    qsort(key, n, sizeof *key, cmp_u64);
    h->perm = gs__malloc(n ? n : 1, sizeof *h->perm);
    h->inv = gs__malloc(n ? n : 1, sizeof *h->inv);
    h->start = gs__calloc((size_t)n + 1, sizeof *h->start);
    if (!h->perm || !h->inv || !h->start) goto oom;
    for (uint32_t j = 0; j < n; ++j) {
        h->perm[j] = (uint32_t)key[j];
        h->inv[h->perm[j]] = j;
    }
    /* g's internal id -> the view's: a direct map for patches that are not
     * tiny next to g, a binary search in key (increasing) otherwise */
    uint32_t *map = NULL;
    if ((uint64_t)n * 64 >= g->nv) {
        map = gs__malloc(g->nv ? g->nv : 1, sizeof *map);
        if (!map) goto oom;
        memset(map, 0xff, (size_t)g->nv * sizeof *map);
        for (uint32_t j = 0; j < n; ++j) map[key[j] >> 32] = j;
    }
    for (int pass = 0; pass < 2; ++pass) {
        uint64_t ne = 0;
        for (uint32_t j = 0; j < n; ++j) {
            uint32_t gi = (uint32_t)(key[j] >> 32);
            for (uint64_t k = g->start[gi]; k < g->start[gi + 1]; ++k) {
                uint32_t gt = g->to[k], lj;
                if (map) {
                    lj = map[gt];
                } else {
                    uint32_t lo = 0, hi = n;
                    while (lo < hi) {
                        uint32_t mid = lo + (hi - lo) / 2;
                        if ((key[mid] >> 32) < gt) lo = mid + 1;
                        else hi = mid;
                    }
                    lj = lo < n && (key[lo] >> 32) == gt ? lo : GS_NONE;
                }
                if (lj == GS_NONE) continue;
                if (pass) h->to[ne] = lj, h->w[ne] = g->w[k];
                ++ne;
            }
            if (!pass) h->start[j + 1] = ne;
        }
        if (!pass) {
            h->to = gs__malloc(ne ? ne : 1, sizeof *h->to);
            h->w = gs__malloc(ne ? ne : 1, sizeof *h->w);
            if (!h->to || !h->w) {
                free(map);
                goto oom;
            }
        }
    }
    free(map);
    free(key);
    *out = h;
    return GS_OK;
oom:
    free(key);
    graph_free(h);
    return gs__fail(err, GS_ENOMEM, "out of memory creating a dgg view");
}

int gs__dgg_view(const void *whole, const gs__topo *t, const uint32_t *vmap, void **state, gs_error *err)
{
    const dgg_state *w = whole;
    if (w->view) return gs__fail(err, GS_EINTERNAL, "gs__dgg_view: the graph's solver is itself a view");
    dgg_state *s;
    int rc = state_new(t, &s, err);
    if (rc) return rc;
    if (!vmap && t->nv == w->g->nv) {
        s->g = w->g; /* the whole patch again (a tree's root): shared */
    } else {
        rc = sub_graph(w->g, t, vmap, &s->own, err);
        if (rc) {
            dgg_destroy(s);
            return rc;
        }
        s->g = s->own;
    }
    s->view = 1;
    s->start = 0; /* builds: many fields per patch; the graph alone */
    *state = s;
    return GS_OK;
}

static inline void relax(dgg_state *s, double *id, uint32_t i, double d, double max_d)
{
    if (d < id[i] && d <= max_d) {
        id[i] = d;
        gs__iheap_push_or_decrease(&s->heap, i, d);
    }
}

static int dgg_solve(void *state, const gs_source *src, uint32_t n_src, double max_d, double *dist,
                     gs__solve_stats *stats, gs_error *err)
{
    dgg_state *s = state;
    const gs__topo *t = s->t;
    const dgg_graph *g = s->g;
    double *id = s->id;
    for (uint32_t i = 0; i < g->nv; ++i) id[i] = INFINITY;
    gs__iheap_clear(&s->heap);
    for (uint32_t i = 0; i < n_src; ++i) {
        if (src[i].face == GS_NONE && s->start <= 1) {
            relax(s, id, g->inv[src[i].vertex], 0, max_d);
            continue;
        }
        if (!s->ex) {
            gs_solver_options o;
            gs_solver_options_default(&o);
            int rc = gs__exact_ops.create(t, &o, &s->ex, err);
            if (rc) return rc;
            s->exd = gs__malloc(t->nv ? t->nv : 1, sizeof *s->exd);
            if (!s->exd) return gs__fail(err, GS_ENOMEM, "out of memory in the dgg solver");
            for (uint32_t v = 0; v < t->nv; ++v) s->exd[v] = INFINITY;
        }
        /* the start: exact distances within start R of the source (at
         * least R and its face's or star's longest edge), one bounded run */
        double r = g->radius, lmax = 0;
        if (src[i].face != GS_NONE) {
            for (int k = 0; k < 3; ++k) lmax = fmax(lmax, t->len[3 * (size_t)src[i].face + k]);
        } else {
            uint32_t v = src[i].vertex;
            for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k)
                lmax = fmax(lmax, fmax(t->len[t->vc[k]], t->len[gs__prev(t->vc[k])]));
        }
        r = fmax(fmax(s->start, 1) * r, lmax) * (1 + 1e-9);
        if (max_d < r) r = max_d;
        const uint32_t *tv;
        uint32_t ntv;
        int rc = gs__exact_solve_local(s->ex, &src[i], r, s->exd, &tv, &ntv, err);
        if (rc) {
            for (uint32_t k = 0; k < t->nv; ++k) s->exd[k] = INFINITY;
            return rc;
        }
        /* every touched vertex holds a real path length (exact within r) */
        for (uint32_t k = 0; k < ntv; ++k) {
            uint32_t u = tv[k];
            relax(s, id, g->inv[u], s->exd[u], max_d);
            s->exd[u] = INFINITY;
        }
    }
    uint64_t pops = 0;
    const uint64_t *start = g->start;
    const uint32_t *to = g->to;
    const double *w = g->w;
    while (s->heap.n) {
        double d;
        uint32_t v = gs__iheap_pop(&s->heap, &d);
        ++pops;
        for (uint64_t k = start[v]; k < start[v + 1]; ++k) relax(s, id, to[k], d + w[k], max_d);
    }
    for (uint32_t i = 0; i < g->nv; ++i) dist[g->perm[i]] = id[i];
    stats->windows_propagated = pops;
    return GS_OK;
}

void gs__dgg_info(const void *state, gs__dgg_stats *st)
{
    const dgg_state *s = state;
    const dgg_graph *g = s->g;
    memset(st, 0, sizeof *st);
    st->seconds = g->seconds;
    st->edges = g->start[g->nv];
    st->candidates = g->n_cand;
    st->radius = g->radius;
    st->bytes = g->start[g->nv] * (sizeof *g->to + sizeof *g->w) + ((uint64_t)g->nv + 1) * sizeof *g->start +
                2 * (uint64_t)g->nv * sizeof *g->perm;
    st->solve_bytes = (uint64_t)s->t->nv * (2 * sizeof(uint32_t) + 2 * sizeof(double));
}

/* Another thread's solver: the graph and maps are shared read-only (src
 * outlives it). */
static int dgg_clone(const void *state, void **out, gs_error *err)
{
    const dgg_state *src = state;
    dgg_state *s;
    int rc = state_new(src->t, &s, err);
    if (rc) return rc;
    s->g = src->g;
    s->view = src->view;
    s->start = src->start;
    *out = s;
    return GS_OK;
}

const gs__method_ops gs__dgg_ops = {"dgg", dgg_create, dgg_destroy, dgg_solve, NULL, dgg_clone};
