/* heat_setup.c - the heat method's solver set-up: the intrinsic Delaunay
 * triangulation, the heat and Poisson matrices and their factorisations, the
 * refined mesh and its sources; create, clone, destroy (see heat_internal.h). */
#include "heat_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- intrinsic geometry ------------------------------------------------- */

/* Area of a triangle from its lengths (Kahan's stable Heron formula). */
static double tri_area(double a, double b, double c)
{
    double s; /* sort a >= b >= c */
    if (a < b) { s = a; a = b; b = s; }
    if (b < c) { s = b; b = c; c = s; }
    if (a < b) { s = a; a = b; b = s; }
    double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    return q > 0 ? 0.25 * sqrt(q) : 0.0;
}

/* cot of the angle opposite length a in the triangle (a, b, c). */
static double cot_opposite(double a, double b, double c)
{
    double A = tri_area(a, b, c);
    if (!(A > 0)) return 0.0;
    return (b * b + c * c - a * a) / (4.0 * A);
}

/* Sum of the cotangents opposite interior edge h (in both faces). */
static double edge_cot_sum(const heat_state *s, uint32_t h)
{
    uint32_t g = s->iopp[h];
    double a = cot_opposite(s->ilen[h], s->ilen[gs__next(h)], s->ilen[gs__prev(h)]);
    double b = cot_opposite(s->ilen[g], s->ilen[gs__next(g)], s->ilen[gs__prev(g)]);
    return a + b;
}

static void set_slot(heat_state *s, uint32_t slot, uint32_t twin, double len)
{
    s->iopp[slot] = twin;
    s->ilen[slot] = len;
    if (twin != GS_NONE) s->iopp[twin] = slot;
}

/* Flip interior edge h (from a to b; c opposite in its face, d opposite in
 * the twin's face). Returns 0 if the configuration is degenerate. */
static int flip_edge(heat_state *s, uint32_t h)
{
    uint32_t g = s->iopp[h];
    uint32_t f1 = h / 3, f2 = g / 3;
    if (f1 == f2) return 0;
    uint32_t nh = gs__next(h), ph = gs__prev(h), ng = gs__next(g), pg = gs__prev(g);
    uint32_t a = s->itri[h], b = s->itri[nh], c = s->itri[ph], d = s->itri[pg];
    if (c == d) return 0;
    uint32_t o_nh = s->iopp[nh], o_ph = s->iopp[ph], o_ng = s->iopp[ng], o_pg = s->iopp[pg];
    uint32_t outer[4] = {o_nh, o_ph, o_ng, o_pg};
    for (int k = 0; k < 4; ++k)
        if (outer[k] != GS_NONE && (outer[k] / 3 == f1 || outer[k] / 3 == f2)) return 0;
    double l_ab = s->ilen[h], l_bc = s->ilen[nh], l_ca = s->ilen[ph];
    double l_ad = s->ilen[ng], l_db = s->ilen[pg];
    /* lay out a = (0,0), b = (l_ab, 0), c above, d below */
    double cx = (l_ab * l_ab + l_ca * l_ca - l_bc * l_bc) / (2 * l_ab);
    double cy = sqrt(fmax(l_ca * l_ca - cx * cx, 0.0));
    double dx = (l_ab * l_ab + l_ad * l_ad - l_db * l_db) / (2 * l_ab);
    double dy = -sqrt(fmax(l_ad * l_ad - dx * dx, 0.0));
    double l_cd = hypot(cx - dx, cy - dy);
    if (!(l_cd > 0) || !isfinite(l_cd)) return 0;
    /* new faces: f1 = (d, c, a), f2 = (c, d, b); h and g are the diagonal */
    s->itri[h] = d; s->itri[nh] = c; s->itri[ph] = a;
    s->itri[g] = c; s->itri[ng] = d; s->itri[pg] = b;
    s->iopp[h] = g; s->iopp[g] = h;
    s->ilen[h] = s->ilen[g] = l_cd;
    set_slot(s, nh, o_ph, l_ca); /* c -> a */
    set_slot(s, ph, o_ng, l_ad); /* a -> d */
    set_slot(s, ng, o_pg, l_db); /* d -> b */
    set_slot(s, pg, o_nh, l_bc); /* b -> c */
    return 1;
}

static int make_intrinsic_delaunay(heat_state *s, gs_error *err)
{
    const gs__topo *t = s->t;
    size_t nh = 3 * (size_t)s->nf;
    memcpy(s->itri, t->tri, nh * sizeof *s->itri);
    memcpy(s->iopp, t->opp, nh * sizeof *s->iopp);
    memcpy(s->ilen, t->len, nh * sizeof *s->ilen);
    /* mollification (Sharp & Crane 2020) */
    double eps = 1e-5 * s->h_mean, delta = 0;
    for (uint32_t f = 0; f < s->nf; ++f)
        for (int i = 0; i < 3; ++i) {
            double a = s->ilen[3 * f + i], b = s->ilen[3 * f + (i + 1) % 3],
                   c = s->ilen[3 * f + (i + 2) % 3];
            delta = fmax(delta, eps - (b + c - a));
        }
    if (delta > 0)
        for (size_t h = 0; h < nh; ++h) s->ilen[h] += delta;
    /* flip non-Delaunay edges: a stack of half-edge slots */
    uint32_t *stack = gs__malloc(nh ? nh : 1, sizeof *stack);
    uint8_t *queued = gs__calloc(nh ? nh : 1, 1);
    if (!stack || !queued) {
        free(stack);
        free(queued);
        return gs__fail(err, GS_ENOMEM, "out of memory building the intrinsic triangulation");
    }
    size_t top = 0;
    for (size_t h = 0; h < nh; ++h)
        if (s->iopp[h] != GS_NONE && h < s->iopp[h]) {
            stack[top++] = (uint32_t)h;
            queued[h] = 1;
        }
    uint64_t max_flips = 50 * (uint64_t)nh + 1000;
    while (top && s->n_flips < max_flips) {
        uint32_t h = stack[--top];
        queued[h] = 0;
        if (s->iopp[h] == GS_NONE) continue;
        if (edge_cot_sum(s, h) >= -1e-10) continue;
        if (!flip_edge(s, h)) continue;
        s->n_flips++;
        uint32_t g = s->iopp[h];
        uint32_t around[4] = {gs__next(h), gs__prev(h), gs__next(g), gs__prev(g)};
        for (int k = 0; k < 4; ++k) {
            uint32_t e = around[k];
            if (s->iopp[e] == GS_NONE) continue;
            if (!queued[e] && top < nh) {
                stack[top++] = e;
                queued[e] = 1;
            }
        }
    }
    free(stack);
    free(queued);
    return GS_OK;
}

/* ---- matrices ----------------------------------------------------------- */

static uint32_t comp_find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

static void build_geometry(heat_state *s)
{
    memset(s->mass, 0, s->nv * sizeof *s->mass);
    for (uint32_t f = 0; f < s->nf; ++f) {
        const double *l = s->ilen + 3 * (size_t)f;
        double A = tri_area(l[0], l[1], l[2]);
        s->area[f] = A;
        for (int i = 0; i < 3; ++i) {
            /* corner i is opposite half-edge (i + 1) % 3 */
            double opp = l[(i + 1) % 3], b = l[i], c = l[(i + 2) % 3];
            s->cot[3 * (size_t)f + i] = A > 0 ? (b * b + c * c - opp * opp) / (4.0 * A) : 0.0;
            s->mass[s->itri[3 * (size_t)f + i]] += A / 3.0;
        }
    }
}

/* Assemble and factor the nv x nv matrix a*M + c*L on the free vertices
 * (map[v] != GS_NONE); a fixed vertex v gets the row and column of the
 * identity (x_v = b_v = 0), its couplings kept as explicit zeros. So every
 * system of a patch has the same sparsity pattern, and the fill-reducing
 * analysis of the first one (like == NULL) is reused by the others. */
static gs__sparse_factor *factor_system(const heat_state *s, const uint32_t *map, double a,
                                       double c, const gs__sparse_factor *like, gs_error *err)
{
    size_t cap = (size_t)s->nv + 3 * (size_t)s->nf * 3;
    uint32_t *ti = gs__malloc(cap, sizeof *ti), *tj = gs__malloc(cap, sizeof *tj);
    double *tx = gs__malloc(cap, sizeof *tx);
    if (!ti || !tj || !tx) {
        free(ti), free(tj), free(tx);
        gs__fail(err, GS_ENOMEM, "out of memory assembling the heat method's matrices");
        return NULL;
    }
    size_t k = 0;
    for (uint32_t v = 0; v < s->nv; ++v) {
        ti[k] = tj[k] = v;
        tx[k++] = map[v] != GS_NONE ? a * s->mass[v] : 1.0;
    }
    /* every half-edge h: weight cot(angle opposite h) / 2 */
    for (size_t h = 0; h < 3 * (size_t)s->nf; ++h) {
        double w = 0.5 * s->cot[3 * (h / 3) + (h % 3 + 2) % 3] * c;
        uint32_t i = s->itri[h], j = s->itri[gs__next((uint32_t)h)];
        int fi = map[i] != GS_NONE, fj = map[j] != GS_NONE;
        if (i == j) continue;
        if (fi) ti[k] = tj[k] = i, tx[k++] = w;
        if (fj) ti[k] = tj[k] = j, tx[k++] = w;
        ti[k] = i > j ? i : j;
        tj[k] = i > j ? j : i;
        tx[k++] = fi && fj ? -w : 0.0;
    }
    gs__sparse_factor *F = gs__sparse_factor_create(s->nv, k, ti, tj, tx, like, err);
    free(ti), free(tj), free(tx);
    return F;
}

/* Per face, from a 2D layout of the intrinsic face (p0 = (0,0), p1 on the
 * x axis, p2 above): the edges opposite each corner rotated by +90 degrees
 * (grad u = sum_i u_i * those / (2 area), only its direction is used) and
 * each corner's divergence weights 0.5 (cot_k (p_j - p_i) + cot_j (p_k -
 * p_i)). Computed once, used by every solve: 12 doubles per face. */
static void build_divergence_geometry(heat_state *s)
{
    for (uint32_t f = 0; f < s->nf; ++f) {
        double *q = s->dgeo + 12 * (size_t)f;
        memset(q, 0, 12 * sizeof *q);
        if (!(s->area[f] > 0)) continue;
        const double *l = s->ilen + 3 * (size_t)f; /* l[0]=|p0p1| l[1]=|p1p2| l[2]=|p2p0| */
        double p[3][2];
        p[0][0] = 0, p[0][1] = 0;
        p[1][0] = l[0], p[1][1] = 0;
        p[2][0] = (l[0] * l[0] + l[2] * l[2] - l[1] * l[1]) / (2 * l[0]);
        p[2][1] = 2 * s->area[f] / l[0];
        const double *ct = s->cot + 3 * (size_t)f;
        for (int i = 0; i < 3; ++i) {
            int j = (i + 1) % 3, k = (i + 2) % 3;
            q[2 * i] = -(p[k][1] - p[j][1]);
            q[2 * i + 1] = p[k][0] - p[j][0];
            q[6 + 2 * i] = 0.5 * (ct[k] * (p[j][0] - p[i][0]) + ct[j] * (p[k][0] - p[i][0]));
            q[7 + 2 * i] = 0.5 * (ct[k] * (p[j][1] - p[i][1]) + ct[j] * (p[k][1] - p[i][1]));
        }
    }
}

/* What a clone owns (and the original too). */
static void free_own(heat_state *s)
{
    gs__sparse_factor_free(s->heat_n);
    gs__sparse_factor_free(s->heat_d);
    gs__sparse_factor_free(s->poisson);
    gs__sparse_factor_free(s->heat_n2);
    gs__sparse_factor_free(s->heat_d2);
    if (s->exact) gs__exact_ops.destroy(s->exact);
    free(s->edist), free(s->fmark);
    free(s->ball_v), free(s->ball_d), free(s->csum);
    free(s->b), free(s->x), free(s->u), free(s->w), free(s->div), free(s->phi), free(s->cmin);
    free(s->kb), free(s->ku), free(s->kx), free(s->kw);
    free(s->rdist), free(s->rsrc);
}

/* The work arrays every solver (original or clone) allocates up front, for
 * s->nv vertices; 0 on failure (free_own frees what was allocated). */
static int alloc_own(heat_state *s)
{
    size_t nv = s->nv ? s->nv : 1;
    int ok = (s->b = gs__malloc(nv, sizeof(double))) && (s->x = gs__malloc(nv, sizeof(double))) &&
             (s->u = gs__malloc(nv, sizeof(double))) && (s->w = gs__malloc(nv, sizeof(double))) &&
             (s->div = gs__malloc(nv, sizeof(double))) && (s->phi = gs__malloc(nv, sizeof(double))) &&
             (s->cmin = gs__malloc(nv, sizeof(double))) && (s->csum = gs__malloc(2 * nv, sizeof(double)));
    if (ok && s->refine) {
        s->rsrc_cap = 16, s->rcap = 1;
        ok = (s->rsrc = gs__malloc(s->rsrc_cap, sizeof *s->rsrc)) && (s->rdist = gs__malloc(nv, sizeof *s->rdist));
    }
    return ok;
}

void gs__heat_destroy(void *state)
{
    heat_state *s = state;
    if (!s) return;
    free_own(s);
    if (!s->base) { /* the original: what its clones share too */
        free(s->vf_start), free(s->vf);
        free(s->itri), free(s->iopp), free(s->ilen), free(s->cot), free(s->area), free(s->dgeo);
        free(s->mass), free(s->comp), free(s->map_n), free(s->map_d), free(s->map_p);
        if (s->refine) gs__topo_free(&s->refined_t);
        free(s->rxyz), free(s->rtri);
    }
    free(s);
}

/* Subdivide t0 `levels` times into s->refined_t (arrays rxyz, rtri). */
static int refine_patch(heat_state *s, const gs__topo *t0, uint32_t levels, gs_error *err)
{
    const gs__topo *cur = t0;
    for (uint32_t l = 0; l < levels; ++l) {
        double *xyz;
        uint32_t *tri, nv, nf;
        int rc = gs__subdivide_arrays(cur, &nv, &xyz, &nf, &tri, err);
        if (l > 0) {
            gs__topo_free(&s->refined_t);
            free(s->rxyz), free(s->rtri);
            s->rxyz = NULL, s->rtri = NULL;
        }
        if (rc) return rc;
        s->rxyz = xyz, s->rtri = tri;
        rc = gs__topo_build(&s->refined_t, nv, xyz, nf, tri, GS_TOPO_ALLOW_NONMANIFOLD_VERTICES, NULL, err);
        if (rc) {
            free(s->rxyz), free(s->rtri);
            s->rxyz = NULL, s->rtri = NULL;
            return rc;
        }
        cur = &s->refined_t;
    }
    return GS_OK;
}

/* A source of the patch as a source of the refined mesh: a vertex keeps its
 * id; a point of face f lies in one of the four faces f becomes at each
 * level (a corner face if one of its coordinates is >= 1/2, else the
 * middle one), with coordinates relative to it; a point that lands on a
 * refined vertex becomes that vertex. */
static gs_source refine_source(const heat_state *s, const gs_source *in)
{
    if (in->face == GS_NONE) return *in;
    uint32_t f = in->face;
    double b0 = in->bary[0], b1 = in->bary[1], b2 = in->bary[2];
    for (uint32_t l = 0; l < s->refine; ++l) {
        uint32_t k;
        double c0, c1, c2;
        if (b0 >= 0.5) k = 0, c0 = 2 * b0 - 1, c1 = 2 * b1, c2 = 2 * b2;
        else if (b1 >= 0.5) k = 1, c0 = 2 * b0, c1 = 2 * b1 - 1, c2 = 2 * b2;
        else if (b2 >= 0.5) k = 2, c0 = 2 * b0, c1 = 2 * b1, c2 = 2 * b2 - 1;
        else k = 3, c0 = 1 - 2 * b2, c1 = 1 - 2 * b0, c2 = 1 - 2 * b1;
        double sum = c0 + c1 + c2;
        b0 = c0 / sum, b1 = c1 / sum, b2 = c2 / sum;
        f = 4 * f + k;
    }
    const uint32_t *c = s->rtri + 3 * (size_t)f;
    if (b0 == 1.0) return gs_source_vertex(c[0]);
    if (b1 == 1.0) return gs_source_vertex(c[1]);
    if (b2 == 1.0) return gs_source_vertex(c[2]);
    return gs_source_point(f, b0, b1, b2);
}

int gs__heat_create(const gs__topo *t, const gs_solver_options *opt, void **state, gs_error *err)
{
    heat_state *s = calloc(1, sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory creating a heat solver");
    s->t0 = t;
    s->nv0 = t->nv;
    if (opt->heat_refine > 0) {
        int rc = refine_patch(s, t, opt->heat_refine, err);
        if (rc) {
            free(s);
            return rc;
        }
        s->refine = opt->heat_refine;
        t = &s->refined_t;
    }
    s->t = t;
    s->nv = t->nv;
    s->nf = t->nf;
    size_t nh = 3 * (size_t)t->nf, nv = t->nv ? t->nv : 1;
    s->itri = gs__malloc(nh + 1, sizeof *s->itri);
    s->iopp = gs__malloc(nh + 1, sizeof *s->iopp);
    s->ilen = gs__malloc(nh + 1, sizeof *s->ilen);
    s->cot = gs__malloc(nh + 1, sizeof *s->cot);
    s->area = gs__malloc(t->nf + 1, sizeof *s->area);
    s->dgeo = gs__malloc(12 * (size_t)t->nf + 1, sizeof *s->dgeo);
    s->mass = gs__malloc(nv, sizeof *s->mass);
    s->comp = gs__malloc(nv, sizeof *s->comp);
    s->map_n = gs__malloc(nv, sizeof *s->map_n);
    s->map_d = gs__malloc(nv, sizeof *s->map_d);
    s->map_p = gs__malloc(nv, sizeof *s->map_p);
    s->vf_start = gs__malloc(nv + 1, sizeof *s->vf_start);
    s->vf = gs__malloc(nh + 1, sizeof *s->vf);
    if (!s->itri || !s->iopp || !s->ilen || !s->cot || !s->area || !s->dgeo || !s->mass || !s->comp ||
        !s->map_n || !s->map_d || !s->map_p || !s->vf_start || !s->vf || !alloc_own(s)) {
        gs__heat_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory creating a heat solver");
    }
    /* mean edge length (each interior edge once) and t = h^2 */
    double sum = 0;
    uint64_t ne = 0;
    for (size_t h = 0; h < nh; ++h)
        if (t->opp[h] == GS_NONE || h < t->opp[h]) sum += t->len[h], ne++;
    s->h_mean = ne ? sum / (double)ne : 1.0;
    /* the time step's h: the mean edge length weighted by area (see
     * heat_internal.h) */
    double area_sum = 0, hw = 0;
    for (uint32_t f = 0; f < t->nf; ++f) {
        const double *l = t->len + 3 * (size_t)f;
        double A = tri_area(l[0], l[1], l[2]);
        area_sum += A, hw += A * (l[0] + l[1] + l[2]) / 3;
    }
    s->h_time = area_sum > 0 ? hw / area_sum : s->h_mean;
    s->t_step = opt->heat_time * s->h_time * s->h_time;
    s->r_ball = HEAT_EXACT_START * s->h_mean;

    int rc = make_intrinsic_delaunay(s, err);
    if (rc) {
        gs__heat_destroy(s);
        return rc;
    }
    build_geometry(s);
    build_divergence_geometry(s);
    /* intrinsic faces around each vertex */
    memset(s->vf_start, 0, ((size_t)s->nv + 1) * sizeof *s->vf_start);
    for (size_t h = 0; h < nh; ++h) s->vf_start[s->itri[h] + 1]++;
    for (uint32_t v = 0; v < s->nv; ++v) s->vf_start[v + 1] += s->vf_start[v];
    for (size_t h = 0; h < nh; ++h) s->vf[s->vf_start[s->itri[h]]++] = (uint32_t)(h / 3);
    for (uint32_t v = s->nv; v > 0; --v) s->vf_start[v] = s->vf_start[v - 1];
    s->vf_start[0] = 0;

    /* connected components (vertices sharing a face), union-find in comp */
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = v;
    for (uint32_t f = 0; f < s->nf; ++f) {
        uint32_t r0 = comp_find(s->comp, t->tri[3 * (size_t)f]);
        for (int i = 1; i < 3; ++i) {
            uint32_t r = comp_find(s->comp, t->tri[3 * (size_t)f + i]);
            if (r == r0) continue;
            uint32_t lo = r < r0 ? r : r0, hi = r < r0 ? r0 : r;
            s->comp[hi] = lo;
            r0 = lo;
        }
    }
    uint8_t *boundary = (uint8_t *)s->b; /* scratch: b holds 8*nv bytes */
    memset(boundary, 0, s->nv);
    for (size_t h = 0; h < nh; ++h)
        if (s->iopp[h] == GS_NONE) {
            boundary[s->itri[h]] = 1;
            boundary[s->itri[gs__next((uint32_t)h)]] = 1;
        }
    uint8_t *used = boundary + s->nv;
    memset(used, 0, s->nv);
    for (size_t h = 0; h < nh; ++h) used[t->tri[h]] = 1;
    uint32_t nn = 0, nd = 0, np = 0, nb = 0;
    /* unknowns: every referenced vertex (Neumann heat), the interior ones
     * (Dirichlet heat) */
    for (uint32_t v = 0; v < s->nv; ++v) {
        s->map_n[v] = s->map_d[v] = s->map_p[v] = GS_NONE;
        if (!used[v]) continue;
        s->map_n[v] = nn++;
        if (!boundary[v]) s->map_d[v] = nd++;
        else nb++;
    }
    /* compact component ids: roots are the smallest vertex of each set */
    uint32_t *cid = s->map_p; /* temporarily: root -> component id */
    for (uint32_t v = 0; v < s->nv; ++v) cid[v] = GS_NONE;
    s->n_comp = 0;
    for (uint32_t v = 0; v < s->nv; ++v) {
        if (!used[v]) continue;
        uint32_t r = comp_find(s->comp, v);
        if (cid[r] == GS_NONE) cid[r] = s->n_comp++;
    }
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = comp_find(s->comp, v);
    for (uint32_t v = 0; v < s->nv; ++v) s->comp[v] = used[v] ? cid[s->comp[v]] : GS_NONE;
    /* the Poisson pin of a component: its first vertex */
    uint8_t *pinned_comp = (uint8_t *)s->cmin; /* n_comp <= nv bytes */
    memset(pinned_comp, 0, s->nv);
    for (uint32_t v = 0; v < s->nv; ++v) {
        s->map_p[v] = GS_NONE;
        if (!used[v]) continue;
        if (!pinned_comp[s->comp[v]]) {
            pinned_comp[s->comp[v]] = 1;
            continue;
        }
        s->map_p[v] = np++;
    }

    gs_error e2 = {0, ""}, *e = err ? err : &e2;
    (void)nn, (void)nd, (void)np;
    double t2 = HEAT_T2_RATIO * s->t_step;
    s->heat_n = factor_system(s, s->map_n, 1.0, s->t_step, NULL, e);
    if (s->heat_n && nb > 0)
        s->heat_d = factor_system(s, s->map_d, 1.0, s->t_step, s->heat_n, e);
    if (s->heat_n && (nb == 0 || s->heat_d))
        s->heat_n2 = factor_system(s, s->map_n, 1.0, t2, s->heat_n, e);
    if (s->heat_n2 && nb > 0)
        s->heat_d2 = factor_system(s, s->map_d, 1.0, t2, s->heat_n, e);
    if (s->heat_n2 && (nb == 0 || s->heat_d2))
        s->poisson = factor_system(s, s->map_p, 0.0, 1.0, s->heat_n, e);
    if (!s->poisson) {
        gs__heat_destroy(s);
        return e->status ? e->status : GS_EINTERNAL;
    }
    *state = s;
    return GS_OK;
}

/* A solver for another thread: the same fields, bit for bit, from base's
 * factorisations (views with their own workspace) and geometry; only the
 * work arrays are new. base must outlive it. */
int gs__heat_clone(const void *state, void **out, gs_error *err)
{
    const heat_state *src = state;
    heat_state *s = malloc(sizeof *s);
    if (!s) return gs__fail(err, GS_ENOMEM, "out of memory cloning a heat solver");
    *s = *src;
    s->base = src->base ? src->base : src;
    s->heat_n = s->heat_d = s->poisson = s->heat_n2 = s->heat_d2 = NULL;
    s->b = s->x = s->u = s->w = s->div = s->phi = s->cmin = s->csum = NULL;
    s->kb = s->ku = s->kx = s->kw = NULL, s->kcap = 0;
    s->exact = NULL, s->edist = NULL, s->fmark = NULL, s->stamp = 0;
    s->ball_v = NULL, s->ball_d = NULL, s->ball_n = s->ball_cap = 0;
    s->rdist = NULL, s->rsrc = NULL, s->rcap = s->rsrc_cap = 0;
    if (!alloc_own(s)) {
        gs__heat_destroy(s);
        return gs__fail(err, GS_ENOMEM, "out of memory cloning a heat solver");
    }
    gs__sparse_factor *const *from[5] = {&src->heat_n, &src->heat_d, &src->poisson, &src->heat_n2, &src->heat_d2};
    gs__sparse_factor **to[5] = {&s->heat_n, &s->heat_d, &s->poisson, &s->heat_n2, &s->heat_d2};
    for (int i = 0; i < 5; ++i)
        if (*from[i] && !(*to[i] = gs__sparse_factor_share(*from[i], err))) {
            gs__heat_destroy(s);
            return err && err->status ? err->status : GS_ENOMEM;
        }
    *out = s;
    return GS_OK;
}

int gs__heat_map_sources(heat_state *s, const gs_source *src, uint32_t n, gs_error *err)
{
    if (n > s->rsrc_cap) {
        gs_source *p = gs__realloc(s->rsrc, n, sizeof *p);
        if (!p) return gs__fail(err, GS_ENOMEM, "out of memory for %u heat sources", n);
        s->rsrc = p, s->rsrc_cap = n;
    }
    for (uint32_t i = 0; i < n; ++i) s->rsrc[i] = refine_source(s, &src[i]);
    return GS_OK;
}
