/* node.c - one node of gs_db_build (paper sec. 4.2): distance fields inside
 * its patch from its curves' samples (or from the corners of the samples'
 * triangles, with the paper's barycentric interpolation), one solver per
 * thread, then every owned vertex's separator distance functions fitted,
 * and their coefficients compacted. */
#include "pipeline.h"

#include "../fit/fit.h"
#include "../geodesic/geodesic_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

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
    const gs__tree_node *node;
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

static int job_prepare(gs__builder *b, const gs__tree_node *nd, uint32_t nthreads, node_job *j, gs_error *err)
{
    const gs__tree *t = b->tree;
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
        const gs__sep_curve *cv = &t->curves[nd->curve_start + c];
        for (uint32_t k = 0; k < cv->n_samples; ++k) {
            const gs__sep_sample *s = &t->samples[cv->sample_start + k];
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

/* Fields are solved in chunks of CHUNK sources (one batched solve for the
 * heat method). Chunks are fixed by the source order alone, never by the
 * thread count, so the result does not depend on it. */
enum { CHUNK = 16 };

/* Sources per block for a node with nown owned vertices: a block of fields
 * (n_block x n_owned doubles, per_source per source) fits in
 * field_memory_mib; at least a chunk. */
static uint32_t block_sources(const gs__builder *b, uint32_t nown, uint32_t per_source)
{
    size_t bytes = (size_t)(b->opt->field_memory_mib ? b->opt->field_memory_mib : 384) << 20;
    size_t k = bytes / ((size_t)(nown ? nown : 1) * per_source * sizeof(double));
    k = k / CHUNK * CHUNK;
    return k < CHUNK ? CHUNK : (k > (1u << 20) ? (1u << 20) : (uint32_t)k);
}

/* Solve one field per source src[0..n) (patch-local) with the node's
 * per-thread solvers and store source k's distances to the owned vertices
 * in F[col[k] * nown ..) (col NULL: column k). */
static int solve_block(gs__builder *b, node_job *j, const gs_source *src, uint32_t n, const uint32_t *col, double *F,
                       gs_error *err)
{
    uint32_t nl = gs_patch_num_vertices(j->patch), nown = j->node->n_verts;
    uint32_t nchunks = (n + CHUNK - 1) / CHUNK;
    int rc = GS_OK;
    /* one factorisation for all threads (heat): the first solver here, the
     * others clone it */
    if (!j->solver[0] && b->dgg && (rc = gs__solver_dgg_view(b->dgg, j->patch, &j->solver[0], err))) return rc;
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
static int fields_from_samples(gs__builder *b, node_job *j, gs_error *err)
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
static int fields_from_vertices(gs__builder *b, node_job *j, gs_error *err)
{
    const gs__topo *pt = j->patch->topo;
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
static int fit_node(gs__builder *b, node_job *j, uint32_t node_id, gs_error *err)
{
    const gs__tree *t = b->tree;
    const gs__tree_node *nd = j->node;
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
        const gs__sep_curve *cv = &t->curves[nd->curve_start + c];
        for (uint32_t k = 0; k < cv->n_samples; ++k) {
            double s = t->samples[cv->sample_start + k].s;
            u_all[j->sample_first[c] + k] =
                cv->closed ? -1.0 + 2.0 * k / cv->n_samples : -1.0 + 2.0 * s / cv->length;
        }
        if (!cv->closed) u_all[j->sample_first[c] + cv->n_samples - 1] = 1.0;
    }
    gs__fit_options fo;
    gs__fit_options_default(&fo);
    fo.m_max = b->opt->mmax;
    fo.tol = gs__fit_tol_at_depth(b->opt->tol, nd->depth);
    int rc = GS_OK;
    uint64_t n_fun = 0, n_mixed = 0, n_over = 0, n_uncert = 0;
    double worst_fit = 0;
    double deg_sum = 0, err_sum = 0;
#pragma omp parallel num_threads(j->nthreads) reduction(+ : n_fun, n_mixed, deg_sum, n_over, err_sum, n_uncert) reduction(max : worst_fit)
    {
        gs__fit_work *w = NULL;
        gs_error e;
        uint32_t max_ns = 0;
        for (uint32_t c = 0; c < nc; ++c)
            if (t->curves[nd->curve_start + c].n_samples > max_ns) max_ns = t->curves[nd->curve_start + c].n_samples;
        double *d = gs__malloc(max_ns, sizeof *d);
        int my = d ? gs__fit_work_create(max_ns, &fo, &w, &e) : GS_ENOMEM;
        gs__fit_result res;
#pragma omp for schedule(dynamic, 64)
        for (uint32_t i = 0; i < nd->n_verts; ++i) {
            if (my) continue;
            uint32_t x = t->verts[nd->vert_start + i];
            double *slot = arena + (size_t)i * cap_total;
            for (uint32_t c = 0; c < nc && !my; ++c) {
                const gs__sep_curve *cv = &t->curves[nd->curve_start + c];
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
                gs__fun *f = &b->funs[b->fun_start[x] + nd->curve_prefix + c];
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
                    my = gs__fit_distance(w, u_all + j->sample_first[c], d, n, cv->closed, cv->length / 2, &res, &e);
                    if (my) break;
                    *f = res.fun;
                    memcpy(slot, res.coef, (res.fun.degree + 1) * sizeof *slot);
                    f->coef = slot;
                    deg_sum += res.fun.degree;
                    err_sum += res.mean_rel_err;
                    n_over += res.mean_rel_err > fo.tol;
                    double worst = fmax(res.max_rel_err, res.cert_err);
                    b->fun_err[f - b->funs] = (float)worst;
                    b->fun_abs[f - b->funs] = (float)res.abs_err;
                    n_uncert += worst >= GS_FIT_MAX_ERR;
                    worst_fit = fmax(worst_fit, worst);
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
        gs__fit_work_free(w);
        free(d);
    }
    free(u_all);
    b->node_fits[node_id] = (gs__node_fits){n_fun, n_mixed, n_over, n_uncert, worst_fit, deg_sum, err_sum};
    return rc;
}

/* Shrink node_id's arena to the coefficients its functions use (the fits
 * reserve room for degree mmax) and repoint them. */
static int compact_arena(gs__builder *b, const gs__tree_node *nd, uint32_t node_id, gs_error *err)
{
    const gs__tree *t = b->tree;
    size_t used = 0;
    for (uint32_t i = 0; i < nd->n_verts; ++i) {
        const gs__fun *f = &b->funs[b->fun_start[t->verts[nd->vert_start + i]] + nd->curve_prefix];
        for (uint32_t c = 0; c < nd->n_curves; ++c)
            if (f[c].coef) used += f[c].degree + 1;
    }
    double *arena = gs__malloc(used + 1, sizeof *arena);
    if (!arena) return gs__fail(err, GS_ENOMEM, "out of memory for node %u's functions", node_id);
    size_t k = 0;
    for (uint32_t i = 0; i < nd->n_verts; ++i) {
        gs__fun *f = &b->funs[b->fun_start[t->verts[nd->vert_start + i]] + nd->curve_prefix];
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
int gs__pipe_process_node(gs__builder *b, uint32_t i, uint32_t nthreads, double *t_fields, double *t_fits,
                          gs_error *err)
{
    const gs__tree_node *nd = &b->tree->nodes[i];
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
