/* build.c - gs_db_build: the preprocessing pipeline of the paper (sec. 3.1,
 * 4.1, 4.2): nested bisection tree -> for every separator curve, distance
 * fields inside its patch from the curve's samples (any gs_method, one
 * solver per thread) -> per-vertex separator distance functions -> packed
 * database. Nodes are processed one at a time, root first; work inside a
 * node is split across threads by samples (fields) and by vertices (fits).
 * Optionally (leaf_exact) the exact distances between the vertices of each
 * leaf (the paper's matrix D), computed leaf by leaf in parallel. */
#include "../db/db_content.h"
#include "../db/db_internal.h"
#include "../fit/fit.h"
#include "../geodesic/geodesic_internal.h"
#include "../partition/tree.h"

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
    o->tol = 0.002; /* at the root, looser with depth (gs_fit_tol_at_depth) */
    o->threads = 0;
    o->vertex_sources = -1; /* by the method (see geosep.h) */
    o->sampled = 0;
    o->leaf_exact = 0;
    o->seed = 1;
    o->sample_spacing = 0.5;
    gs_solver_options_default(&o->solver);
    o->solver.heat_refine = GS_HEAT_REFINE_AUTO;
    o->max_samples = 96;
    o->field_memory_mib = 384;
}

/* Thin every curve of more than cap samples to cap samples, in place: the
 * samples nearest to cap targets at regular arc length (a path keeps both
 * ends). A distance function is fitted with degree <= mmax, so a long curve
 * gains nothing from thousands of samples, while each one costs a field
 * (or three corner fields) over the whole patch. */
static void thin_samples(gs_tree *t, uint32_t cap)
{
    for (uint32_t c = 0; c < t->n_curves && cap; ++c) {
        gs_sep_curve *cv = &t->curves[c];
        uint32_t n = cv->n_samples;
        if (n <= cap) continue;
        gs_sep_sample *sm = t->samples + cv->sample_start;
        double step = cv->length / (cv->closed ? cap : cap - 1);
        uint32_t prev = 0;
        for (uint32_t k = 1; k < cap; ++k) {
            uint32_t i = prev + 1, last = n - (cap - k); /* room for the rest */
            double target = k * step;
            while (i < last && fabs(sm[i + 1].s - target) <= fabs(sm[i].s - target)) ++i;
            if (!cv->closed && k == cap - 1) i = n - 1;
            sm[k] = sm[i];
            prev = i;
        }
        cv->n_samples = cap;
    }
}

/* Per-vertex function slots: vertex x owns funs[fun_start[x] ..) and each
 * function's coefficients live in a per-node arena. */
typedef struct builder {
    const gs_mesh *mesh;
    const double *xyz_out;  /* the positions the database stores (the      */
                            /*   caller's: mesh may be a centred copy)      */
    const gs_build_options *opt;
    const gs_tree *tree;
    uint32_t nthreads;
    uint64_t *fun_start;   /* nv+1 */
    gs_fun *funs;
    double **arenas;       /* one coefficient arena per node (or NULL)     */
    /* progress */
    double work_total, work_done;
    /* stats */
    uint64_t n_fields, n_functions, n_mixed, n_over_tol;
    double degree_sum, fit_err_sum;
} builder;

static void progress(builder *b, const char *stage, double frac)
{
    if (b->opt->progress) b->opt->progress(b->opt->progress_user, stage, frac);
}

static void tree_progress(void *user, double frac)
{
    progress(user, "tree", frac);
}

/* mesh face -> position in a node's face list, by binary search over a
 * sorted copy of (face, position) pairs. */
typedef struct face_pos {
    uint32_t face, pos;
} face_pos;

static int cmp_face_pos(const void *a, const void *b)
{
    const face_pos *x = a, *y = b;
    return x->face < y->face ? -1 : (x->face > y->face);
}

static uint32_t local_face(const face_pos *fp, uint32_t n, uint32_t face)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (fp[mid].face < face)
            lo = mid + 1;
        else
            hi = mid;
    }
    return (lo < n && fp[lo].face == face) ? fp[lo].pos : GS_NONE;
}

/* Everything one node needs while its fields and fits are computed. */
typedef struct node_job {
    const gs_tree_node *node;
    gs_patch *patch;
    uint32_t n_samples;       /* over all curves of the node              */
    uint32_t *sample_first;   /* per curve: first column                  */
    uint32_t *owned_local;    /* owned vertex -> patch-local id           */
    float *D;                 /* n_owned x n_samples distances (row = x)  */
    gs_source *src;           /* one per sample (patch-local)             */
    /* per thread, created on first use: a solver (solver[0] first, the
     * others its clones, sharing its factorisations) and CHUNK fields */
    uint32_t nthreads;
    gs_solver **solver;
    double **buf;
} node_job;

/* The solvers (factorisations for heat) and field buffers: freed as soon as
 * the node's fields are done. */
static void job_free_solvers(node_job *j)
{
    for (uint32_t t = j->nthreads; t-- > 0;) { /* clones before solver[0] */
        if (j->solver) gs_solver_free(j->solver[t]);
        if (j->buf) free(j->buf[t]);
    }
    free(j->solver);
    free(j->buf);
    j->solver = NULL;
    j->buf = NULL;
}

static void job_free(node_job *j)
{
    job_free_solvers(j);
    gs_patch_free(j->patch);
    free(j->sample_first);
    free(j->owned_local);
    free(j->D);
    free(j->src);
    memset(j, 0, sizeof *j);
}

static int job_prepare(builder *b, const gs_tree_node *nd, uint32_t nthreads, node_job *j, gs_error *err)
{
    const gs_tree *t = b->tree;
    memset(j, 0, sizeof *j);
    j->node = nd;
    j->nthreads = nthreads;
    j->solver = gs__calloc(nthreads, sizeof *j->solver);
    j->buf = gs__calloc(nthreads, sizeof *j->buf);
    if (!j->solver || !j->buf) return gs__fail(err, GS_ENOMEM, "out of memory preparing node");
    int rc = gs_patch_create(b->mesh, t->faces + nd->face_start, nd->n_faces, &j->patch, err);
    if (rc) return rc;
    face_pos *fp = gs__malloc(nd->n_faces, sizeof *fp);
    j->sample_first = gs__malloc(nd->n_curves + 1, sizeof *j->sample_first);
    j->owned_local = gs__malloc(nd->n_verts, sizeof *j->owned_local);
    if (!fp || !j->sample_first || !j->owned_local) {
        free(fp);
        return gs__fail(err, GS_ENOMEM, "out of memory preparing node");
    }
    for (uint32_t i = 0; i < nd->n_faces; ++i) fp[i] = (face_pos){t->faces[nd->face_start + i], i};
    qsort(fp, nd->n_faces, sizeof *fp, cmp_face_pos);
    uint32_t ns = 0;
    for (uint32_t c = 0; c < nd->n_curves; ++c) {
        j->sample_first[c] = ns;
        ns += t->curves[nd->curve_start + c].n_samples;
    }
    j->sample_first[nd->n_curves] = ns;
    j->n_samples = ns;
    j->src = gs__malloc(ns, sizeof *j->src);
    j->D = gs__malloc((size_t)nd->n_verts * ns, sizeof *j->D);
    if (!j->src || !j->D) {
        free(fp);
        return gs__fail(err, GS_ENOMEM, "out of memory: %u vertices x %u samples", nd->n_verts, ns);
    }
    for (uint32_t c = 0; c < nd->n_curves; ++c) {
        const gs_sep_curve *cv = &t->curves[nd->curve_start + c];
        for (uint32_t k = 0; k < cv->n_samples; ++k) {
            const gs_sep_sample *s = &t->samples[cv->sample_start + k];
            uint32_t lf = local_face(fp, nd->n_faces, s->face);
            if (lf == GS_NONE) {
                free(fp);
                return gs__fail(err, GS_EINTERNAL, "sample %u of curve %u lies on face %u outside its patch",
                                k, nd->curve_start + c, s->face);
            }
            j->src[j->sample_first[c] + k] = gs_source_point(lf, s->bary[0], s->bary[1], s->bary[2]);
        }
    }
    free(fp);
    for (uint32_t i = 0; i < nd->n_verts; ++i) {
        uint32_t lv = gs_patch_vertex_from_mesh(j->patch, t->verts[nd->vert_start + i]);
        if (lv == GS_NONE)
            return gs__fail(err, GS_EINTERNAL, "vertex %u is owned by a node whose patch lacks it",
                            t->verts[nd->vert_start + i]);
        j->owned_local[i] = lv;
    }
    return GS_OK;
}

/* Nodes with fewer owned vertices are processed in parallel, one thread
 * each; larger ones one at a time with all threads. */
enum { SMALL_NODE = 4096 };

/* Fields are solved in chunks of CHUNK sources (one batched solve for the
 * heat method). Chunks are fixed by the source order alone, never by the
 * thread count, so the result does not depend on it. */
enum { CHUNK = 16 };

/* Sources per block for a node with nown owned vertices: a block of fields
 * (n_block x n_owned doubles, per_source per source) fits in
 * field_memory_mib; at least a chunk. */
static uint32_t block_sources(const builder *b, uint32_t nown, uint32_t per_source)
{
    size_t bytes = (size_t)(b->opt->field_memory_mib ? b->opt->field_memory_mib : 384) << 20;
    size_t k = bytes / ((size_t)(nown ? nown : 1) * per_source * sizeof(double));
    k = k / CHUNK * CHUNK;
    return k < CHUNK ? CHUNK : (k > (1u << 20) ? (1u << 20) : (uint32_t)k);
}

/* Solve one field per source src[0..n) (patch-local) with the node's
 * per-thread solvers and store source k's distances to the owned vertices
 * in F[col[k] * nown ..) (col NULL: column k). */
static int solve_block(builder *b, node_job *j, const gs_source *src, uint32_t n, const uint32_t *col, double *F,
                       gs_error *err)
{
    uint32_t nl = gs_patch_num_vertices(j->patch), nown = j->node->n_verts;
    uint32_t nchunks = (n + CHUNK - 1) / CHUNK;
    int rc = GS_OK;
    /* one factorisation for all threads (heat): the first solver here, the
     * others clone it */
    if (!j->solver[0] && (rc = gs_solver_create_ex(j->patch, b->opt->method, &b->opt->solver, &j->solver[0], err)))
        return rc;
#pragma omp parallel num_threads(j->nthreads)
    {
        uint32_t tid = (uint32_t)omp_get_thread_num();
        gs_error e;
        int my = GS_OK;
#pragma omp for schedule(dynamic, 1)
        for (uint32_t q = 0; q < nchunks; ++q) {
            if (my) continue;
            if (!j->solver[tid]) my = gs__solver_clone(j->solver[0], &j->solver[tid], &e);
            if (!my && !j->buf[tid] && !(j->buf[tid] = gs__malloc((size_t)CHUNK * nl + 1, sizeof(double))))
                my = gs__fail(&e, GS_ENOMEM, "out of memory for %u fields of %u vertices", CHUNK, nl);
            if (my) continue;
            uint32_t k0 = q * CHUNK, k = n - k0 < CHUNK ? n - k0 : CHUNK;
            my = gs__solver_solve_each(j->solver[tid], src + k0, k, j->buf[tid], &e);
            if (my) continue;
            for (uint32_t c = 0; c < k; ++c) {
                const double *dist = j->buf[tid] + (size_t)c * nl;
                double *out = F + (size_t)(col ? col[k0 + c] : k0 + c) * nown;
                for (uint32_t i = 0; i < nown; ++i) out[i] = dist[j->owned_local[i]];
            }
        }
#pragma omp critical
        if (my && rc == GS_OK) {
            rc = my;
            if (err) *err = e;
        }
    }
#pragma omp atomic
    b->n_fields += n;
    return rc;
}

/* Fields from every sample (sample sources): column k of D, block by block. */
static int fields_from_samples(builder *b, node_job *j, gs_error *err)
{
    uint32_t nown = j->node->n_verts, ns = j->n_samples;
    uint32_t blk = block_sources(b, nown, 1);
    if (blk > ns) blk = ns;
    double *F = gs__malloc((size_t)blk * nown + 1, sizeof *F);
    if (!F) return gs__fail(err, GS_ENOMEM, "out of memory: %u vertices x %u fields", nown, blk);
    int rc = GS_OK;
    for (uint32_t k0 = 0; k0 < ns && rc == GS_OK; k0 += blk) {
        uint32_t k = ns - k0 < blk ? ns - k0 : blk;
        rc = solve_block(b, j, j->src + k0, k, NULL, F, err);
        if (rc) break;
#pragma omp parallel for num_threads(j->nthreads) schedule(static)
        for (uint32_t i = 0; i < nown; ++i)
            for (uint32_t c = 0; c < k; ++c) j->D[(size_t)i * ns + k0 + c] = (float)F[(size_t)c * nown + i];
    }
    free(F);
    return rc;
}

/* The paper's variant: fields from the corners of the sample faces, then
 * d(x,s)^2 ~ sum l_i d(x,v_i)^2 - sum_{i<j} l_i l_j |v_i - v_j|^2. */
static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : (x > y);
}

static uint32_t find_u32(const uint32_t *a, uint32_t n, uint32_t v)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* One block of corner fields: the sorted distinct corners of some samples,
 * and each one's column in F (nown doubles per column). */
typedef struct corner_block {
    uint32_t n, *corner, *col;
    double *F;
} corner_block;

/* The corner fields are computed block by block of samples (consecutive
 * samples share corners: those of the previous block are copied, not
 * solved again), each block folded into D before the next one. */
static int fields_from_vertices(builder *b, node_job *j, gs_error *err)
{
    const gs_topo *pt = j->patch->topo;
    uint32_t nown = j->node->n_verts, ns = j->n_samples;
    uint32_t blk = block_sources(b, nown, 3);
    if (blk > ns) blk = ns;
    if (blk == 0) blk = 1;
    size_t ncol = 3 * (size_t)blk;
    corner_block cb[2];
    uint32_t *todo_col = gs__malloc(ncol, sizeof *todo_col), *scol = gs__malloc(ncol, sizeof *scol);
    double *scross = gs__malloc(blk, sizeof *scross);
    gs_source *vs = gs__malloc(ncol, sizeof *vs);
    int rc = todo_col && scol && scross && vs ? GS_OK : GS_ENOMEM;
    for (int q = 0; q < 2; ++q) {
        cb[q].n = 0;
        cb[q].corner = gs__malloc(ncol, sizeof *cb[q].corner);
        cb[q].col = gs__malloc(ncol, sizeof *cb[q].col);
        cb[q].F = gs__malloc(ncol * nown + 1, sizeof *cb[q].F);
        if (!cb[q].corner || !cb[q].col || !cb[q].F) rc = GS_ENOMEM;
    }
    if (rc) gs__fail(err, rc, "out of memory: %u vertices x %zu corner fields", nown, 2 * ncol);
    for (uint32_t k0 = 0; k0 < ns && rc == GS_OK; k0 += blk) {
        uint32_t nk = ns - k0 < blk ? ns - k0 : blk;
        corner_block *cur = &cb[(k0 / blk) & 1], *prev = &cb[((k0 / blk) & 1) ^ 1];
        uint32_t nc = 0;
        for (uint32_t k = k0; k < k0 + nk; ++k)
            for (int i = 0; i < 3; ++i) cur->corner[nc++] = pt->tri[3 * (size_t)j->src[k].face + i];
        qsort(cur->corner, nc, sizeof *cur->corner, cmp_u32);
        uint32_t nu = 0;
        for (uint32_t i = 0; i < nc; ++i)
            if (i == 0 || cur->corner[i] != cur->corner[i - 1]) cur->corner[nu++] = cur->corner[i];
        cur->n = nu;
        /* columns: corners to solve first (in corner order), then copies */
        uint32_t nt = 0, next = 0;
        for (uint32_t u = 0; u < nu; ++u) {
            uint32_t p = find_u32(prev->corner, prev->n, cur->corner[u]);
            if (p < prev->n && prev->corner[p] == cur->corner[u]) continue;
            vs[nt] = gs_source_vertex(cur->corner[u]);
            todo_col[nt++] = cur->col[u] = next++;
        }
        for (uint32_t u = 0; u < nu; ++u) {
            uint32_t p = find_u32(prev->corner, prev->n, cur->corner[u]);
            if (p < prev->n && prev->corner[p] == cur->corner[u]) {
                cur->col[u] = next++;
                memcpy(cur->F + (size_t)cur->col[u] * nown, prev->F + (size_t)prev->col[p] * nown,
                       nown * sizeof *cur->F);
            }
        }
        rc = solve_block(b, j, vs, nt, todo_col, cur->F, err);
        if (rc) break;
        /* per sample: its corners' columns and sum_{q<r} l_q l_r |v_q - v_r|^2 */
        for (uint32_t k = k0; k < k0 + nk; ++k) {
            const double *l = j->src[k].bary;
            const uint32_t *c = pt->tri + 3 * (size_t)j->src[k].face;
            double p[3][3], cross = 0;
            for (int q = 0; q < 3; ++q) {
                scol[3 * (size_t)(k - k0) + q] = cur->col[find_u32(cur->corner, nu, c[q])];
                memcpy(p[q], pt->xyz + 3 * (size_t)c[q], sizeof p[q]);
            }
            for (int q = 0; q < 3; ++q)
                for (int r = q + 1; r < 3; ++r) {
                    double dx = p[q][0] - p[r][0], dy = p[q][1] - p[r][1], dz = p[q][2] - p[r][2];
                    cross += l[q] * l[r] * (dx * dx + dy * dy + dz * dz);
                }
            scross[k - k0] = cross;
        }
#pragma omp parallel for num_threads(j->nthreads) schedule(static)
        for (uint32_t i = 0; i < nown; ++i) {
            for (uint32_t k = k0; k < k0 + nk; ++k) {
                const double *l = j->src[k].bary;
                const uint32_t *col = scol + 3 * (size_t)(k - k0);
                double v = 0;
                for (int q = 0; q < 3; ++q) {
                    double d = cur->F[(size_t)col[q] * nown + i];
                    v += l[q] * d * d;
                }
                v -= scross[k - k0];
                j->D[(size_t)i * ns + k] = (float)(isfinite(v) ? sqrt(v > 0 ? v : 0) : INFINITY);
            }
        }
    }
    for (int q = 0; q < 2; ++q) {
        free(cb[q].corner);
        free(cb[q].col);
        free(cb[q].F);
    }
    free(todo_col);
    free(scol);
    free(scross);
    free(vs);
    return rc;
}

/* Fit every owned vertex's function for every curve of the node. */
static int fit_node(builder *b, node_job *j, uint32_t node_id, gs_error *err)
{
    const gs_tree *t = b->tree;
    const gs_tree_node *nd = j->node;
    uint32_t ns = j->n_samples, nc = nd->n_curves;
    uint32_t cap_total = 0; /* coefficient room per vertex */
    for (uint32_t c = 0; c < nc; ++c)
        cap_total += b->opt->sampled ? t->curves[nd->curve_start + c].n_samples : b->opt->mmax + 1;
    double *arena = gs__malloc((size_t)nd->n_verts * cap_total, sizeof *arena);
    double *u_all = gs__malloc(ns, sizeof *u_all);
    if (!arena || !u_all) {
        free(arena);
        free(u_all);
        return gs__fail(err, GS_ENOMEM, "out of memory for node %u's functions", node_id);
    }
    b->arenas[node_id] = arena;
    for (uint32_t c = 0; c < nc; ++c) {
        const gs_sep_curve *cv = &t->curves[nd->curve_start + c];
        for (uint32_t k = 0; k < cv->n_samples; ++k) {
            double s = t->samples[cv->sample_start + k].s;
            u_all[j->sample_first[c] + k] =
                cv->closed ? -1.0 + 2.0 * k / cv->n_samples : -1.0 + 2.0 * s / cv->length;
        }
        if (!cv->closed) u_all[j->sample_first[c] + cv->n_samples - 1] = 1.0;
    }
    gs_fit_options fo;
    gs_fit_options_default(&fo);
    fo.m_max = b->opt->mmax;
    fo.tol = gs_fit_tol_at_depth(b->opt->tol, nd->depth);
    int rc = GS_OK;
    uint64_t n_fun = 0, n_mixed = 0, n_over = 0;
    double deg_sum = 0, err_sum = 0;
#pragma omp parallel num_threads(j->nthreads) reduction(+ : n_fun, n_mixed, deg_sum, n_over, err_sum)
    {
        gs_fit_work *w = NULL;
        gs_error e;
        uint32_t max_ns = 0;
        for (uint32_t c = 0; c < nc; ++c)
            if (t->curves[nd->curve_start + c].n_samples > max_ns) max_ns = t->curves[nd->curve_start + c].n_samples;
        double *d = gs__malloc(max_ns, sizeof *d);
        int my = d ? gs_fit_work_create(max_ns, &fo, &w, &e) : GS_ENOMEM;
        gs_fit_result res;
#pragma omp for schedule(dynamic, 64)
        for (uint32_t i = 0; i < nd->n_verts; ++i) {
            if (my) continue;
            uint32_t x = t->verts[nd->vert_start + i];
            double *slot = arena + (size_t)i * cap_total;
            for (uint32_t c = 0; c < nc && !my; ++c) {
                const gs_sep_curve *cv = &t->curves[nd->curve_start + c];
                uint32_t n = cv->n_samples;
                const float *row = j->D + (size_t)i * ns + j->sample_first[c];
                double mx = 0, mn = INFINITY;
                uint32_t n_inf = 0;
                for (uint32_t k = 0; k < n; ++k) {
                    if (isfinite(row[k])) {
                        if (row[k] > mx) mx = row[k];
                        if (row[k] < mn) mn = row[k];
                    } else
                        n_inf++;
                }
                gs_fun *f = &b->funs[b->fun_start[x] + nd->curve_prefix + c];
                uint32_t cap = b->opt->sampled ? n : b->opt->mmax + 1;
                memset(f, 0, sizeof *f);
                f->closed = cv->closed;
                if (n_inf == n) { /* the curve is in another component */
                    f->minval = INFINITY;
                    slot += cap;
                    continue;
                }
                for (uint32_t k = 0; k < n; ++k) d[k] = isfinite(row[k]) ? row[k] : 2 * mx;
                if (n_inf) n_mixed++;
                if (b->opt->sampled) {
                    memcpy(slot, d, n * sizeof *d);
                    f->kind = GS_FUN_SAMPLED;
                    f->degree = n - 1;
                    f->minval = n_inf ? fmin(mn, 2 * mx) : mn;
                    f->coef = slot;
                } else {
                    my = gs_fit_distance(w, u_all + j->sample_first[c], d, n, cv->closed, &res, &e);
                    if (my) break;
                    *f = res.fun;
                    memcpy(slot, res.coef, (res.fun.degree + 1) * sizeof *slot);
                    f->coef = slot;
                    deg_sum += res.fun.degree;
                    err_sum += res.mean_rel_err;
                    n_over += res.mean_rel_err > fo.tol;
                }
                n_fun++;
                slot += cap;
            }
        }
#pragma omp critical
        if (my && rc == GS_OK) {
            rc = my;
            if (err) *err = e;
        }
        gs_fit_work_free(w);
        free(d);
    }
    free(u_all);
#pragma omp critical(gs_build_stats)
    {
        b->n_functions += n_fun;
        b->n_mixed += n_mixed;
        b->degree_sum += deg_sum;
        b->n_over_tol += n_over;
        b->fit_err_sum += err_sum;
    }
    return rc;
}

/* Shrink node_id's arena to the coefficients its functions use (the fits
 * reserve room for degree mmax) and repoint them. */
static int compact_arena(builder *b, const gs_tree_node *nd, uint32_t node_id, gs_error *err)
{
    const gs_tree *t = b->tree;
    size_t used = 0;
    for (uint32_t i = 0; i < nd->n_verts; ++i) {
        const gs_fun *f = &b->funs[b->fun_start[t->verts[nd->vert_start + i]] + nd->curve_prefix];
        for (uint32_t c = 0; c < nd->n_curves; ++c)
            if (f[c].coef) used += f[c].degree + 1;
    }
    double *arena = gs__malloc(used + 1, sizeof *arena);
    if (!arena) return gs__fail(err, GS_ENOMEM, "out of memory for node %u's functions", node_id);
    size_t k = 0;
    for (uint32_t i = 0; i < nd->n_verts; ++i) {
        gs_fun *f = &b->funs[b->fun_start[t->verts[nd->vert_start + i]] + nd->curve_prefix];
        for (uint32_t c = 0; c < nd->n_curves; ++c) {
            if (!f[c].coef) continue;
            memcpy(arena + k, f[c].coef, (f[c].degree + 1) * sizeof *arena);
            f[c].coef = arena + k;
            k += f[c].degree + 1;
        }
    }
    free(b->arenas[node_id]);
    b->arenas[node_id] = arena;
    return GS_OK;
}

/* Fields, fits and compaction of node i with nthreads threads; adds the
 * seconds spent to *t_fields and *t_fits. */
static int process_node(builder *b, uint32_t i, uint32_t nthreads, double *t_fields, double *t_fits,
                        gs_error *err)
{
    const gs_tree_node *nd = &b->tree->nodes[i];
    node_job j;
    double ta = gs__now();
    int rc = job_prepare(b, nd, nthreads, &j, err);
    if (rc == GS_OK)
        rc = b->opt->vertex_sources ? fields_from_vertices(b, &j, err) : fields_from_samples(b, &j, err);
    double tb = gs__now();
    job_free_solvers(&j);
    if (rc == GS_OK) rc = fit_node(b, &j, i, err);
    if (rc == GS_OK) rc = compact_arena(b, nd, i, err);
    job_free(&j);
    *t_fields += tb - ta;
    *t_fits += gs__now() - tb;
    return rc;
}

/* ---- exact same-leaf distances (leaf_exact; paper sec. 3.1, matrix D) ------
 * For every leaf L and every pair x, y of its vertices, the exact distance
 * d_M(x, y) on the whole mesh (with the builder's method). Solving a field
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
typedef struct leaf_tables {
    uint32_t *vstart;  /* n_nodes+1 */
    uint32_t *verts;
    uint64_t *dstart;  /* n_nodes+1 */
    double *dist;
} leaf_tables;

static void leaf_tables_free(leaf_tables *lt)
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

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap) return 0;
    size_t n = *cap ? *cap : 256;
    while (n < need) n *= 2;
    void *q = gs__realloc(*p, n, size);
    if (!q) return -1;
    *p = q;
    *cap = n;
    return 0;
}

/* Can face f meet the ball B(x, r) of some leaf vertex x? */
static int face_near_leaf(const gs_mesh *m, uint32_t f, const uint32_t *lv, uint32_t n, const double *r)
{
    const gs_topo *t = &m->topo;
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

/* The faces of the region of a leaf (see above) into w->faces; returns the
 * count, or GS_NONE when out of memory. stamp is unique per leaf (> 0). */
static uint32_t leaf_region(const gs_mesh *m, const uint32_t *lv, uint32_t n, const double *r, uint32_t stamp,
                            leaf_work *w)
{
    const gs_topo *t = &m->topo;
    size_t nf = 0;
    for (uint32_t k = 0; k < n; ++k)
        for (uint32_t c = t->vc_start[lv[k]]; c < t->vc_start[lv[k] + 1]; ++c) {
            uint32_t f = t->vc[c] / 3;
            if (w->fstamp[f] == stamp) continue;
            w->fstamp[f] = stamp;
            if (grow((void **)&w->faces, &w->cap, nf + 1, sizeof *w->faces)) return GS_NONE;
            w->faces[nf++] = f;
        }
    for (size_t q = 0; q < nf; ++q) { /* breadth first through shared vertices */
        uint32_t f = w->faces[q];
        for (int i = 0; i < 3; ++i) {
            uint32_t v = m->tri[3 * (size_t)f + i];
            for (uint32_t c = t->vc_start[v]; c < t->vc_start[v + 1]; ++c) {
                uint32_t g = t->vc[c] / 3;
                if (w->fstamp[g] == stamp) continue;
                w->fstamp[g] = stamp;
                if (!face_near_leaf(m, g, lv, n, r)) continue;
                if (grow((void **)&w->faces, &w->cap, nf + 1, sizeof *w->faces)) return GS_NONE;
                w->faces[nf++] = g;
            }
        }
    }
    return (uint32_t)nf;
}

/* Fields from every vertex of patch p's subset lv (n vertices); row k of T
 * (n x n) gets source k's distances to all of lv. bound: per-source bound
 * (NULL: none). */
static int leaf_solve(const gs_patch *p, gs_method method, const gs_solver_options *so_opt, const uint32_t *lv, uint32_t n, const double *bound,
                      double *T, leaf_work *w, gs_error *err)
{
    uint32_t nl = gs_patch_num_vertices(p);
    if (grow((void **)&w->dist, &w->dcap, nl, sizeof *w->dist))
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

static int leaf_table(builder *b, uint32_t node, const uint32_t *lv, double *T, uint32_t stamp, leaf_work *w,
                      gs_error *err)
{
    const gs_tree_node *nd = &b->tree->nodes[node];
    uint32_t n = nd->n_verts;
    gs_method method = b->opt->method;
    if (grow((void **)&w->radius, &w->rcap, n, sizeof *w->radius))
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

static int build_leaf_tables(builder *b, leaf_tables *lt, gs_error *err)
{
    const gs_tree *t = b->tree;
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
        const gs_tree_node *nd = &t->nodes[i];
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
            if (omp_get_thread_num() == 0) progress(b, "leaves", (double)d / n_leaves);
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

static int assemble(builder *b, const leaf_tables *lt, gs_db **out, gs_error *err)
{
    const gs_tree *t = b->tree;
    gs_db_node *nodes = gs__malloc(t->n_nodes, sizeof *nodes);
    gs_db_curve *curves = gs__malloc(t->n_curves, sizeof *curves);
    if (!nodes || !curves) {
        free(nodes);
        free(curves);
        return gs__fail(err, GS_ENOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < t->n_nodes; ++i) {
        const gs_tree_node *n = &t->nodes[i];
        nodes[i] = (gs_db_node){n->parent, n->depth, n->curve_start, n->n_curves, n->curve_prefix};
    }
    for (uint32_t i = 0; i < t->n_curves; ++i) {
        const gs_sep_curve *c = &t->curves[i];
        curves[i] = (gs_db_curve){c->node, c->closed, c->n_samples, c->length};
    }
    gs_db_content c;
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

static int check_options(const gs_build_options *o, gs_error *err)
{
    if (!gs_method_name(o->method)) return gs__fail(err, GS_EARG, "unknown method %d", (int)o->method);
    if (o->vmax < 3) return gs__fail(err, GS_EARG, "vmax %u is too small (>= 3)", o->vmax);
    if (o->mmax < 2 || o->mmax > GS_FUN_MAX_DEGREE)
        return gs__fail(err, GS_EARG, "mmax %u out of range [2, %d]", o->mmax, GS_FUN_MAX_DEGREE);
    if (!(o->tol > 0 && o->tol < 1)) return gs__fail(err, GS_EARG, "tol %g out of range (0, 1)", o->tol);
    if (!(o->sample_spacing >= 0.01 && o->sample_spacing <= 100))
        return gs__fail(err, GS_EARG, "sample_spacing %g out of range [0.01, 100]", o->sample_spacing);
    if (o->max_samples && (o->max_samples < 8 || o->max_samples > (1u << 24)))
        return gs__fail(err, GS_EARG, "max_samples %u out of range (0 or [8, 2^24])", o->max_samples);
    if (o->field_memory_mib > (1u << 20))
        return gs__fail(err, GS_EARG, "field_memory_mib %u is absurd", o->field_memory_mib);
    if (o->threads > 1024) return gs__fail(err, GS_EARG, "threads %u is absurd", o->threads);
    if (!(o->solver.heat_time >= GS_HEAT_TIME_MIN && o->solver.heat_time <= GS_HEAT_TIME_MAX))
        return gs__fail(err, GS_EARG, "solver.heat_time %g out of range [%g, %g]", o->solver.heat_time,
                        GS_HEAT_TIME_MIN, GS_HEAT_TIME_MAX);
    if (!(isfinite(o->solver.fmm_exact_start) && o->solver.fmm_exact_start >= 0))
        return gs__fail(err, GS_EARG, "solver.fmm_exact_start %g must be finite and >= 0", o->solver.fmm_exact_start);
    if (o->solver.heat_refine > GS_HEAT_REFINE_MAX && o->solver.heat_refine != GS_HEAT_REFINE_AUTO)
        return gs__fail(err, GS_EARG, "solver.heat_refine %u must be at most %d (or GS_HEAT_REFINE_AUTO)",
                        o->solver.heat_refine, GS_HEAT_REFINE_MAX);
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
    if (rc) return rc;
    /* the heat method's resolution from the whole mesh's size, the same for
     * every patch; other methods ignore it (recorded as 0) */
    if (resolved.method != GS_METHOD_HEAT) resolved.solver.heat_refine = 0;
    else if (resolved.solver.heat_refine == GS_HEAT_REFINE_AUTO)
        resolved.solver.heat_refine = gs_heat_refine_auto(gs_mesh_num_vertices(mesh));
    builder b;
    memset(&b, 0, sizeof b);
    b.mesh = mesh;
    b.xyz_out = xyz_out;
    b.opt = opt;
    b.nthreads = opt->threads ? opt->threads : (uint32_t)omp_get_max_threads();
    double t0 = gs__now();

    gs_tree_options to;
    gs_tree_options_default(&to);
    to.vmax = opt->vmax;
    to.seed = opt->seed;
    to.sample_spacing = opt->sample_spacing;
    to.threads = b.nthreads;
    to.progress = tree_progress;
    to.progress_user = &b;
    gs_tree *tree = NULL;
    progress(&b, "tree", 0);
    rc = gs_tree_build(mesh, &to, &tree, err);
    if (rc) return rc;
    thin_samples(tree, opt->max_samples);
    b.tree = tree;
    double t1 = gs__now();
    progress(&b, "tree", 1);

    b.fun_start = gs__malloc((size_t)mesh->nv + 1, sizeof *b.fun_start);
    b.arenas = gs__calloc(tree->n_nodes, sizeof *b.arenas);
    if (!b.fun_start || !b.arenas) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory");
        goto done;
    }
    b.fun_start[0] = 0;
    for (uint32_t x = 0; x < mesh->nv; ++x) {
        uint32_t l = tree->leaf_of_vertex[x];
        b.fun_start[x + 1] = b.fun_start[x] + (l == GS_NONE ? 0 : tree->nodes[l].curve_prefix);
    }
    b.funs = gs__calloc(b.fun_start[mesh->nv], sizeof *b.funs);
    if (!b.funs) {
        rc = gs__fail(err, GS_ENOMEM, "out of memory for %llu functions",
                      (unsigned long long)b.fun_start[mesh->nv]);
        goto done;
    }
    for (uint32_t i = 0; i < tree->n_nodes; ++i)
        if (tree->nodes[i].n_curves)
            b.work_total += (double)tree->nodes[i].n_faces * tree->nodes[i].n_curves;
    double t_fields = 0, t_fits = 0;
    /* Large nodes one at a time, threads inside each (sources, vertices);
     * then the small ones in parallel, one thread each. The result is the
     * same either way (chunks of sources do not depend on threads). */
    for (uint32_t i = 0; i < tree->n_nodes && rc == GS_OK; ++i) {
        const gs_tree_node *nd = &tree->nodes[i];
        if (nd->n_curves == 0 || (b.nthreads > 1 && nd->n_verts < SMALL_NODE)) continue;
        rc = process_node(&b, i, b.nthreads, &t_fields, &t_fits, err);
        b.work_done += (double)nd->n_faces * nd->n_curves;
        progress(&b, "fields", b.work_total > 0 ? b.work_done / b.work_total : 1);
    }
    if (rc == GS_OK && b.nthreads > 1) {
        double ta = gs__now(), sf = 0, sfit = 0;
#pragma omp parallel num_threads(b.nthreads) reduction(+ : sf, sfit)
        {
            gs_error e;
            int my = GS_OK;
#pragma omp for schedule(dynamic, 1)
            for (uint32_t i = 0; i < tree->n_nodes; ++i) {
                const gs_tree_node *nd = &tree->nodes[i];
                if (my || nd->n_curves == 0 || nd->n_verts >= SMALL_NODE) continue;
                my = process_node(&b, i, 1, &sf, &sfit, &e);
                double w;
#pragma omp critical(gs_build_stats)
                w = b.work_done += (double)nd->n_faces * nd->n_curves;
                if (omp_get_thread_num() == 0) progress(&b, "fields", b.work_total > 0 ? w / b.work_total : 1);
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
    leaf_tables lt;
    memset(&lt, 0, sizeof lt);
    if (rc == GS_OK && opt->leaf_exact) {
        double ta = gs__now();
        progress(&b, "leaves", 0);
        rc = build_leaf_tables(&b, &lt, err);
        t_fields += gs__now() - ta; /* exact leaf fields count as fields */
    }
    if (rc == GS_OK) {
        progress(&b, "write", 0);
        rc = assemble(&b, &lt, out, err);
        progress(&b, "write", 1);
    }
    leaf_tables_free(&lt);
    if (rc == GS_OK && stats) {
        stats->seconds_tree = t1 - t0;
        stats->seconds_fields = t_fields;
        stats->seconds_fits = t_fits;
        stats->seconds_total = gs__now() - t0;
        stats->n_fields = b.n_fields;
        stats->n_functions = b.n_functions;
        stats->mean_degree = b.n_functions ? b.degree_sum / (double)b.n_functions : 0;
        stats->n_over_tol = b.n_over_tol;
        stats->mean_fit_error = b.n_functions ? b.fit_err_sum / (double)b.n_functions : 0;
    }
done:
    if (b.arenas)
        for (uint32_t i = 0; i < tree->n_nodes; ++i) free(b.arenas[i]);
    free(b.arenas);
    free(b.funs);
    free(b.fun_start);
    gs_tree_free(tree);
    return rc;
}
