/* tree.c - the nested bisection tree (paper sec. 2.2, 3.1, 4.1): nodes are
 * split breadth-first until they own at most vmax vertices; each child's
 * patch holds every face of its parent touching a vertex the child owns, so
 * the faces crossed by the separator go to both children (ghost triangles). */
#include "partition_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

void gs__tree_options_default(gs__tree_options *o)
{
    if (!o) return;
    o->vmax = 30;
    o->sample_spacing = 1.0;
    o->smooth_iters = 0; /* level-set curves are smooth; projecting filtered
                          * points back onto the cut edges re-kinks them */
    o->seed = 1;
    o->level_iters = 16;
    /* 0: the samples stay on the separator, the zero level of phi that
     * decides the sides. Filtered samples leave it (inside the strip of
     * crossed faces), and a pair of neighbours on either side then sees no
     * curve between them: answered through a detour (measured on a trefoil
     * tube: near pairs off by up to 172%, 8% without filtering) */
    o->filter_iters = 0;
    o->min_samples = 3;
    o->cut_seeds = 4;
    o->bisector = 1;
    o->level_bias = 1.25;
    o->long_curve = 2.0;
    o->threads = 0;
    o->progress = NULL;
    o->progress_user = NULL;
}

void gs__tree_free(gs__tree *t)
{
    if (!t) return;
    free(t->nodes);
    free(t->curves);
    free(t->samples);
    free(t->cross);
    free(t->faces);
    free(t->verts);
    free(t->leaf_of_vertex);
    free(t);
}

/* Per thread of choose_cut: its own sides, phi and curve output, and the
 * best candidate it has seen (lowest score, then lowest index). */
typedef struct cut_slot {
    uint8_t *side, *best_side;
    double *phi, *best_phi;
    size_t cap_side, cap_best_side, cap_phi, cap_best_phi;
    gs__part_out out;
    double best;
    uint32_t best_k, fail_k;
    int best_valid, rc;
    gs_error err;
} cut_slot;

static void cut_slot_free(cut_slot *s)
{
    free(s->side);
    free(s->best_side);
    free(s->phi);
    free(s->best_phi);
    free(s->out.curves);
    free(s->out.samples);
    free(s->out.cross);
}

typedef struct builder {
    const gs_mesh *mesh;
    const gs__tree_options *opt;
    gs__tree *t;
    size_t cap_nodes, cap_faces;
    gs__part_out out;
    double mean_edge;
    uint32_t *vloc, *floc;     /* mesh-sized maps, GS_NONE outside a node */
    uint32_t *lv, *lf, *tmp;   /* node scratch (grown as needed)          */
    uint8_t *side;
    double *phi;
    size_t cap_lv, cap_lf, cap_tmp, cap_side, cap_phi;
    double long_curve;         /* L of choose_cut (0: plain lengths)      */
    cut_slot *slot;            /* choose_cut's, one per thread, kept and  */
    uint32_t n_slot;           /*   grown across nodes                    */
} builder;

static void builder_free(builder *b)
{
    for (uint32_t t = 0; t < b->n_slot; ++t) cut_slot_free(&b->slot[t]);
    free(b->slot);
    free(b->out.curves);
    free(b->out.samples);
    free(b->out.cross);
    free(b->vloc);
    free(b->floc);
    free(b->lv);
    free(b->lf);
    free(b->tmp);
    free(b->side);
    free(b->phi);
}

#define RESERVE(ptr, cap, need) gs__grow((void **)&(ptr), &(cap), (need), sizeof *(ptr))

/* The root: every referenced vertex, every face. */
static int init_root(builder *b)
{
    const gs_mesh *m = b->mesh;
    gs__tree *t = b->t;
    t->verts = gs__malloc(m->nv ? m->nv : 1, sizeof *t->verts);
    t->leaf_of_vertex = gs__malloc(m->nv ? m->nv : 1, sizeof *t->leaf_of_vertex);
    b->vloc = gs__malloc(m->nv ? m->nv : 1, sizeof *b->vloc);
    b->floc = gs__malloc(m->nf ? m->nf : 1, sizeof *b->floc);
    if (!t->verts || !t->leaf_of_vertex || !b->vloc || !b->floc) return GS_ENOMEM;
    if (RESERVE(t->faces, b->cap_faces, m->nf) || RESERVE(t->nodes, b->cap_nodes, 1))
        return GS_ENOMEM;
    for (uint32_t v = 0; v < m->nv; ++v) {
        b->vloc[v] = GS_NONE;
        t->leaf_of_vertex[v] = GS_NONE;
        if (!(m->topo.vflag[v] & GS_V_UNUSED)) t->verts[t->n_verts++] = v;
    }
    for (uint32_t f = 0; f < m->nf; ++f) {
        b->floc[f] = GS_NONE;
        t->faces[f] = f;
    }
    t->n_face_refs = m->nf;
    t->nodes[0] = (gs__tree_node){GS_NONE, {GS_NONE, GS_NONE}, 0, 0, m->nf, 0, t->n_verts,
                                 0, 0, 0};
    t->n_nodes = 1;
    return GS_OK;
}

/* Local view of node id: owned vertices first, then ghosts. */
static int load_node(builder *b, uint32_t id, gs__part_node *nd)
{
    const gs__tree_node *n = &b->t->nodes[id];
    const uint32_t *tri = b->mesh->tri;
    size_t max_lv = (size_t)n->n_verts + 3 * (size_t)n->n_faces;
    if (RESERVE(b->lf, b->cap_lf, n->n_faces) || RESERVE(b->lv, b->cap_lv, max_lv))
        return GS_ENOMEM;
    memcpy(b->lf, b->t->faces + n->face_start, (size_t)n->n_faces * sizeof *b->lf);
    uint32_t nl = 0;
    for (uint32_t i = 0; i < n->n_verts; ++i) {
        uint32_t v = b->t->verts[n->vert_start + i];
        b->vloc[v] = nl;
        b->lv[nl++] = v;
    }
    for (uint32_t i = 0; i < n->n_faces; ++i) {
        b->floc[b->lf[i]] = i;
        for (int k = 0; k < 3; ++k) {
            uint32_t v = tri[3 * (size_t)b->lf[i] + k];
            if (b->vloc[v] != GS_NONE) continue;
            b->vloc[v] = nl;
            b->lv[nl++] = v;
        }
    }
    if (RESERVE(b->side, b->cap_side, nl ? nl : 1) || RESERVE(b->phi, b->cap_phi, nl ? nl : 1))
        return GS_ENOMEM;
    *nd = (gs__part_node){b->mesh, id, n->n_verts, nl, n->n_faces, b->lv, b->lf,
                         b->vloc, b->floc, b->side, b->phi, 0};
    return GS_OK;
}

static void unload_node(builder *b, const gs__part_node *nd)
{
    for (uint32_t i = 0; i < nd->nl; ++i) b->vloc[nd->lv[i]] = GS_NONE;
    for (uint32_t i = 0; i < nd->nf; ++i) b->floc[nd->faces[i]] = GS_NONE;
}

/* Faces of P(N) with a corner owned on side s, appended to tree faces. */
static uint32_t child_faces(builder *b, const gs__part_node *nd, uint8_t s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < nd->nf; ++i) {
        const uint32_t *c = b->mesh->tri + 3 * (size_t)nd->faces[i];
        int has = 0;
        for (int k = 0; k < 3; ++k) {
            uint32_t l = nd->vloc[c[k]];
            has |= l < nd->no && nd->side[l] == s;
        }
        if (has) b->t->faces[b->t->n_face_refs + n++] = nd->faces[i];
    }
    b->t->n_face_refs += n;
    return n;
}

/* Reorder the node's vertex range (side 0 first) and add both children. */
static int make_children(builder *b, uint32_t id, const gs__part_node *nd)
{
    gs__tree *t = b->t;
    if (RESERVE(t->nodes, b->cap_nodes, (size_t)t->n_nodes + 2) ||
        RESERVE(t->faces, b->cap_faces, t->n_face_refs + 2 * (size_t)nd->nf) ||
        RESERVE(b->tmp, b->cap_tmp, nd->no))
        return GS_ENOMEM;
    gs__tree_node *n = &t->nodes[id];
    uint32_t *range = t->verts + n->vert_start, n0 = 0;
    for (uint8_t s = 0; s < 2; ++s)
        for (uint32_t i = 0; i < nd->no; ++i)
            if (nd->side[i] == s) b->tmp[n0++] = nd->lv[i];
    memcpy(range, b->tmp, (size_t)nd->no * sizeof *range);
    n0 = 0;
    for (uint32_t i = 0; i < nd->no; ++i) n0 += nd->side[i] == 0;
    for (uint8_t s = 0; s < 2; ++s) {
        uint32_t c = t->n_nodes++;
        size_t fs = t->n_face_refs;
        uint32_t nf = child_faces(b, nd, s);
        t->nodes[c] = (gs__tree_node){id, {GS_NONE, GS_NONE}, n->depth + 1, (uint32_t)fs, nf,
                                     n->vert_start + (s ? n0 : 0), s ? nd->no - n0 : n0,
                                     0, 0, n->curve_prefix + n->n_curves};
        n->child[s] = c;
    }
    return GS_OK;
}

/* One candidate cut of node nd: sides by METIS with `seed`, then the
 * diffusion level set, and with `bisector` the power bisector of its two
 * sides (split.c). */
static int candidate_sides(builder *b, gs__part_node *nd, uint32_t seed, int bisector,
                           gs_error *err)
{
    nd->phi_valid = 0;
    int rc = gs__part_sides(nd, seed, b->mean_edge, err);
    if (rc == GS_OK) rc = gs__part_level_set(nd, b->opt->level_iters, err);
    if (rc == GS_OK && bisector) rc = gs__part_bisector(nd, 1, err);
    return rc;
}

/* The candidate cuts (METIS seeds seed, seed+1, ... x diffusion level set /
 * power bisector): each one's curves are built into the output, measured
 * and taken back out; the sides and phi of the one whose curves score
 * lowest are left in nd. A curve of length l scores l (1 + l / L), L =
 * long_curve * mean edge * sqrt(vertices) (about twice the side of a square
 * of the mesh's area): one long curve needs a higher degree than two curves
 * of half its length together (it can exceed mmax), so long ones pay more.
 * Level-set candidates' scores are multiplied by level_bias. */
/* Patches with more vertices try one METIS seed (both smoothings): the tree
 * stage is sequential, and 8 candidates per node over a 1M-vertex mesh's top
 * levels cost minutes. */
#define FEW_CANDIDATES_ABOVE 200000u

/* Candidate k (seed index k / nvar; the bisector variant first) in slot s. */
static void try_candidate(builder *b, const gs__part_node *nd, uint32_t k, int nvar, cut_slot *s)
{
    gs__part_node c = *nd;
    c.side = s->side;
    c.phi = s->phi;
    int bis = nvar == 2 ? 1 - (int)(k % 2) : 0;
    s->out.n_curves = s->out.n_samples = s->out.n_cross = 0;
    int rc = candidate_sides(b, &c, b->opt->seed + k / (uint32_t)nvar, bis, &s->err);
    if (rc == GS_OK) rc = gs__part_curves(&c, b->opt, b->mean_edge, &s->out, &s->err);
    if (rc) {
        if (s->rc == GS_OK || k < s->fail_k) s->rc = rc, s->fail_k = k;
        return;
    }
    double len = 0;
    for (size_t i = 0; i < s->out.n_curves; ++i) {
        double l = s->out.curves[i].length;
        len += b->long_curve > 0 ? l * (1 + l / b->long_curve) : l;
    }
    if (!bis) len *= b->opt->level_bias;
    if (len < s->best || (len == s->best && k < s->best_k)) {
        s->best = len;
        s->best_k = k;
        memcpy(s->best_side, c.side, nd->nl * sizeof *c.side);
        memcpy(s->best_phi, c.phi, nd->nl * sizeof *c.phi);
        s->best_valid = c.phi_valid;
    }
}

static int choose_cut(builder *b, gs__part_node *nd, gs_error *err)
{
    uint32_t nseeds = b->opt->cut_seeds ? b->opt->cut_seeds : 1;
    if (nd->nl > FEW_CANDIDATES_ABOVE) nseeds = 1;
    int nvar = b->opt->bisector && b->opt->level_iters ? 2 : 1;
    uint32_t ncand = nseeds * (uint32_t)nvar;
    if (ncand == 1) return candidate_sides(b, nd, b->opt->seed, 0, err);
    /* Candidates are independent: each thread tries some in its own slot
     * (METIS calls are serialised in split.c). The winner is the lowest
     * (score, index), so the tree does not depend on the thread count. */
    uint32_t nt = b->opt->threads ? b->opt->threads : (uint32_t)omp_get_max_threads();
    if (nt > ncand) nt = ncand;
    if (nt < 1) nt = 1;
    size_t nl = nd->nl ? nd->nl : 1;
    int rc = GS_OK;
    if (nt > b->n_slot) {
        cut_slot *p = gs__realloc(b->slot, nt, sizeof *p);
        if (p) {
            memset(p + b->n_slot, 0, (nt - b->n_slot) * sizeof *p);
            b->slot = p, b->n_slot = nt;
        } else {
            rc = GS_ENOMEM;
        }
    }
    cut_slot *slot = b->slot;
    for (uint32_t t = 0; rc == GS_OK && t < nt; ++t) {
        cut_slot *c = &slot[t];
        if (RESERVE(c->side, c->cap_side, nl) || RESERVE(c->best_side, c->cap_best_side, nl) ||
            RESERVE(c->phi, c->cap_phi, nl) || RESERVE(c->best_phi, c->cap_best_phi, nl))
            rc = GS_ENOMEM;
        c->best = INFINITY;
        c->best_k = c->fail_k = UINT32_MAX;
        c->best_valid = 0;
        c->rc = GS_OK;
    }
    if (rc == GS_OK) {
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
        for (uint32_t k = 0; k < ncand; ++k) try_candidate(b, nd, k, nvar, &slot[omp_get_thread_num()]);
        uint32_t win = UINT32_MAX, fail = UINT32_MAX;
        for (uint32_t t = 0; t < nt; ++t) {
            if (slot[t].rc && (fail == UINT32_MAX || slot[t].fail_k < slot[fail].fail_k)) fail = t;
            if (slot[t].best_k != UINT32_MAX &&
                (win == UINT32_MAX || slot[t].best < slot[win].best ||
                 (slot[t].best == slot[win].best && slot[t].best_k < slot[win].best_k)))
                win = t;
        }
        if (fail != UINT32_MAX) {
            rc = slot[fail].rc;
            if (err) *err = slot[fail].err;
        } else if (win == UINT32_MAX) {
            rc = gs__fail(err, GS_EINTERNAL, "no candidate cut for tree node %u", nd->id);
        } else {
            memcpy(nd->side, slot[win].best_side, nd->nl * sizeof *nd->side);
            memcpy(nd->phi, slot[win].best_phi, nd->nl * sizeof *nd->phi);
            nd->phi_valid = slot[win].best_valid;
        }
    } else {
        rc = gs__fail(err, GS_ENOMEM, "out of memory building the tree");
    }
    return rc;
}

static int split_node(builder *b, uint32_t id, gs_error *err)
{
    gs__part_node nd;
    b->t->nodes[id].curve_start = (uint32_t)b->out.n_curves;
    if (b->t->nodes[id].n_verts <= b->opt->vmax) return GS_OK;
    if (load_node(b, id, &nd)) return gs__fail(err, GS_ENOMEM, "out of memory building the tree");
    int rc = choose_cut(b, &nd, err);
    if (rc == GS_OK) rc = gs__part_curves(&nd, b->opt, b->mean_edge, &b->out, err);
    if (rc == GS_OK) {
        b->t->nodes[id].n_curves = (uint32_t)(b->out.n_curves - b->t->nodes[id].curve_start);
        if (make_children(b, id, &nd)) rc = gs__fail(err, GS_ENOMEM, "out of memory building the tree");
    }
    unload_node(b, &nd);
    return rc;
}

static void finish_stats(gs__tree *t)
{
    double sum = 0;
    uint32_t n_sep = 0;
    for (uint32_t i = 0; i < t->n_nodes; ++i) {
        const gs__tree_node *n = &t->nodes[i];
        n_sep += n->n_curves > 0;
        if (n->child[0] != GS_NONE) continue;
        t->n_leaves++;
        sum += (double)n->depth * n->n_verts;
        if (n->depth > t->max_depth) t->max_depth = n->depth;
        for (uint32_t k = 0; k < n->n_verts; ++k) t->leaf_of_vertex[t->verts[n->vert_start + k]] = i;
    }
    t->avg_leaf_depth = t->n_verts ? sum / t->n_verts : 0;
    t->avg_curves_per_separator = n_sep ? (double)t->n_curves / n_sep : 0;
    t->avg_samples_per_curve = t->n_curves ? (double)t->n_samples / t->n_curves : 0;
}

/* Move the curve arrays into the tree and trim the growable ones. */
static int take_output(builder *b)
{
    gs__tree *t = b->t;
    if (b->out.n_samples > UINT32_MAX || b->out.n_cross > UINT32_MAX) return GS_ELIMIT;
    t->curves = b->out.curves;
    t->samples = b->out.samples;
    t->cross = b->out.cross;
    t->n_curves = (uint32_t)b->out.n_curves;
    t->n_samples = (uint32_t)b->out.n_samples;
    t->n_cross = (uint32_t)b->out.n_cross;
    b->out.curves = NULL;
    b->out.samples = NULL;
    b->out.cross = NULL;
    void *p = gs__realloc(t->faces, t->n_face_refs ? t->n_face_refs : 1, sizeof *t->faces);
    if (p) t->faces = p;
    p = gs__realloc(t->nodes, t->n_nodes, sizeof *t->nodes);
    if (p) t->nodes = p;
    return GS_OK;
}

int gs__tree_build(const gs_mesh *mesh, const gs__tree_options *opt, gs__tree **out,
                  gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs__tree_build: out is NULL");
    *out = NULL;
    gs__tree_options def;
    gs__tree_options_default(&def);
    if (!opt) opt = &def;
    if (!mesh) return gs__fail(err, GS_EARG, "gs__tree_build: mesh is NULL");
    if (opt->vmax < 1) return gs__fail(err, GS_EARG, "gs__tree_build: vmax must be >= 1");
    if (!(opt->level_bias > 0) || opt->level_bias > 1e6)
        return gs__fail(err, GS_EARG, "gs__tree_build: level_bias %g out of range", opt->level_bias);
    if (!(opt->long_curve >= 0) || opt->long_curve > 1e6)
        return gs__fail(err, GS_EARG, "gs__tree_build: long_curve %g out of range", opt->long_curve);
    if (opt->threads > GS_MAX_THREADS)
        return gs__fail(err, GS_EARG, "gs__tree_build: threads %u out of range", opt->threads);
    if (opt->cut_seeds > 1024)
        return gs__fail(err, GS_EARG, "gs__tree_build: cut_seeds %u out of range", opt->cut_seeds);
    if (opt->min_samples > (1u << 20))
        return gs__fail(err, GS_EARG, "gs__tree_build: min_samples %u out of range", opt->min_samples);
    if (!(opt->sample_spacing > 0) || opt->sample_spacing > 1e6)
        return gs__fail(err, GS_EARG, "gs__tree_build: sample_spacing %g out of range",
                        opt->sample_spacing);
    builder b = {.mesh = mesh, .opt = opt};
    b.mean_edge = mesh->report.mean_edge > 0 ? mesh->report.mean_edge : 1.0;
    b.t = gs__calloc(1, sizeof *b.t);
    int rc = b.t ? init_root(&b) : GS_ENOMEM;
    if (rc) rc = gs__fail(err, rc, "out of memory building the tree");
    if (rc == GS_OK) b.long_curve = opt->long_curve * b.mean_edge * sqrt((double)b.t->n_verts);
    /* progress: each level of the tree handles about every vertex once, and
     * there are about log2(n / vmax) levels */
    double work_total = 0, work_done = 0;
    if (rc == GS_OK && opt->progress) {
        double levels = ceil(log2(fmax(2.0, (double)b.t->n_verts / opt->vmax)));
        work_total = (double)b.t->n_verts * fmax(1.0, levels);
        opt->progress(opt->progress_user, 0);
    }
    for (uint32_t i = 0; rc == GS_OK && i < b.t->n_nodes; ++i) {
        rc = split_node(&b, i, err);
        if (opt->progress && b.t->nodes[i].child[0] != GS_NONE) {
            work_done += b.t->nodes[i].n_verts;
            opt->progress(opt->progress_user, fmin(0.99, work_done / work_total));
        }
    }
    if (rc == GS_OK && (rc = take_output(&b)) != GS_OK)
        rc = gs__fail(err, rc, "tree too large (%zu samples)", b.out.n_samples);
    if (rc == GS_OK) finish_stats(b.t);
    builder_free(&b);
    if (rc) {
        gs__tree_free(b.t);
        return rc;
    }
    *out = b.t;
    return GS_OK;
}
