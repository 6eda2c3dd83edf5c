/* build.c - gs_db_build: the preprocessing pipeline of the paper (sec. 3.1,
 * 4.1, 4.2): nested bisection tree -> for every separator curve, distance
 * fields inside its patch from the curve's samples (any gs_method, one
 * solver per thread) -> per-vertex separator distance functions -> packed
 * database. Nodes are processed one at a time, root first; work inside a
 * node is split across threads by samples (fields) and by vertices (fits).
 * Optionally (leaf_exact) the exact distances between the vertices of each
 * leaf (the paper's matrix D), computed leaf by leaf in parallel. */
#include "pipeline.h"

#include "../db/db_content.h"
#include "../db/db_internal.h"
#include "../fit/fit.h"
#include "../geodesic/geodesic_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

void gs_build_options_default(gs_build_options *o)
{
    memset(o, 0, sizeof *o);
    o->method = GS_METHOD_EXACT;
    o->vmax = 30;
    o->mmax = 20; /* long top-level curves need more than 12 (paper 4.2) */
    o->tol = 0.003; /* at the root, looser with depth (gs__fit_tol_at_depth); the certified fits (fit.h) need the slack: 0.002 cost bunny-5k 97 numbers per vertex */
    o->threads = 0;
    o->vertex_sources = -1; /* by the method (see geosep.h) */
    o->sampled = 0;
    o->leaf_exact = 1; /* same-leaf pairs: Euclidean answers were off by up to 56% (bunny-5k) */
    o->near_radius = 5; /* twice that around uncertified fits: every pair beyond within 5% on every shared mesh (doc/accuracy.md) */
    o->seed = 1;
    o->sample_spacing = 0.5;
    gs_solver_options_default(&o->solver);
    o->solver.heat_refine = GS_HEAT_REFINE_AUTO;
    o->max_samples = 192; /* then split into pieces of <= GS_PIPE_PIECE intervals */
    o->field_memory_mib = 384;
}


/* Longest curve piece, in sample intervals (homer, all pairs: max error 166%
 * -> 20%, RMSE 0.54% -> 0.21% with pieces of 48; a piece costs each vertex
 * of its node one more function) */
#define GS_PIPE_PIECE 48

/* How rough the surface is at the scale of its edges: the median over the
 * vertices of |h(v) - mean of h over v's neighbours|, where h(v) is the
 * component along v's normal of the umbrella vector (the neighbours' mean
 * less v) in units of v's mean edge: a smooth surface's h varies slowly,
 * however coarse its triangles (torus:24,12 0.004, bunny-5k 0.039,
 * rocker-arm 0.021), a noisy one's flips from vertex to vertex (radial
 * noise of +-0.34 mean edges on a sphere: 0.21; height noise of +-0.75
 * cells: 0.24). Neighbours through each face (an inner edge counts twice);
 * vertices on no face or with a zero normal are left out. 0 when none is
 * left or out of memory (then nothing is rough). */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y);
}

static double mesh_roughness(const gs_mesh *m)
{
    uint32_t nv = m->nv;
    double *acc = gs__calloc((size_t)nv * 8 + 1, sizeof *acc), *h = gs__malloc((size_t)nv + 1, sizeof *h);
    double rough = 0;
    uint32_t k = 0;
    if (!acc || !h) goto out;
    /* acc per vertex: neighbour sum (3), normal (3), edge length sum, count */
    for (uint32_t f = 0; f < m->nf; ++f) {
        const uint32_t *t = m->tri + 3 * (size_t)f;
        const double *p[3] = {m->xyz + 3 * (size_t)t[0], m->xyz + 3 * (size_t)t[1], m->xyz + 3 * (size_t)t[2]};
        double e1[3], e2[3], n[3];
        for (int d = 0; d < 3; ++d) e1[d] = p[1][d] - p[0][d], e2[d] = p[2][d] - p[0][d];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        for (int a = 0; a < 3; ++a) {
            double *q = acc + 8 * (size_t)t[a];
            for (int o = 1; o < 3; ++o) {
                const double *r = p[(a + o) % 3];
                double dx = r[0] - p[a][0], dy = r[1] - p[a][1], dz = r[2] - p[a][2];
                q[0] += r[0], q[1] += r[1], q[2] += r[2];
                q[6] += sqrt(dx * dx + dy * dy + dz * dz), q[7] += 1;
            }
            q[3] += n[0], q[4] += n[1], q[5] += n[2];
        }
    }
    for (uint32_t v = 0; v < nv; ++v) {
        const double *q = acc + 8 * (size_t)v, *p = m->xyz + 3 * (size_t)v;
        double nl = sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5]), el = q[7] > 0 ? q[6] / q[7] : 0;
        h[v] = NAN;
        if (!(nl > 0) || !(el > 0)) continue;
        double u = 0;
        for (int d = 0; d < 3; ++d) u += (q[d] / q[7] - p[d]) * q[3 + d] / nl;
        h[v] = u / el;
    }
    /* second pass: the neighbours' mean of h, into acc[8v] (sum) and [8v+1] (count) */
    for (uint32_t v = 0; v < nv; ++v) acc[8 * (size_t)v] = acc[8 * (size_t)v + 1] = 0;
    for (uint32_t f = 0; f < m->nf; ++f) {
        const uint32_t *t = m->tri + 3 * (size_t)f;
        for (int a = 0; a < 3; ++a)
            for (int o = 1; o < 3; ++o) {
                double hu = h[t[(a + o) % 3]];
                if (hu == hu) acc[8 * (size_t)t[a]] += hu, acc[8 * (size_t)t[a] + 1] += 1;
            }
    }
    for (uint32_t v = 0; v < nv; ++v)
        if (h[v] == h[v] && acc[8 * (size_t)v + 1] > 0) h[k++] = fabs(h[v] - acc[8 * (size_t)v] / acc[8 * (size_t)v + 1]);
    if (k) {
        qsort(h, k, sizeof *h, cmp_double);
        rough = h[k / 2];
    }
out:
    free(acc), free(h);
    return rough;
}

/* Rough surfaces (noisy scans, spiky at the scale of the edges): each
 * vertex's distance along a curve kinks at nearly every edge the curve
 * crosses, and a series of degree mmax over 48 sample intervals smooths
 * the kinks away, its minima sitting above the true ones (queries through
 * such fits overestimate: ME 0.37% on a spiky sphere). The nodes of depth
 * <= GS_PIPE_ROUGH_DEPTH (they split 15/16 of the vertex pairs) are
 * processed first. On a rough surface (mesh_roughness at least
 * GS_PIPE_ROUGH_MESH: the noisy meshes of doc/accuracy.md 0.14-0.36, every
 * shared mesh at most 0.04) each of those nodes where more than
 * GS_PIPE_ROUGH_SOME of the functions miss the tolerance at degree mmax
 * (noisy spheres and height fields: 1-21%; a spiky sphere whose fits meet
 * it, 0.9%, is left alone) gets its curves cut into pieces of at most
 * GS_PIPE_PIECE_ROUGH intervals and is processed again (its fields too:
 * doc/accuracy.md, "Rough surfaces"). Exact fields only: approximate
 * fields' own noise is not the surface's. */
#define GS_PIPE_ROUGH_MESH 0.1
#define GS_PIPE_ROUGH_SOME 0.01
#define GS_PIPE_ROUGH_DEPTH 3
#define GS_PIPE_PIECE_ROUGH 16
/* ... and their near pairs are checked GS_PIPE_NEAR_ROUGH times further out
 * (the shorter pieces leave fewer fits uncertified, whose vertices' radius
 * near.c widens, yet pairs at 5-10 edges can be off by 5%) */
#define GS_PIPE_NEAR_ROUGH 2.0


void gs__pipe_progress(gs__builder *b, const char *stage, double frac)
{
    if (b->opt->progress) b->opt->progress(b->opt->progress_user, stage, frac);
}

static void tree_progress(void *user, double frac)
{
    gs__pipe_progress(user, "tree", frac);
}

static void graph_progress(void *user, double frac)
{
    gs__pipe_progress(user, "graph", frac);
}

/* near_radius > 0: the section 'near_pairs' with pairs[0..n_near). */
static int assemble(gs__builder *b, const gs__leaf_tables *lt, double near_radius, const gs__near_pair *pairs,
                    uint64_t n_near, gs_db **out, gs_error *err)
{
    const gs__tree *t = b->tree;
    gs__db_node *nodes = gs__malloc(t->n_nodes, sizeof *nodes);
    gs__db_curve *curves = gs__malloc(t->n_curves, sizeof *curves);
    if (!nodes || !curves) {
        free(nodes);
        free(curves);
        return gs__fail(err, GS_ENOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < t->n_nodes; ++i) {
        const gs__tree_node *n = &t->nodes[i];
        nodes[i] = (gs__db_node){n->parent, n->depth, n->curve_start, n->n_curves, n->curve_prefix};
    }
    for (uint32_t i = 0; i < t->n_curves; ++i) {
        const gs__sep_curve *c = &t->curves[i];
        curves[i] = (gs__db_curve){c->node, c->closed, c->n_samples, c->length};
    }
    gs__db_content c;
    memset(&c, 0, sizeof c);
    c.nv = b->mesh->nv;
    c.xyz = b->xyz_out;
    c.n_nodes = t->n_nodes;
    c.nodes = nodes;
    c.n_curves = t->n_curves;
    c.curves = curves;
    c.leaf = t->leaf_of_vertex;
    c.fun_start = b->fun_start;
    c.funs = b->funs;
    if (lt && lt->dist) {
        c.leaf_vstart = lt->vstart;
        c.leaf_verts = lt->verts;
        c.leaf_dstart = lt->dstart;
        c.leaf_dist = lt->dist;
    }
    c.near_radius = near_radius;
    c.near_pairs = pairs;
    c.n_near = n_near;
    c.method = (uint32_t)b->opt->method;
    c.vmax = b->opt->vmax;
    c.mmax = b->opt->mmax;
    c.tol = b->opt->tol;
    c.vertex_sources = (uint32_t)b->opt->vertex_sources;
    c.sample_spacing = b->opt->sample_spacing;
    c.seed = b->opt->seed;
    c.max_samples = b->opt->max_samples;
    c.heat_time = b->opt->solver.heat_time;
    c.fmm_exact_start = b->opt->solver.fmm_exact_start;
    c.dgg_eps = b->opt->method == GS_METHOD_DGG ? b->opt->solver.dgg_eps : 0.0;
    if (b->opt->repair) { /* input-id aliases (checked against the mesh by check_options) */
        c.n_input = b->opt->repair->n_input_vertices;
        c.alias_start = b->opt->repair->alias_start;
        c.alias = b->opt->repair->alias;
    }
    c.heat_refine = b->opt->solver.heat_refine;
    c.sampled = (uint32_t)b->opt->sampled;
    c.avg_depth = t->avg_leaf_depth;
    c.max_depth = t->max_depth;
    c.n_leaves = t->n_leaves;
    int rc = gs__db_pack(&c, out, err);
    free(nodes);
    free(curves);
    return rc;
}

/* Each vertex's near radius: R0, or when one of its functions is
 * uncertified (a fit off by more than GS_FIT_MAX_ERR somewhere) R0 times
 * its worst fit error / GS_FIT_MAX_ERR, clamped to [GS_PIPE_NEAR_WIDE,
 * GS_PIPE_NEAR_WIDE_MAX]: answers through such functions were off by up to
 * 9% 6 to 10 mean edges apart on homer (fits off by 2-5%), 5.2% 10.3 edges
 * apart on rocker-arm (a fit off by 8%); and at least the largest absolute
 * error A of its uncertified functions / GS_PIPE_NEAR_TOL (at most
 * GS_PIPE_NEAR_ABS_MAX R0): a fit that dips by A moves an answer through
 * it by at most A, less than GS_PIPE_NEAR_TOL of any pair farther apart
 * than that (a noisy height field: pairs 19 mean edges apart were off by
 * 8.8% through fits off by up to 25%, beyond the 15 edges of the rule
 * above; with A, 2.6% at most). Exact fields only: with approximate ones
 * the field's own error dominates the pairs off by 2%, and a wider radius
 * stores more of them (peaks:40, fmm). *rmax: the largest. NULL when out
 * of memory. */
static double *near_radii(const gs__builder *b, double R0, double *rmax)
{
    uint32_t nv = b->mesh->nv;
    double *r = gs__malloc(nv ? nv : 1, sizeof *r);
    int exact = b->opt->method == GS_METHOD_EXACT;
    if (!r) return NULL;
    *rmax = 0;
    for (uint32_t x = 0; x < nv; ++x) {
        float worst = 0, dip = 0;
        for (uint64_t k = b->fun_start[x]; k < b->fun_start[x + 1]; ++k) {
            worst = fmaxf(worst, b->fun_err[k]);
            if (b->fun_err[k] >= GS_FIT_MAX_ERR) dip = fmaxf(dip, b->fun_abs[k]);
        }
        double w = fmin(GS_PIPE_NEAR_WIDE_MAX, fmax(GS_PIPE_NEAR_WIDE, worst / GS_FIT_MAX_ERR));
        double wa = exact ? fmin(GS_PIPE_NEAR_ABS_MAX * R0, dip / GS_PIPE_NEAR_TOL) : 0;
        r[x] = worst >= GS_FIT_MAX_ERR ? fmax(w * R0, wa) : R0;
        *rmax = fmax(*rmax, r[x]);
    }
    return r;
}

static int check_options(const gs_build_options *o, gs_error *err)
{
    if (!gs_method_name(o->method)) return gs__fail(err, GS_EARG, "unknown method %d", (int)o->method);
    if (o->vmax < 3) return gs__fail(err, GS_EARG, "vmax %u is too small (>= 3)", o->vmax);
    if (o->mmax < 2 || o->mmax > GS_FUN_MAX_DEGREE)
        return gs__fail(err, GS_EARG, "mmax %u out of range [2, %d]", o->mmax, GS_FUN_MAX_DEGREE);
    if (!(o->tol > 0 && o->tol < 1)) return gs__fail(err, GS_EARG, "tol %g out of range (0, 1)", o->tol);
    if (!(o->near_radius >= 0 && o->near_radius <= 100))
        return gs__fail(err, GS_EARG, "near_radius %g out of range [0, 100] (mean edge lengths)", o->near_radius);
    if (!(o->sample_spacing >= 0.01 && o->sample_spacing <= 100))
        return gs__fail(err, GS_EARG, "sample_spacing %g out of range [0.01, 100]", o->sample_spacing);
    if (o->max_samples && (o->max_samples < 8 || o->max_samples > (1u << 24)))
        return gs__fail(err, GS_EARG, "max_samples %u out of range (0 or [8, 2^24])", o->max_samples);
    if (o->field_memory_mib > (1u << 20))
        return gs__fail(err, GS_EARG, "field_memory_mib %u is absurd", o->field_memory_mib);
    if (o->threads > GS_MAX_THREADS)
        return gs__fail(err, GS_EARG, "threads %u out of range [0, %u]", o->threads, GS_MAX_THREADS);
    if (!(o->solver.heat_time >= GS_HEAT_TIME_MIN && o->solver.heat_time <= GS_HEAT_TIME_MAX))
        return gs__fail(err, GS_EARG, "solver.heat_time %g out of range [%g, %g]", o->solver.heat_time,
                        GS_HEAT_TIME_MIN, GS_HEAT_TIME_MAX);
    if (!(isfinite(o->solver.fmm_exact_start) && o->solver.fmm_exact_start >= 0))
        return gs__fail(err, GS_EARG, "solver.fmm_exact_start %g must be finite and >= 0", o->solver.fmm_exact_start);
    if (o->solver.heat_refine > GS_HEAT_REFINE_MAX && o->solver.heat_refine != GS_HEAT_REFINE_AUTO)
        return gs__fail(err, GS_EARG, "solver.heat_refine %u must be at most %d (or GS_HEAT_REFINE_AUTO)",
                        o->solver.heat_refine, GS_HEAT_REFINE_MAX);
    if (o->method == GS_METHOD_DGG && !(o->solver.dgg_eps >= GS_DGG_EPS_MIN && o->solver.dgg_eps <= GS_DGG_EPS_MAX))
        return gs__fail(err, GS_EARG, "solver.dgg_eps %g out of range [%g, %g]", o->solver.dgg_eps, GS_DGG_EPS_MIN,
                        GS_DGG_EPS_MAX);
    return GS_OK;
}

/* opt->repair must describe this mesh: its repaired vertex count, and the
 * alias lists the writer stores (each list non-empty, every alias a vertex
 * of the mesh: the writer checks those). */
static int check_repair(const gs_repair *r, const gs_mesh *mesh, gs_error *err)
{
    uint32_t nv = gs_mesh_num_vertices(mesh);
    if (r->n_vertices != nv || r->n_input_vertices == 0 || r->n_input_vertices > nv || !r->alias_start || !r->alias)
        return gs__fail(err, GS_EARG,
                        "repair: made a mesh of %u vertices from %u input vertices, but the mesh has %u vertices "
                        "(the repair's mesh only)",
                        r->n_vertices, r->n_input_vertices, nv);
    return GS_OK;
}

static int build_db(const gs_mesh *mesh, const double *xyz_out, const gs_build_options *opt_in, gs_db **out,
                    gs_build_stats *stats, gs_error *err);

/* A mesh farther from the origin than CENTRE_FAR times its bounding box's
 * diagonal is built from a copy moved to the origin: the separators'
 * points are convex combinations of positions, which far from the origin
 * lose the digits that tell them apart (a flat grid at z = 1e90 failed
 * with its curve parameters out of order). Geodesic distances do not
 * change; the database keeps the caller's positions. Nearer meshes are
 * built as they are (so their files do not change). */
#define CENTRE_FAR 1e3

int gs_db_build(const gs_mesh *mesh, const gs_build_options *opt_in, gs_db **out,
                gs_build_stats *stats, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_db_build: out is NULL");
    *out = NULL;
    if (!mesh) return gs__fail(err, GS_EARG, "gs_db_build: mesh is NULL");
    const double *lo = mesh->report.bbox_min, *hi = mesh->report.bbox_max; /* 0 without vertices */
    double c[3], far = 0.0, diag = 0.0;
    for (int k = 0; k < 3; ++k) {
        c[k] = lo[k] + 0.5 * (hi[k] - lo[k]);
        far = fabs(c[k]) > far ? fabs(c[k]) : far;
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    diag = sqrt(diag);
    if (!(far > CENTRE_FAR * diag)) return build_db(mesh, mesh->xyz, opt_in, out, stats, err);
    double *xyz = gs__malloc((size_t)mesh->nv, 3 * sizeof *xyz);
    if (!xyz) return gs__fail(err, GS_ENOMEM, "gs_db_build: out of memory");
    for (uint32_t v = 0; v < mesh->nv; ++v)
        for (int k = 0; k < 3; ++k) xyz[3 * (size_t)v + k] = mesh->xyz[3 * (size_t)v + k] - c[k];
    gs_mesh *moved = NULL;
    int rc = gs_mesh_create(xyz, mesh->nv, mesh->tri, mesh->nf, &moved, err);
    free(xyz);
    if (rc) return rc;
    rc = build_db(moved, mesh->xyz, opt_in, out, stats, err);
    gs_mesh_free(moved);
    return rc;
}

/* The per-vertex function slots of b->tree's curves, empty; the work
 * total for progress. On failure the caller frees what was made
 * (free_functions). */
static int alloc_functions(gs__builder *b, gs_error *err)
{
    const gs__tree *tree = b->tree;
    uint32_t nv = b->mesh->nv;
    b->fun_start = gs__malloc((size_t)nv + 1, sizeof *b->fun_start);
    b->arenas = gs__calloc(tree->n_nodes, sizeof *b->arenas);
    b->node_fits = gs__calloc((size_t)tree->n_nodes + 1, sizeof *b->node_fits);
    if (!b->fun_start || !b->arenas || !b->node_fits) return gs__fail(err, GS_ENOMEM, "out of memory");
    b->fun_start[0] = 0;
    for (uint32_t x = 0; x < nv; ++x) {
        uint32_t l = tree->leaf_of_vertex[x];
        b->fun_start[x + 1] = b->fun_start[x] + (l == GS_NONE ? 0 : tree->nodes[l].curve_prefix);
    }
    b->funs = gs__calloc(b->fun_start[nv], sizeof *b->funs);
    b->fun_err = gs__calloc(b->fun_start[nv] + 1, sizeof *b->fun_err);
    b->fun_abs = gs__calloc(b->fun_start[nv] + 1, sizeof *b->fun_abs);
    if (!b->funs || !b->fun_err || !b->fun_abs)
        return gs__fail(err, GS_ENOMEM, "out of memory for %llu functions", (unsigned long long)b->fun_start[nv]);
    b->work_total = 0;
    for (uint32_t i = 0; i < tree->n_nodes; ++i)
        if (tree->nodes[i].n_curves) b->work_total += (double)tree->nodes[i].n_faces * tree->nodes[i].n_curves;
    return GS_OK;
}

static void free_functions(gs__builder *b)
{
    if (b->arenas)
        for (uint32_t i = 0; i < b->tree->n_nodes; ++i) free(b->arenas[i]);
    free(b->arenas), free(b->funs), free(b->fun_err), free(b->fun_abs), free(b->fun_start), free(b->node_fits);
    b->arenas = NULL, b->funs = NULL, b->fun_err = b->fun_abs = NULL, b->fun_start = NULL, b->node_fits = NULL;
}

/* Cut the curves of the nodes with rough[i] into pieces of
 * GS_PIPE_PIECE_ROUGH intervals and lay the function slots out again: the
 * functions of the nodes already fitted (done[i]) and not rough move to
 * their new slots (their coefficients stay in their arenas); rough nodes
 * are left to be processed again (done[i] = 0). */
static int cut_rough(gs__builder *b, gs__tree *tree, const uint8_t *rough, uint8_t *done, gs_error *err)
{
    uint32_t nn = tree->n_nodes;
    gs__builder old = *b;
    uint32_t *prefix = gs__malloc((size_t)nn + 1, sizeof *prefix), *ncurves = gs__malloc((size_t)nn + 1, sizeof *ncurves);
    if (!prefix || !ncurves) {
        free(prefix), free(ncurves);
        return gs__fail(err, GS_ENOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < nn; ++i) prefix[i] = tree->nodes[i].curve_prefix, ncurves[i] = tree->nodes[i].n_curves;
    b->arenas = NULL, b->funs = NULL, b->fun_err = b->fun_abs = NULL, b->fun_start = NULL, b->node_fits = NULL;
    int rc = gs__pipe_split_curves(tree, GS_PIPE_PIECE_ROUGH, rough, NULL, err);
    if (rc == GS_OK) rc = alloc_functions(b, err);
    if (rc) {
        free_functions(b);
        *b = old; /* the caller frees it and gives up */
        free(prefix), free(ncurves);
        return rc;
    }
    for (uint32_t i = 0; i < nn; ++i) {
        const gs__tree_node *nd = &tree->nodes[i];
        if (!done[i]) continue;
        if (rough[i]) {
            done[i] = 0;
            continue;
        }
        b->arenas[i] = old.arenas[i], old.arenas[i] = NULL;
        b->node_fits[i] = old.node_fits[i];
        for (uint32_t v = 0; v < nd->n_verts; ++v) {
            uint32_t x = tree->verts[nd->vert_start + v];
            uint64_t from = old.fun_start[x] + prefix[i], to = b->fun_start[x] + nd->curve_prefix;
            memcpy(b->funs + to, old.funs + from, ncurves[i] * sizeof *b->funs);
            memcpy(b->fun_err + to, old.fun_err + from, ncurves[i] * sizeof *b->fun_err);
            memcpy(b->fun_abs + to, old.fun_abs + from, ncurves[i] * sizeof *b->fun_abs);
        }
    }
    free_functions(&old);
    free(prefix), free(ncurves);
    return GS_OK;
}

static int build_db(const gs_mesh *mesh, const double *xyz_out, const gs_build_options *opt_in, gs_db **out,
                    gs_build_stats *stats, gs_error *err)
{
    gs_build_options defaults;
    gs_build_options_default(&defaults);
    gs_build_options resolved = opt_in ? *opt_in : defaults;
    /* exact fields: sample sources (bunny-5k ME 0.36% vs 0.38%); approximate
     * fields reproduce themselves far better from vertex sources, the
     * sources they are made for (FMM on bunny-5k: ME 0.69% vs 1.59%) */
    if (resolved.vertex_sources < 0) resolved.vertex_sources = resolved.method != GS_METHOD_EXACT;
    const gs_build_options *opt = &resolved;
    int rc = check_options(opt, err);
    if (!rc && opt->repair) rc = check_repair(opt->repair, mesh, err);
    if (rc) return rc;
    /* the heat method's resolution from the whole mesh's size, the same for
     * every patch; other methods ignore it (recorded as 0) */
    if (resolved.method != GS_METHOD_HEAT) resolved.solver.heat_refine = 0;
    else if (resolved.solver.heat_refine == GS_HEAT_REFINE_AUTO)
        resolved.solver.heat_refine = gs_heat_refine_auto(gs_mesh_num_vertices(mesh));
    gs__builder b;
    memset(&b, 0, sizeof b);
    b.mesh = mesh;
    b.xyz_out = xyz_out;
    b.opt = opt;
    b.nthreads = opt->threads ? opt->threads : (uint32_t)omp_get_max_threads();
    double t0 = gs__now();

    gs__tree_options to;
    gs__tree_options_default(&to);
    to.vmax = opt->vmax;
    to.seed = opt->seed;
    to.sample_spacing = opt->sample_spacing;
    /* short curves: two samples per coefficient of degree mmax, so that a
     * fit that follows a vertex's sharp dip can be certified between the
     * samples (trefoil tube: max error 23% with at least 25, 13% with 41) */
    to.min_samples = 2 * opt->mmax + 1;
    to.threads = b.nthreads;
    to.progress = tree_progress;
    to.progress_user = &b;
    gs__tree *tree = NULL;
    gs__pipe_progress(&b, "tree", 0);
    rc = gs__tree_build(mesh, &to, &tree, err);
    if (rc) return rc;
    gs__pipe_thin_samples(tree, opt->max_samples);
    uint8_t *cut = NULL;
    if ((rc = gs__pipe_insert_pivots(tree, mesh, &cut, err)) ||
        (rc = gs__pipe_split_curves(tree, GS_PIPE_PIECE, NULL, cut, err))) {
        free(cut);
        gs__tree_free(tree);
        return rc;
    }
    free(cut);
    b.tree = tree;
    double t1 = gs__now();
    gs__pipe_progress(&b, "tree", 1);

    uint8_t *done_node = gs__calloc((size_t)tree->n_nodes + 1, 1), *rough = gs__calloc((size_t)tree->n_nodes + 1, 1);
    if (!done_node || !rough || (rc = alloc_functions(&b, err))) {
        if (!done_node || !rough) rc = gs__fail(err, GS_ENOMEM, "out of memory");
        goto done;
    }
    double t_fields = 0, t_fits = 0;
    if (opt->method == GS_METHOD_DGG) {
        /* one graph for every node (doc/approximate-fields.md: patches) */
        double ta = gs__now();
        gs__dgg_progress pr = {graph_progress, &b};
        gs__pipe_progress(&b, "graph", 0);
        rc = gs_patch_create(mesh, NULL, 0, &b.dgg_patch, err);
        if (rc == GS_OK) rc = gs__solver_create_dgg(b.dgg_patch, &opt->solver, b.nthreads, 1, &pr, &b.dgg, err);
        if (rc) goto done;
        t_fields += gs__now() - ta;
    }
    /* The top nodes first, all threads each; on a rough surface those whose
     * fits miss (above) get shorter pieces and are processed again below */
    int is_rough = 0;
    for (uint32_t i = 0; i < tree->n_nodes && rc == GS_OK; ++i) {
        const gs__tree_node *nd = &tree->nodes[i];
        if (nd->n_curves == 0 || nd->depth > GS_PIPE_ROUGH_DEPTH) continue;
        rc = gs__pipe_process_node(&b, i, b.nthreads, &t_fields, &t_fits, err);
        done_node[i] = 1;
        const gs__node_fits *nf = &b.node_fits[i];
        rough[i] = nf->n_over_tol > GS_PIPE_ROUGH_SOME * (double)nf->n_functions;
        is_rough |= rough[i];
        b.work_done += (double)nd->n_faces * nd->n_curves;
        gs__pipe_progress(&b, "fields", b.work_total > 0 ? b.work_done / b.work_total : 1);
    }
    is_rough = is_rough && opt->method == GS_METHOD_EXACT && mesh_roughness(mesh) >= GS_PIPE_ROUGH_MESH;
    for (uint32_t i = 0; i < tree->n_nodes; ++i) b.n_rough += rough[i] = is_rough && rough[i];
    if (rc == GS_OK && b.n_rough) {
        double ta = gs__now();
        rc = cut_rough(&b, tree, rough, done_node, err);
        t_fits += gs__now() - ta;
        if (rc) goto done;
        b.work_done = 0;
        for (uint32_t i = 0; i < tree->n_nodes; ++i)
            if (done_node[i]) b.work_done += (double)tree->nodes[i].n_faces * tree->nodes[i].n_curves;
    }
    /* Large nodes one at a time, threads inside each (sources, vertices);
     * then the small ones in parallel, one thread each. The result is the
     * same either way (chunks of sources do not depend on threads). */
    for (uint32_t i = 0; i < tree->n_nodes && rc == GS_OK; ++i) {
        const gs__tree_node *nd = &tree->nodes[i];
        if (done_node[i] || nd->n_curves == 0 || (b.nthreads > 1 && nd->n_verts < GS_PIPE_SMALL_NODE)) continue;
        rc = gs__pipe_process_node(&b, i, b.nthreads, &t_fields, &t_fits, err);
        b.work_done += (double)nd->n_faces * nd->n_curves;
        gs__pipe_progress(&b, "fields", b.work_total > 0 ? b.work_done / b.work_total : 1);
    }
    if (rc == GS_OK && b.nthreads > 1) {
        double ta = gs__now(), sf = 0, sfit = 0;
#pragma omp parallel num_threads(b.nthreads) reduction(+ : sf, sfit)
        {
            gs_error e;
            int my = GS_OK;
#pragma omp for schedule(dynamic, 1)
            for (uint32_t i = 0; i < tree->n_nodes; ++i) {
                const gs__tree_node *nd = &tree->nodes[i];
                if (my || done_node[i] || nd->n_curves == 0 || nd->n_verts >= GS_PIPE_SMALL_NODE) continue;
                my = gs__pipe_process_node(&b, i, 1, &sf, &sfit, &e);
                double w;
#pragma omp critical(gs_build_stats)
                w = b.work_done += (double)nd->n_faces * nd->n_curves;
                if (omp_get_thread_num() == 0) gs__pipe_progress(&b, "fields", b.work_total > 0 ? w / b.work_total : 1);
            }
#pragma omp critical
            if (my && rc == GS_OK) {
                rc = my;
                if (err) *err = e;
            }
        }
        /* wall time of this phase, shared by the threads' field / fit split */
        double wall = gs__now() - ta;
        t_fields += sf + sfit > 0 ? wall * sf / (sf + sfit) : 0;
        t_fits += sf + sfit > 0 ? wall * sfit / (sf + sfit) : 0;
    }
    /* the dgg graph serves the node fields only */
    gs_solver_free(b.dgg);
    gs_patch_free(b.dgg_patch);
    b.dgg = NULL, b.dgg_patch = NULL;
    gs__leaf_tables lt;
    memset(&lt, 0, sizeof lt);
    if (rc == GS_OK && opt->leaf_exact) {
        double ta = gs__now();
        gs__pipe_progress(&b, "leaves", 0);
        rc = gs__pipe_leaf_tables(&b, &lt, err);
        t_fields += gs__now() - ta; /* exact leaf fields count as fields */
    }
    /* near pairs: checked against the database without them (the same
     * records), then the database is packed again with them */
    double t_near = 0, R = 0;
    gs__near_pair *pairs = NULL;
    uint64_t n_near = 0;
    if (stats) memset(stats, 0, sizeof *stats);
    if (rc == GS_OK && opt->near_radius > 0 && mesh->report.mean_edge > 0) {
        double ta = gs__now();
        gs_db *db0 = NULL;
        gs__pipe_progress(&b, "near", 0);
        double R0 = opt->near_radius * mesh->report.mean_edge * (b.n_rough ? GS_PIPE_NEAR_ROUGH : 1.0);
        double *radius = near_radii(&b, R0, &R);
        rc = radius ? assemble(&b, &lt, 0, NULL, 0, &db0, err) : gs__fail(err, GS_ENOMEM, "out of memory for near pairs");
        if (rc == GS_OK) rc = gs__pipe_near_pairs(&b, db0, radius, GS_PIPE_NEAR_TOL, &pairs, &n_near, err);
        free(radius);
        gs_db_free(db0);
        t_near = gs__now() - ta;
        t_fields += t_near; /* exact near fields count as fields */
        if (stats) stats->n_near_pairs = n_near;
    }
    if (rc == GS_OK) {
        gs__pipe_progress(&b, "write", 0);
        rc = assemble(&b, &lt, R, pairs, n_near, out, err);
        gs__pipe_progress(&b, "write", 1);
    }
    free(pairs);
    gs__pipe_leaf_tables_free(&lt);
    if (rc == GS_OK && stats) {
        stats->seconds_tree = t1 - t0;
        stats->seconds_fields = t_fields;
        stats->seconds_fits = t_fits;
        stats->seconds_total = gs__now() - t0;
        stats->n_fields = b.n_fields;
        gs__node_fits t = {0, 0, 0, 0, 0, 0, 0};
        for (uint32_t i = 0; i < tree->n_nodes; ++i) {
            const gs__node_fits *f = &b.node_fits[i];
            t.n_functions += f->n_functions, t.n_over_tol += f->n_over_tol, t.n_uncertified += f->n_uncertified;
            t.degree_sum += f->degree_sum, t.fit_err_sum += f->fit_err_sum;
            t.max_fit_error = fmax(t.max_fit_error, f->max_fit_error);
        }
        stats->n_functions = t.n_functions;
        stats->mean_degree = t.n_functions ? t.degree_sum / (double)t.n_functions : 0;
        stats->n_over_tol = t.n_over_tol;
        stats->n_uncertified = t.n_uncertified;
        stats->max_fit_error = t.max_fit_error;
        stats->mean_fit_error = t.n_functions ? t.fit_err_sum / (double)t.n_functions : 0;
        stats->seconds_near = t_near;
    }
done:
    gs_solver_free(b.dgg);
    gs_patch_free(b.dgg_patch);
    free_functions(&b);
    free(done_node);
    free(rough);
    gs__tree_free(tree);
    return rc;
}
