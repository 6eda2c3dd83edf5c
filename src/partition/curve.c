/* curve.c - smooth separator curves of one node of the nested bisection
 * (paper sec. 4.1): the faces crossed by the cut are chained into paths and
 * loops; each curve is pulled taut between three anchors inside its corridor
 * of crossed faces (funnel algorithm on the unfolded strip), filtered and
 * projected back onto the cut edges, and resampled at regular arc length. */
#include "partition_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A crossing stays this fraction of its edge away from the edge's ends. */
#define EDGE_MARGIN 0.05
/* Level-set crossings keep only this margin: their positions come from a
 * smooth function, and clamping harder would put kinks into the curve. */
#define LEVEL_MARGIN 1e-3
/* Half-width of the smoothing filter, in mean edge lengths. */
#define FILTER_WIDTH 2.0

/* One crossed edge of a curve: va on side 0, vb on side 1 (mesh ids);
 * face is the mesh face the curve enters there (GS_NONE at a path's end). */
typedef struct portal {
    uint32_t va, vb, face;
} portal;

/* Working arrays for one curve, reused for all curves of a node. */
typedef struct curve_work {
    portal *p;      /* np crossings                                       */
    double *t;      /* np positions on the crossed edges                  */
    double *x;      /* 3*np points                                        */
    double *y;      /* 3*np filtered points                               */
    double *s;      /* np+1 arc lengths at the crossings                  */
    double (*a2)[2], (*b2)[2], (*l2)[2], (*r2)[2]; /* unfolded strip      */
    uint32_t *corner;
    uint8_t *corner_side;
    size_t cap;
    uint32_t np;
    int closed;
} curve_work;

static void work_free(curve_work *w)
{
    free(w->p);
    free(w->t);
    free(w->x);
    free(w->y);
    free(w->s);
    free(w->a2);
    free(w->b2);
    free(w->l2);
    free(w->r2);
    free(w->corner);
    free(w->corner_side);
}

static int work_reserve(curve_work *w, size_t n)
{
    if (n <= w->cap) return GS_OK;
    size_t c = w->cap ? w->cap : 64;
    while (c < n) c *= 2;
    void *ptrs[] = {
        realloc(w->p, c * sizeof *w->p),           realloc(w->t, c * sizeof *w->t),
        realloc(w->x, 3 * c * sizeof *w->x),       realloc(w->y, 3 * c * sizeof *w->y),
        realloc(w->s, (c + 1) * sizeof *w->s),     realloc(w->a2, c * sizeof *w->a2),
        realloc(w->b2, c * sizeof *w->b2),         realloc(w->l2, c * sizeof *w->l2),
        realloc(w->r2, c * sizeof *w->r2),         realloc(w->corner, c * sizeof *w->corner),
        realloc(w->corner_side, c)};
    int ok = 1;
    for (size_t i = 0; i < sizeof ptrs / sizeof *ptrs; ++i) ok &= ptrs[i] != NULL;
    /* keep whatever was reallocated so that work_free releases it */
    if (ptrs[0]) w->p = ptrs[0];
    if (ptrs[1]) w->t = ptrs[1];
    if (ptrs[2]) w->x = ptrs[2];
    if (ptrs[3]) w->y = ptrs[3];
    if (ptrs[4]) w->s = ptrs[4];
    if (ptrs[5]) w->a2 = ptrs[5];
    if (ptrs[6]) w->b2 = ptrs[6];
    if (ptrs[7]) w->l2 = ptrs[7];
    if (ptrs[8]) w->r2 = ptrs[8];
    if (ptrs[9]) w->corner = ptrs[9];
    if (ptrs[10]) w->corner_side = ptrs[10];
    if (!ok) return GS_ENOMEM;
    w->cap = c;
    return GS_OK;
}

/* ---- chaining the crossed faces -------------------------------------- */

/* The two cut slots (edges k -> k+1 joining the sides) of a local face;
 * returns 0 if the face is not crossed. */
static int cut_slots(const gs__part_node *nd, uint32_t lf, uint32_t k[2])
{
    const uint32_t *c = nd->mesh->tri + 3 * (size_t)nd->faces[lf];
    uint32_t n = 0;
    for (uint32_t i = 0; i < 3; ++i)
        if (nd->side[nd->vloc[c[i]]] != nd->side[nd->vloc[c[(i + 1) % 3]]]) k[n++] = i;
    return n == 2;
}

/* The local face across slot k of local face lf, GS_NONE on the boundary of
 * P(N); *entry receives the slot of the shared edge in that face. */
static uint32_t across(const gs__part_node *nd, uint32_t lf, uint32_t k, uint32_t *entry)
{
    uint32_t o = nd->mesh->topo.opp[3 * nd->faces[lf] + k];
    if (o == GS_NONE || nd->floc[o / 3] == GS_NONE) return GS_NONE;
    *entry = o % 3;
    return nd->floc[o / 3];
}

static portal make_portal(const gs__part_node *nd, uint32_t lf, uint32_t k, int last)
{
    uint32_t h = 3 * nd->faces[lf] + k;
    uint32_t u = nd->mesh->tri[h], v = nd->mesh->tri[gs__next(h)];
    portal p = {u, v, last ? GS_NONE : nd->faces[lf]};
    if (nd->side[nd->vloc[u]]) {
        p.va = v;
        p.vb = u;
    }
    return p;
}

/* Walk from local face lf0, entered through slot k0, until the boundary
 * (path) or back at lf0 (loop). Fills w->p, w->np. */
static int walk(const gs__part_node *nd, uint8_t *visited, uint32_t lf0, uint32_t k0,
                int closed, curve_work *w)
{
    uint32_t lf = lf0, k = k0;
    w->np = 0;
    w->closed = closed;
    for (;;) {
        uint32_t cut[2], next_k = 0;
        if (work_reserve(w, (size_t)w->np + 2)) return GS_ENOMEM;
        cut_slots(nd, lf, cut);
        uint32_t exit = cut[0] == k ? cut[1] : cut[0];
        w->p[w->np++] = make_portal(nd, lf, k, 0);
        visited[lf] = 1;
        uint32_t nx = across(nd, lf, exit, &next_k);
        if (nx == GS_NONE) {
            if (closed) return GS_EINTERNAL;
            w->p[w->np++] = make_portal(nd, lf, exit, 1);
            return GS_OK;
        }
        if (closed && nx == lf0) return GS_OK;
        if (visited[nx]) return GS_EINTERNAL;
        lf = nx;
        k = next_k;
    }
}

/* ---- geometry helpers -------------------------------------------------- */

static const double *vpos(const gs__part_node *nd, uint32_t v) { return nd->mesh->xyz + 3 * (size_t)v; }

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static double cross2(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static double clamp_t(double t)
{
    if (!(t >= EDGE_MARGIN)) return EDGE_MARGIN; /* also catches NaN */
    return t > 1 - EDGE_MARGIN ? 1 - EDGE_MARGIN : t;
}

/* 3D point of crossing i at w->t[i] into w->x. */
static void crossing_point(const gs__part_node *nd, curve_work *w, uint32_t i)
{
    const double *a = vpos(nd, w->p[i].va), *b = vpos(nd, w->p[i].vb);
    for (int d = 0; d < 3; ++d) w->x[3 * i + d] = a[d] + w->t[i] * (b[d] - a[d]);
}

/* Number of straight pieces: np-1 for a path, np for a loop. */
static uint32_t n_pieces(const curve_work *w) { return w->closed ? w->np : w->np - 1; }

/* Arc lengths w->s[0..pieces] of the polyline through w->x; returns total. */
static double arc_lengths(const gs__part_node *nd, curve_work *w)
{
    uint32_t np = w->np, ns = n_pieces(w);
    for (uint32_t i = 0; i < np; ++i) crossing_point(nd, w, i);
    w->s[0] = 0;
    for (uint32_t i = 0; i < ns; ++i)
        w->s[i + 1] = w->s[i] + dist3(w->x + 3 * i, w->x + 3 * ((i + 1) % np));
    return w->s[ns];
}

/* Piece holding arc length s (binary search), clamped to valid pieces. */
static uint32_t piece_at(const curve_work *w, double s)
{
    uint32_t lo = 0, hi = n_pieces(w);
    while (hi - lo > 1) {
        uint32_t mid = (lo + hi) / 2;
        if (w->s[mid] <= s)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Point at arc length s (paths clamp, loops wrap) into q; returns the
 * piece and the fraction along it. */
static uint32_t point_at(const curve_work *w, double s, double q[3], double *lambda)
{
    double len = w->s[n_pieces(w)];
    if (w->closed && len > 0) s = fmod(fmod(s, len) + len, len);
    if (s < 0) s = 0;
    if (s > len) s = len;
    uint32_t i = piece_at(w, s);
    double dl = w->s[i + 1] - w->s[i];
    double f = dl > 0 ? (s - w->s[i]) / dl : 0;
    if (f > 1) f = 1;
    const double *a = w->x + 3 * i, *b = w->x + 3 * ((i + 1) % w->np);
    for (int d = 0; d < 3; ++d) q[d] = a[d] + f * (b[d] - a[d]);
    if (lambda) *lambda = f;
    return i;
}

/* ---- pulling the curve taut between anchors ----------------------------- */

/* Unfold the strip of crossings j = 0..k (curve indices (a + j) mod np)
 * into the plane: side-0 ends to the left of the direction of travel. */
static void unfold(const gs__part_node *nd, curve_work *w, uint32_t a, uint32_t k)
{
    uint32_t np = w->np;
    const portal *p0 = &w->p[a];
    w->a2[0][0] = 0;
    w->a2[0][1] = dist3(vpos(nd, p0->va), vpos(nd, p0->vb));
    w->b2[0][0] = w->b2[0][1] = 0;
    for (uint32_t j = 0; j < k; ++j) {
        const portal *p = &w->p[(a + j) % np], *q = &w->p[(a + j + 1) % np];
        const uint32_t *c = nd->mesh->tri + 3 * (size_t)p->face;
        uint32_t vc = c[0];
        for (int i = 1; i < 3; ++i)
            if (vc == p->va || vc == p->vb) vc = c[i];
        const double *A = w->a2[j], *B = w->b2[j];
        double e[2] = {A[0] - B[0], A[1] - B[1]};
        double lab = sqrt(e[0] * e[0] + e[1] * e[1]);
        double lbc = dist3(vpos(nd, p->vb), vpos(nd, vc));
        double lac = dist3(vpos(nd, p->va), vpos(nd, vc));
        e[0] /= lab;
        e[1] /= lab;
        double x = (lbc * lbc - lac * lac + lab * lab) / (2 * lab);
        double y = sqrt(fmax(0.0, lbc * lbc - x * x));
        double C[2] = {B[0] + x * e[0] + y * e[1], B[1] + x * e[1] - y * e[0]};
        int c_is_a = q->va == vc;
        memcpy(w->a2[j + 1], c_is_a ? C : A, sizeof C);
        memcpy(w->b2[j + 1], c_is_a ? B : C, sizeof C);
    }
}

/* The shortest path through portals l2/r2[0..k] (0 and k are points):
 * its corners into corner/corner_side (0 left, 1 right, 2 end point). */
static uint32_t funnel(curve_work *w, uint32_t k)
{
    double (*L)[2] = w->l2, (*R)[2] = w->r2;
    uint32_t nc = 0, apex = 0, li = 0, ri = 0;
    w->corner[nc] = 0;
    w->corner_side[nc++] = 2;
    for (uint32_t i = 1; i <= k; ++i) {
        const double *o = L[apex];
        if (w->corner_side[nc - 1] == 1) o = R[apex];
        if (cross2(o, R[ri], R[i]) >= 0 || ri == apex) {
            if (ri == apex || li == apex || cross2(o, L[li], R[i]) < 0) {
                ri = i;
            } else { /* the right side crossed the left: left corner */
                apex = ri = li;
                w->corner[nc] = li;
                w->corner_side[nc++] = 0;
                i = apex;
                continue;
            }
        }
        if (cross2(o, L[li], L[i]) <= 0 || li == apex) {
            if (li == apex || ri == apex || cross2(o, R[ri], L[i]) > 0) {
                li = i;
            } else {
                apex = li = ri;
                w->corner[nc] = ri;
                w->corner_side[nc++] = 1;
                i = apex;
                continue;
            }
        }
    }
    w->corner[nc] = k;
    w->corner_side[nc++] = 2;
    return nc;
}

/* Parameter on crossing j (unfolded a2[j] -> b2[j]) of the line P -> Q. */
static double line_param(const curve_work *w, uint32_t j, const double *P, const double *Q)
{
    const double *A = w->a2[j], *B = w->b2[j];
    double d[2] = {Q[0] - P[0], Q[1] - P[1]}, e[2] = {B[0] - A[0], B[1] - A[1]};
    double den = e[0] * d[1] - e[1] * d[0];
    if (fabs(den) < 1e-300) return 0.5;
    double num = (P[0] - A[0]) * d[1] - (P[1] - A[1]) * d[0];
    return clamp_t(num / den);
}

/* Straighten the curve between the anchors at crossings a and a + k
 * (their t are fixed): t of the crossings in between. */
static void pull_taut(const gs__part_node *nd, curve_work *w, uint32_t a, uint32_t k)
{
    uint32_t np = w->np;
    if (k < 2) return;
    unfold(nd, w, a, k);
    for (uint32_t j = 0; j <= k; ++j) {
        const double *A = w->a2[j], *B = w->b2[j];
        double tl = EDGE_MARGIN, tr = 1 - EDGE_MARGIN;
        if (j == 0 || j == k) tl = tr = w->t[(a + j) % np];
        for (int d = 0; d < 2; ++d) {
            w->l2[j][d] = A[d] + tl * (B[d] - A[d]);
            w->r2[j][d] = A[d] + tr * (B[d] - A[d]);
        }
    }
    uint32_t nc = funnel(w, k);
    for (uint32_t c = 0; c + 1 < nc; ++c) {
        uint32_t j0 = w->corner[c], j1 = w->corner[c + 1];
        const double *P = w->corner_side[c] == 1 ? w->r2[j0] : w->l2[j0];
        const double *Q = w->corner_side[c + 1] == 1 ? w->r2[j1] : w->l2[j1];
        if (w->corner_side[c] != 2) w->t[(a + j0) % np] = w->corner_side[c] ? 1 - EDGE_MARGIN : EDGE_MARGIN;
        for (uint32_t j = j0 + 1; j < j1; ++j) w->t[(a + j) % np] = line_param(w, j, P, Q);
    }
}

/* Crossing whose midpoint-polyline arc length is closest to s. */
static uint32_t nearest_crossing(const curve_work *w, double s)
{
    uint32_t i = piece_at(w, s);
    if (i + 1 < w->np && fabs(w->s[i + 1] - s) < fabs(w->s[i] - s)) return i + 1;
    return i;
}

/* Anchors (paper: path ends and middle; three points around a loop) and
 * the taut curve between them. */
static void straighten(const gs__part_node *nd, curve_work *w)
{
    uint32_t np = w->np;
    for (uint32_t i = 0; i < np; ++i) w->t[i] = 0.5;
    if (np < 3) return;
    double len = arc_lengths(nd, w);
    uint32_t anc[4];
    if (!w->closed) {
        anc[0] = 0;
        anc[1] = nearest_crossing(w, len / 2);
        anc[2] = np - 1;
        if (anc[1] == 0 || anc[1] == np - 1) anc[1] = np / 2;
        pull_taut(nd, w, anc[0], anc[1] - anc[0]);
        pull_taut(nd, w, anc[1], anc[2] - anc[1]);
        return;
    }
    anc[0] = 0;
    anc[1] = nearest_crossing(w, len / 3);
    anc[2] = nearest_crossing(w, 2 * len / 3);
    if (!(anc[1] > 0 && anc[2] > anc[1] && anc[2] < np)) {
        anc[1] = np / 3;
        anc[2] = 2 * np / 3;
    }
    anc[3] = np;
    for (int i = 0; i < 3; ++i) pull_taut(nd, w, anc[i], anc[i + 1] - anc[i]);
}

/* ---- smoothing and resampling --------------------------------------------- */

/* A few rounds of a [1 2 1]/4 filter over +-h of arc length, each point
 * projected back onto its crossed edge (paper: filter and project). */
static void smooth(const gs__part_node *nd, curve_work *w, uint32_t iters, double h)
{
    uint32_t np = w->np;
    for (uint32_t it = 0; it < iters; ++it) {
        arc_lengths(nd, w);
        for (uint32_t i = 0; i < np; ++i) {
            double q0[3], q1[3];
            point_at(w, w->s[i] - h, q0, NULL);
            point_at(w, w->s[i] + h, q1, NULL);
            for (int d = 0; d < 3; ++d)
                w->y[3 * i + d] = 0.25 * (q0[d] + 2 * w->x[3 * i + d] + q1[d]);
        }
        for (uint32_t i = 0; i < np; ++i) {
            const double *a = vpos(nd, w->p[i].va), *b = vpos(nd, w->p[i].vb);
            double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double num = 0, den = 0;
            for (int d = 0; d < 3; ++d) {
                num += (w->y[3 * i + d] - a[d]) * e[d];
                den += e[d] * e[d];
            }
            w->t[i] = clamp_t(den > 0 ? num / den : 0.5);
        }
    }
}

/* Barycentric coordinates in face f of (1-lambda)*X_i + lambda*X_{i+1}. */
static void sample_bary(const gs__part_node *nd, const curve_work *w, uint32_t i, double lambda,
                        gs__sep_sample *out)
{
    const portal *p = &w->p[i], *q = &w->p[(i + 1) % w->np];
    const uint32_t *c = nd->mesh->tri + 3 * (size_t)p->face;
    uint32_t v[4] = {p->va, p->vb, q->va, q->vb};
    double wt[4] = {(1 - lambda) * (1 - w->t[i]), (1 - lambda) * w->t[i],
                    lambda * (1 - w->t[(i + 1) % w->np]), lambda * w->t[(i + 1) % w->np]};
    out->face = p->face;
    out->bary[0] = out->bary[1] = out->bary[2] = 0;
    for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 3; ++k)
            if (c[k] == v[j]) out->bary[k] += wt[j];
}

/* ---- filtering the samples and projecting them onto the surface -------- */

/* Closest point of triangle (a, b, c) to p: barycentric coordinates in l,
 * squared distance returned (regions of the triangle's Voronoi diagram). */
static double closest_on_triangle(const double *p, const double *a, const double *b, const double *c,
                                  double l[3])
{
    double ab[3], ac[3], ap[3];
    for (int i = 0; i < 3; ++i) ab[i] = b[i] - a[i], ac[i] = c[i] - a[i], ap[i] = p[i] - a[i];
    double d1 = ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2], d2 = ac[0] * ap[0] + ac[1] * ap[1] + ac[2] * ap[2];
    double aa = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2], cc = ac[0] * ac[0] + ac[1] * ac[1] + ac[2] * ac[2];
    double bc = ab[0] * ac[0] + ab[1] * ac[1] + ab[2] * ac[2];
    double det = aa * cc - bc * bc;
    double v = det > 0 ? (cc * d1 - bc * d2) / det : 0, w = det > 0 ? (aa * d2 - bc * d1) / det : 0;
    if (v < 0 || w < 0 || v + w > 1) { /* outside: closest point on an edge */
        const double *e0[3] = {a, b, c}, *e1[3] = {b, c, a};
        double best = INFINITY;
        for (int k = 0; k < 3; ++k) {
            double e[3], q[3], t = 0, ee = 0;
            for (int i = 0; i < 3; ++i) e[i] = e1[k][i] - e0[k][i], ee += e[i] * e[i];
            for (int i = 0; i < 3; ++i) t += (p[i] - e0[k][i]) * e[i];
            t = ee > 0 ? fmin(1, fmax(0, t / ee)) : 0;
            double d = 0;
            for (int i = 0; i < 3; ++i) q[i] = e0[k][i] + t * e[i] - p[i], d += q[i] * q[i];
            if (d < best) {
                best = d;
                double lk[3] = {0, 0, 0};
                lk[k] = 1 - t, lk[(k + 1) % 3] = t;
                memcpy(l, lk, sizeof lk);
            }
        }
        return best;
    }
    l[0] = fmax(0.0, 1 - v - w), l[1] = v, l[2] = w; /* rounding: keep l >= 0, sum 1 */
    double sum = l[0] + l[1] + l[2];
    l[0] /= sum, l[1] /= sum, l[2] /= sum;
    double d = 0;
    for (int i = 0; i < 3; ++i) {
        double q = l[0] * a[i] + l[1] * b[i] + l[2] * c[i] - p[i];
        d += q * q;
    }
    return d;
}

static void sample_point(const gs__part_node *nd, const gs__sep_sample *sm, double q[3])
{
    const uint32_t *c = nd->mesh->tri + 3 * (size_t)sm->face;
    for (int i = 0; i < 3; ++i)
        q[i] = sm->bary[0] * vpos(nd, c[0])[i] + sm->bary[1] * vpos(nd, c[1])[i] + sm->bary[2] * vpos(nd, c[2])[i];
}

/* Whether local face f of P(N) is crossed by the cut (corners on both sides). */
static int crossed(const gs__part_node *nd, uint32_t f)
{
    const uint32_t *c = nd->mesh->tri + 3 * (size_t)f;
    uint8_t a = nd->side[nd->vloc[c[0]]], b = nd->side[nd->vloc[c[1]]], d = nd->side[nd->vloc[c[2]]];
    return a != b || a != d;
}

/* Move sample sm to the closest point to p on the faces crossed by the cut
 * around the corners of its current face: filtered samples smooth the curve
 * inside the strip of crossed faces and never drift past it (a pair of
 * neighbours on either side must not see the separator move away). */
static void project_sample(const gs__part_node *nd, const double *p, gs__sep_sample *sm)
{
    const gs__topo *t = &nd->mesh->topo;
    const uint32_t *c0 = nd->mesh->tri + 3 * (size_t)sm->face;
    uint32_t corners[3] = {c0[0], c0[1], c0[2]};
    double best = INFINITY;
    for (int j = 0; j < 3; ++j)
        for (uint32_t k = t->vc_start[corners[j]]; k < t->vc_start[corners[j] + 1]; ++k) {
            uint32_t f = t->vc[k] / 3;
            if (nd->floc[f] == GS_NONE || !crossed(nd, f)) continue;
            const uint32_t *c = nd->mesh->tri + 3 * (size_t)f;
            double l[3], d = closest_on_triangle(p, vpos(nd, c[0]), vpos(nd, c[1]), vpos(nd, c[2]), l);
            if (d < best) {
                best = d;
                sm->face = f;
                memcpy(sm->bary, l, sizeof l);
            }
        }
}

/* Arc lengths of the samples' polyline (pts must hold their positions);
 * returns the total, with the closing segment for a loop. */
static double sample_lengths(gs__sep_sample *sm, const double *pts, uint32_t n, int closed)
{
    double s = 0;
    for (uint32_t k = 0; k < n; ++k) {
        if (k) s += dist3(pts + 3 * (k - 1), pts + 3 * k);
        sm[k].s = s;
    }
    return closed && n ? s + dist3(pts + 3 * (n - 1), pts) : s;
}

/* Put the n samples back at regular arc length along their own polyline,
 * each projected onto the surface near the sample it comes from. old/pts
 * are scratch for n samples / 3n doubles. */
static void resample_regular(const gs__part_node *nd, gs__sep_sample *sm, uint32_t n, int closed,
                             gs__sep_sample *old, double *pts)
{
    memcpy(old, sm, n * sizeof *old);
    for (uint32_t k = 0; k < n; ++k) sample_point(nd, &old[k], pts + 3 * k);
    double len = sample_lengths(old, pts, n, closed), step = len / (closed ? n : n - 1);
    uint32_t i = 0;
    for (uint32_t k = 1; k + (closed ? 0 : 1) < n; ++k) {
        double target = k * step;
        while (i + 1 < n && old[i + 1].s <= target) ++i;
        uint32_t j = (i + 1) % n;
        double seg = (i + 1 < n ? old[i + 1].s : len) - old[i].s;
        double f = seg > 0 ? (target - old[i].s) / seg : 0, q[3];
        for (int d = 0; d < 3; ++d) q[d] = pts[3 * i + d] + f * (pts[3 * j + d] - pts[3 * i + d]);
        sm[k] = old[f < 0.5 ? i : j];
        project_sample(nd, q, &sm[k]);
    }
}

/* The paper's "filter and project": a few rounds of a [1 2 1]/4 filter over
 * the samples (a path's ends stay on the boundary), each filtered point
 * projected back onto the surface; then the samples are put back at
 * regular arc length and their arc lengths recomputed. */
static int filter_samples(const gs__part_node *nd, gs__sep_sample *sm, uint32_t n, int closed,
                          uint32_t iters, double *len)
{
    double *pts = gs__malloc(3 * (size_t)n, sizeof *pts);
    gs__sep_sample *old = gs__malloc(n, sizeof *old);
    if (!pts || !old) {
        free(pts);
        free(old);
        return GS_ENOMEM;
    }
    if (n < 3) iters = 0; /* nothing to filter; lengths still become chords */
    for (uint32_t it = 0; it < iters; ++it) {
        for (uint32_t k = 0; k < n; ++k) sample_point(nd, &sm[k], pts + 3 * k);
        for (uint32_t k = 0; k < n; ++k) {
            if (!closed && (k == 0 || k == n - 1)) continue;
            const double *a = pts + 3 * ((k + n - 1) % n), *b = pts + 3 * k, *c = pts + 3 * ((k + 1) % n);
            double q[3];
            for (int i = 0; i < 3; ++i) q[i] = 0.25 * (a[i] + 2 * b[i] + c[i]);
            project_sample(nd, q, &sm[k]);
        }
    }
    if (n >= 3) resample_regular(nd, sm, n, closed, old, pts);
    for (uint32_t k = 0; k < n; ++k) sample_point(nd, &sm[k], pts + 3 * k);
    *len = sample_lengths(sm, pts, n, closed);
    free(pts);
    free(old);
    return GS_OK;
}

/* Regular samples along the final curve, its crossings and its record. */
static int emit(const gs__part_node *nd, curve_work *w, double spacing, uint32_t filter_iters,
                uint32_t min_samples, gs__part_out *out)
{
    double len = arc_lengths(nd, w);
    double r = spacing > 0 ? len / spacing : 0;
    uint32_t n = (r > 1e8) ? 100000000u : (uint32_t)floor(r + 0.5);
    n = w->closed ? (n < 3 ? 3 : n) : (n < 1 ? 2 : n + 1);
    if (n < min_samples) n = min_samples;
    if (gs__grow((void **)&out->samples, &out->cap_samples, out->n_samples + n, sizeof *out->samples) ||
        gs__grow((void **)&out->cross, &out->cap_cross, out->n_cross + w->np, sizeof *out->cross) ||
        gs__grow((void **)&out->curves, &out->cap_curves, out->n_curves + 1, sizeof *out->curves))
        return GS_ENOMEM;
    gs__sep_curve *cv = &out->curves[out->n_curves++];
    *cv = (gs__sep_curve){nd->id, (uint32_t)w->closed, (uint32_t)out->n_samples, n, len,
                         (uint32_t)out->n_cross, w->np};
    double step = len / (w->closed ? n : n - 1);
    for (uint32_t j = 0; j < n; ++j) {
        gs__sep_sample *sm = &out->samples[out->n_samples++];
        double q[3], lambda, s = (!w->closed && j == n - 1) ? len : j * step;
        uint32_t i = point_at(w, s, q, &lambda);
        sample_bary(nd, w, i, lambda, sm);
        sm->s = s;
    }
    if (filter_iters && filter_samples(nd, out->samples + cv->sample_start, n, w->closed, filter_iters,
                                       &cv->length))
        return GS_ENOMEM;
    for (uint32_t i = 0; i < w->np; ++i)
        out->cross[out->n_cross++] =
            (gs__sep_cross){w->p[i].face, {w->p[i].va, w->p[i].vb}, w->t[i]};
    return GS_OK;
}

/* Crossings at the zero level of nd->phi (linear along each edge). */
static void level_crossings(const gs__part_node *nd, curve_work *w)
{
    for (uint32_t i = 0; i < w->np; ++i) {
        double a = nd->phi[nd->vloc[w->p[i].va]], b = nd->phi[nd->vloc[w->p[i].vb]];
        double t = b > a ? -a / (b - a) : 0.5; /* a <= 0 < b: t in [0, 1) */
        w->t[i] = t < LEVEL_MARGIN ? LEVEL_MARGIN : (t > 1 - LEVEL_MARGIN ? 1 - LEVEL_MARGIN : t);
    }
}

static int finish_curve(const gs__part_node *nd, const gs__tree_options *opt, double mean_edge,
                        curve_work *w, gs__part_out *out)
{
    if (nd->phi_valid)
        level_crossings(nd, w);
    else
        straighten(nd, w);
    smooth(nd, w, opt->smooth_iters, FILTER_WIDTH * mean_edge);
    return emit(nd, w, opt->sample_spacing * mean_edge, opt->filter_iters, opt->min_samples, out);
}

/* Paths first (from a crossed face with a cut edge on the boundary), then
 * loops from the crossed faces left. */
static int chain_all(const gs__part_node *nd, const gs__tree_options *opt, double mean_edge,
                     uint8_t *visited, curve_work *w, gs__part_out *out)
{
    for (int closed = 0; closed < 2; ++closed)
        for (uint32_t lf = 0; lf < nd->nf; ++lf) {
            uint32_t cut[2], e, start = GS_NONE;
            if (visited[lf] || !cut_slots(nd, lf, cut)) continue;
            for (int j = 0; j < 2 && start == GS_NONE; ++j)
                if (closed || across(nd, lf, cut[j], &e) == GS_NONE) start = cut[j];
            if (start == GS_NONE) continue;
            int rc = walk(nd, visited, lf, start, closed, w);
            if (rc == GS_OK) rc = finish_curve(nd, opt, mean_edge, w, out);
            if (rc) return rc;
        }
    return GS_OK;
}

int gs__part_curves(const gs__part_node *nd, const gs__tree_options *opt, double mean_edge,
                    gs__part_out *out, gs_error *err)
{
    curve_work w = {0};
    uint8_t *visited = calloc(nd->nf ? nd->nf : 1, 1);
    int rc = visited ? chain_all(nd, opt, mean_edge, visited, &w, out) : GS_ENOMEM;
    free(visited);
    work_free(&w);
    if (rc == GS_ENOMEM) return gs__fail(err, rc, "out of memory building separator curves");
    if (rc) return gs__fail(err, rc, "inconsistent cut at tree node %u", nd->id);
    return GS_OK;
}
