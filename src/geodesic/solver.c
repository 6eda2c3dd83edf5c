/* solver.c - gs_solver: the public, method-independent front of the distance
 * field methods. Validates and normalises sources, dispatches to a method. */
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct gs_solver {
    const gs_patch *patch;
    const gs__method_ops *ops;
    void *state;
    gs_source *src; /* normalised copy of the sources */
    uint32_t src_cap;
    gs__solve_stats stats;
    double seconds;
    gs_solver_options opt; /* as created (gs__solver_clone)               */
};

static const gs__method_ops *ops_of(gs_method m)
{
    switch (m) {
    case GS_METHOD_EXACT: return &gs__exact_ops;
    case GS_METHOD_GRAPH: return &gs__graph_ops;
    case GS_METHOD_FMM: return &gs__fmm_ops;
    case GS_METHOD_HEAT: return &gs__heat_ops;
    case GS_METHOD_DGG: return &gs__dgg_ops;
    default: return NULL;
    }
}

const char *gs_method_name(gs_method m)
{
    const gs__method_ops *o = ops_of(m);
    return o ? o->name : NULL;
}

int gs_method_from_name(const char *name, gs_method *m, gs_error *err)
{
    static const gs_method all[] = {GS_METHOD_EXACT, GS_METHOD_GRAPH, GS_METHOD_FMM, GS_METHOD_HEAT, GS_METHOD_DGG};
    if (!m) return gs__fail(err, GS_EARG, "gs_method_from_name: method is NULL");
    for (size_t i = 0; name && i < sizeof all / sizeof all[0]; ++i)
        if (strcmp(name, ops_of(all[i])->name) == 0) {
            *m = all[i];
            return GS_OK;
        }
    return gs__fail(err, GS_EARG, "unknown method '%s' (expected exact, graph, fmm, heat or dgg)",
                    name ? name : "(null)");
}

gs_source gs_source_vertex(uint32_t v)
{
    gs_source s = {v, GS_NONE, {0, 0, 0}};
    return s;
}

gs_source gs_source_point(uint32_t f, double b0, double b1, double b2)
{
    gs_source s = {GS_NONE, f, {b0, b1, b2}};
    return s;
}

void gs__source_position(const gs__topo *t, const gs_source *s, double p[3])
{
    if (s->face == GS_NONE) {
        memcpy(p, t->xyz + 3 * (size_t)s->vertex, 3 * sizeof(double));
        return;
    }
    gs__face_point(t, s->face, s->bary, p);
}

uint32_t gs__source_seeds(const gs__topo *t, const gs_source *s, uint32_t v[3], double d[3])
{
    if (s->face == GS_NONE) {
        v[0] = s->vertex, d[0] = 0.0;
        return 1;
    }
    double p[3];
    gs__source_position(t, s, p);
    for (int k = 0; k < 3; ++k) {
        v[k] = t->tri[3 * (size_t)s->face + k];
        const double *q = t->xyz + 3 * (size_t)v[k];
        double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
        d[k] = sqrt(dx * dx + dy * dy + dz * dz);
    }
    return 3;
}

void gs_solver_options_default(gs_solver_options *o)
{
    if (!o) return;
    o->heat_time = 1.0;
    o->fmm_exact_start = 4.0;
    o->heat_refine = 0;
    o->dgg_eps = 1e-3;
}

uint32_t gs_heat_refine_auto(uint32_t nv)
{
    uint32_t n = 0;
    for (uint64_t v = nv; n < 2 && v < GS_HEAT_REFINE_AUTO_VERTICES; v *= 4) ++n;
    return n;
}

int gs_solver_create(const gs_patch *patch, gs_method method, gs_solver **out, gs_error *err)
{
    return gs_solver_create_ex(patch, method, NULL, out, err);
}

/* Validated options (defaults for NULL) into *o. */
static int resolve_options(const gs_patch *patch, const gs_solver_options *opt, gs_solver_options *o, gs_error *err)
{
    gs_solver_options_default(o);
    if (opt) *o = *opt;
    if (!(o->heat_time >= GS_HEAT_TIME_MIN && o->heat_time <= GS_HEAT_TIME_MAX))
        return gs__fail(err, GS_EARG, "gs_solver_create: heat_time %g out of range [%g, %g]", o->heat_time,
                        GS_HEAT_TIME_MIN, GS_HEAT_TIME_MAX);
    if (!(isfinite(o->fmm_exact_start) && o->fmm_exact_start >= 0))
        return gs__fail(err, GS_EARG, "gs_solver_create: fmm_exact_start %g must be finite and >= 0",
                        o->fmm_exact_start);
    if (!(o->dgg_eps >= GS_DGG_EPS_MIN && o->dgg_eps <= GS_DGG_EPS_MAX))
        return gs__fail(err, GS_EARG, "gs_solver_create: dgg_eps %g out of range [%g, %g]", o->dgg_eps,
                        GS_DGG_EPS_MIN, GS_DGG_EPS_MAX);
    if (o->heat_refine == GS_HEAT_REFINE_AUTO) o->heat_refine = gs_heat_refine_auto(gs_patch_num_vertices(patch));
    if (o->heat_refine > GS_HEAT_REFINE_MAX)
        return gs__fail(err, GS_EARG, "gs_solver_create: heat_refine %u must be at most %d (or GS_HEAT_REFINE_AUTO)",
                        o->heat_refine, GS_HEAT_REFINE_MAX);
    return GS_OK;
}

int gs_solver_create_ex(const gs_patch *patch, gs_method method, const gs_solver_options *opt,
                        gs_solver **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_solver_create: out is NULL");
    *out = NULL;
    if (!patch) return gs__fail(err, GS_EARG, "gs_solver_create: patch is NULL");
    const gs__method_ops *ops = ops_of(method);
    if (!ops) return gs__fail(err, GS_EARG, "gs_solver_create: unknown method %d", (int)method);
    gs_solver_options o;
    int rc = resolve_options(patch, opt, &o, err);
    if (rc) return rc;
    gs_solver *s = gs__calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory");
    s->patch = patch;
    s->ops = ops;
    s->opt = o;
    rc = ops->create(patch->topo, &o, &s->state, err);
    if (rc) {
        free(s);
        return rc;
    }
    *out = s;
    return GS_OK;
}

int gs__solver_create_dgg(const gs_patch *patch, const gs_solver_options *opt, uint32_t nthreads, int prune,
                          const gs__dgg_progress *progress, gs_solver **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_solver_create: out is NULL");
    *out = NULL;
    if (!patch) return gs__fail(err, GS_EARG, "gs_solver_create: patch is NULL");
    gs_solver_options o;
    int rc = resolve_options(patch, opt, &o, err);
    if (rc) return rc;
    gs_solver *s = gs__calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory");
    s->patch = patch;
    s->ops = &gs__dgg_ops;
    s->opt = o;
    void *g = NULL;
    rc = gs__dgg_build(patch->topo, o.dgg_eps, prune, nthreads, progress, &g, err);
    if (rc == GS_OK) rc = gs__dgg_state_from_graph(patch->topo, g, &s->state, err);
    if (rc) {
        free(s);
        return rc;
    }
    *out = s;
    return GS_OK;
}

int gs__solver_dgg_view(const gs_solver *whole, const gs_patch *sub, gs_solver **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs__solver_dgg_view: out is NULL");
    *out = NULL;
    if (!whole || !sub || whole->ops != &gs__dgg_ops)
        return gs__fail(err, GS_EARG, "gs__solver_dgg_view: needs a dgg solver and a patch");
    if (!whole->patch->identity || sub->mesh != whole->patch->mesh)
        return gs__fail(err, GS_EARG, "gs__solver_dgg_view: the dgg solver must be of the sub-patch's whole mesh");
    gs_solver *s = gs__calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory");
    s->patch = sub;
    s->ops = &gs__dgg_ops;
    s->opt = whole->opt;
    int rc = gs__dgg_view(whole->state, sub->topo, sub->identity ? NULL : sub->vmap, &s->state, err);
    if (rc) {
        free(s);
        return rc;
    }
    *out = s;
    return GS_OK;
}

int gs__solver_clone(const gs_solver *src, gs_solver **out, gs_error *err)
{
    if (!src || !out) return gs__fail(err, GS_EARG, "gs__solver_clone: NULL argument");
    *out = NULL;
    gs_solver *s = gs__calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory");
    s->patch = src->patch;
    s->ops = src->ops;
    s->opt = src->opt;
    int rc = s->ops->clone ? s->ops->clone(src->state, &s->state, err)
                           : s->ops->create(s->patch->topo, &s->opt, &s->state, err);
    if (rc) {
        free(s);
        return rc;
    }
    *out = s;
    return GS_OK;
}

void gs_solver_free(gs_solver *s)
{
    if (!s) return;
    if (s->state) s->ops->destroy(s->state);
    free(s->src);
    free(s);
}

static int normalise_source(const gs__topo *t, const gs_source *in, uint32_t i, gs_source *o,
                            gs_error *err)
{
    if (in->face == GS_NONE) {
        if (in->vertex >= t->nv)
            return gs__fail(err, GS_EARG, "source %u: vertex %u out of range (%u vertices)", i,
                            in->vertex, t->nv);
        if (t->vflag[in->vertex] & GS_V_UNUSED) {
            /* an isolated vertex: it reaches only itself */
        }
        *o = gs_source_vertex(in->vertex);
        return GS_OK;
    }
    if (in->face >= t->nf)
        return gs__fail(err, GS_EARG, "source %u: face %u out of range (%u faces)", i, in->face,
                        t->nf);
    double b[3], sum = 0;
    for (int k = 0; k < 3; ++k) {
        b[k] = in->bary[k];
        if (!isfinite(b[k]) || b[k] < -1e-9)
            return gs__fail(err, GS_EARG,
                            "source %u: barycentric coordinate %d is %g (must be >= 0)", i, k,
                            b[k]);
        if (b[k] < 0) b[k] = 0;
        sum += b[k];
    }
    if (fabs(sum - 1.0) > 1e-9)
        return gs__fail(err, GS_EARG,
                        "source %u: barycentric coordinates sum to %.17g (must be 1)", i, sum);
    for (int k = 0; k < 3; ++k) b[k] /= sum;
    for (int k = 0; k < 3; ++k)
        if (b[k] == 1.0) {
            *o = gs_source_vertex(t->tri[3 * (size_t)in->face + k]);
            return GS_OK;
        }
    *o = gs_source_point(in->face, b[0], b[1], b[2]);
    return GS_OK;
}

int gs_solver_solve(gs_solver *s, const gs_source *sources, uint32_t n, double max_distance,
                    double *dist, gs_error *err)
{
    if (!s || !dist || (n && !sources))
        return gs__fail(err, GS_EARG, "gs_solver_solve: NULL argument");
    if (n == 0) return gs__fail(err, GS_EARG, "gs_solver_solve: no source given");
    if (isnan(max_distance) || max_distance < 0)
        return gs__fail(err, GS_EARG, "gs_solver_solve: max_distance %g is invalid",
                        max_distance);
    if (max_distance == 0) max_distance = INFINITY;
    const gs__topo *t = s->patch->topo;
    if (n > s->src_cap) {
        gs_source *ns = gs__realloc(s->src, n, sizeof *ns);
        if (!ns) return gs__fail(err, GS_ENOMEM, "out of memory");
        s->src = ns;
        s->src_cap = n;
    }
    for (uint32_t i = 0; i < n; ++i) {
        int rc = normalise_source(t, &sources[i], i, &s->src[i], err);
        if (rc) return rc;
    }
    memset(&s->stats, 0, sizeof s->stats);
    double t0 = gs__now();
    int rc = s->ops->solve(s->state, s->src, n, max_distance, dist, &s->stats, err);
    s->seconds = gs__now() - t0;
    return rc;
}

int gs__solver_solve_each(gs_solver *s, const gs_source *sources, uint32_t n, double *dist, gs_error *err)
{
    if (!s || !dist || (n && !sources)) return gs__fail(err, GS_EARG, "gs__solver_solve_each: NULL argument");
    if (!s->ops->solve_each) {
        size_t nv = s->patch->topo->nv;
        for (uint32_t i = 0; i < n; ++i) {
            int rc = gs_solver_solve(s, &sources[i], 1, 0, dist + i * nv, err);
            if (rc) return rc;
        }
        return GS_OK;
    }
    if (n > s->src_cap) {
        gs_source *ns = gs__realloc(s->src, n, sizeof *ns);
        if (!ns) return gs__fail(err, GS_ENOMEM, "out of memory");
        s->src = ns;
        s->src_cap = n;
    }
    const gs__topo *t = s->patch->topo;
    for (uint32_t i = 0; i < n; ++i) {
        int rc = normalise_source(t, &sources[i], i, &s->src[i], err);
        if (rc) return rc;
    }
    memset(&s->stats, 0, sizeof s->stats);
    double t0 = gs__now();
    int rc = s->ops->solve_each(s->state, s->src, n, dist, &s->stats, err);
    s->seconds = gs__now() - t0;
    return rc;
}

void gs_solver_last_stats(const gs_solver *s, uint64_t *created, uint64_t *propagated,
                          double *seconds)
{
    if (created) *created = s ? s->stats.windows_created : 0;
    if (propagated) *propagated = s ? s->stats.windows_propagated : 0;
    if (seconds) *seconds = s ? s->seconds : 0;
}

int gs_distance_field(const gs_patch *patch, gs_method method, const gs_source *sources,
                      uint32_t n, double max_distance, double *dist, gs_error *err)
{
    gs_solver *s = NULL;
    int rc = gs_solver_create(patch, method, &s, err);
    if (rc) return rc;
    rc = gs_solver_solve(s, sources, n, max_distance, dist, err);
    gs_solver_free(s);
    return rc;
}

/* ---- exact paths (path.c) ------------------------------------------------- */

int gs_solver_trace(gs_solver *s, const gs_source *target, gs_path **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_solver_trace: out is NULL");
    *out = NULL;
    if (!s || !target) return gs__fail(err, GS_EARG, "gs_solver_trace: NULL argument");
    if (s->ops != &gs__exact_ops)
        return gs__fail(err, GS_EARG, "gs_solver_trace: paths need the exact method (this solver is %s)",
                        s->ops->name);
    const gs__topo *t = s->patch->topo;
    const gs__exact_trace *tr = gs__exact_get_trace(s->state);
    if (!tr) return gs__fail(err, GS_EARG, "gs_solver_trace: no exact field solved yet");
    gs_source q;
    gs_error e2 = {0};
    int rc = normalise_source(t, target, 0, &q, &e2);
    if (rc) return gs__fail(err, rc, "gs_solver_trace: target: %s", e2.message + strlen("source 0: "));
    if (q.face != GS_NONE)
        return gs__fail(err, GS_EARG, "gs_solver_trace: the target is a surface point (face %u); "
                        "gs_solver_path traces to surface points", q.face);
    if (tr->dist[q.vertex] > tr->max_d && tr->dist[q.vertex] < INFINITY)
        return gs__fail(err, GS_EARG, "gs_solver_trace: vertex %u lies beyond the last solve's max_distance %g",
                        q.vertex, tr->max_d);
    return gs__exact_trace_path(t, tr, &q, out, err);
}

int gs_solver_path(gs_solver *s, const gs_source *source, const gs_source *target, gs_path **out,
                   gs_error *err)
{
    return gs__solver_path_bounded(s, source, target, 0, out, err);
}

int gs__solver_path_bounded(gs_solver *s, const gs_source *source, const gs_source *target, double max_distance,
                            gs_path **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_solver_path: out is NULL");
    *out = NULL;
    if (!s || !source || !target) return gs__fail(err, GS_EARG, "gs_solver_path: NULL argument");
    if (s->ops != &gs__exact_ops)
        return gs__fail(err, GS_EARG, "gs_solver_path: paths need the exact method (this solver is %s)",
                        s->ops->name);
    const gs__topo *t = s->patch->topo;
    gs_source q;
    gs_error e2 = {0};
    int rc = normalise_source(t, target, 0, &q, &e2);
    if (rc) return gs__fail(err, rc, "gs_solver_path: target: %s", e2.message + strlen("source 0: "));
    double *dist = gs__malloc(t->nv ? t->nv : 1, sizeof *dist);
    if (!dist) return gs__fail(err, GS_ENOMEM, "out of memory");
    gs__exact_set_target(s->state, &q);
    double goal[3];
    gs__source_position(t, &q, goal);
    int bounded = max_distance > 0 && max_distance < INFINITY;
    if (bounded) gs__exact_set_goal(s->state, goal);
    rc = gs_solver_solve(s, source, 1, max_distance, dist, err);
    gs__exact_set_target(s->state, NULL);
    gs__exact_set_goal(s->state, NULL);
    free(dist);
    if (rc) return rc;
    const gs__exact_trace *tr = gs__exact_get_trace(s->state);
    if (bounded && !(q.face != GS_NONE && tr->n_src && tr->src[0].face == q.face)) {
        /* only what lies within the bound is exact: a target beyond it gets no path */
        double dt = q.face == GS_NONE ? tr->dist[q.vertex] : INFINITY;
        for (int k = 0; q.face != GS_NONE && k < 3; ++k) {
            double e[3];
            const double *x = t->xyz + 3 * (size_t)t->tri[3 * (size_t)q.face + k];
            for (int j = 0; j < 3; ++j) e[j] = x[j] - goal[j]; /* goal: the target's position */
            dt = fmin(dt, tr->dist[t->tri[3 * (size_t)q.face + k]] + sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]));
        }
        if (q.face != GS_NONE && tr->target.face == q.face) dt = fmin(dt, tr->target.dist);
        if (!(dt <= max_distance)) return gs__path_adopt(0, NULL, NULL, NULL, INFINITY, out, err);
    }
    return gs__exact_trace_path(t, tr, &q, out, err);
}

int gs__solver_dgg_info(const gs_solver *s, gs__dgg_stats *st, gs_error *err)
{
    if (!s || s->ops != &gs__dgg_ops) return gs__fail(err, GS_EARG, "gs__solver_dgg_info: not a dgg solver");
    gs__dgg_info(s->state, st);
    return GS_OK;
}
