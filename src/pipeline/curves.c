/* curves.c - the separator curves of the tree shaped for the fields and
 * the fits (gs_db_build, between the tree and the fields): long curves
 * thinned to max_samples, curves passing next to a sharp saddle pivoted
 * through it, and curves split into pieces (at most GS_PIPE_PIECE sample
 * intervals, shorter on rough surfaces, and at the pivots). Each takes the
 * tree and the mesh and rewrites the tree's curves and samples. */
#include "pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Thin every curve of more than cap samples to cap samples, in place: the
 * samples nearest to cap targets at regular arc length (a path keeps both
 * ends). A distance function is fitted with degree <= mmax, so a long curve
 * gains nothing from thousands of samples, while each one costs a field
 * (or three corner fields) over the whole patch. */
void gs__pipe_thin_samples(gs__tree *t, uint32_t cap)
{
    for (uint32_t c = 0; c < t->n_curves && cap; ++c) {
        gs__sep_curve *cv = &t->curves[c];
        uint32_t n = cv->n_samples;
        if (n <= cap) continue;
        gs__sep_sample *sm = t->samples + cv->sample_start;
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

/* Shortest paths bend at saddle vertices (total angle above 2 pi), and
 * there only (inside the surface). A curve passing such a vertex v at a
 * distance delta answers the pairs whose paths bend at it through points at
 * least delta from v, where d(x, .) + d(., y) has a V-shaped minimum: too
 * long by up to 2 delta. A plate with two square holes through it (genus 2,
 * its holes' corners are saddles of excess pi / 2): 2,506 of its 2,507
 * pairs off by more than 2%, 5 to 9 mean edges apart, went round a hole's
 * corner, p99.9 2.0%. So each such vertex becomes a pivot of the curves
 * passing next to it (find_pivots, insert_pivots): the curve makes a detour
 * through the vertex, and split_curves ends its pieces there (series
 * across the kink of the detour cost two such plates 6% and 10% more bytes
 * and were less accurate). Those pairs are then answered through v itself
 * (the plate: none over by more than 2%, p99.9 1.5%, 8% more bytes).
 * Sharp: an excess (total angle - 2 pi) of at least GS_PIPE_PIVOT_EXCESS
 * radians, and as much left with its neighbours' (their cones do not
 * cancel it: on a noisy surface they do, and the pieces cost a spiky sphere
 * 17% more bytes for 3% of its ME; with this, 1 of its 110 sharp saddles is
 * a pivot, none of terrain's 5). Milder saddles bend paths too little to pay
 * for the pieces (at 0.5: bunny-5k, 8 vertices, 25% more bytes for
 * nothing); bunny-5k and spot have none, homer 3, fandisk 7. Boundary
 * corners (reflex: a total angle above pi) bend paths too, but a perforated
 * plate's 100 gained nothing for 57% more bytes: they are left alone. */
#define GS_PIPE_PIVOT_EXCESS 1.0

static double excess(const gs__topo *t, uint32_t v)
{
    return t->vflag[v] & (GS_V_BOUNDARY | GS_V_UNUSED | GS_V_NONMANIFOLD) ? 0.0 : t->vangle[v] - 2.0 * M_PI;
}

static int sharp_saddle(const gs_mesh *m, uint32_t v)
{
    const gs__topo *t = &m->topo;
    double e = excess(t, v);
    if (!(e >= GS_PIPE_PIVOT_EXCESS)) return 0;
    for (uint32_t k = t->vc_start[v]; k < t->vc_start[v + 1]; ++k) { /* each neighbour once (a fan) */
        uint32_t h = t->vc[k];
        e += excess(t, m->tri[3 * (h / 3) + (h % 3 + 1) % 3]);
    }
    return e >= GS_PIPE_PIVOT_EXCESS;
}

static double sample_gap(const gs_mesh *m, const gs__sep_sample *a, const gs__sep_sample *b)
{
    double p[3], q[3];
    gs__face_point(&m->topo, a->face, a->bary, p), gs__face_point(&m->topo, b->face, b->bary, q);
    return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

/* The pivots of curve cv (n samples sm): for each sharp saddle corner v of
 * the samples' faces, the nearest sample k of the run of consecutive
 * samples whose faces have v as a corner, and of k's two neighbours the
 * nearer one j: v goes between k and j (at[q] = min(k, j), loops: n - 1
 * for between the last and the first; face and corner in piv[q]). None
 * where a sample already lies on v. Returns the count (at most n). */
typedef struct pivot {
    uint32_t at;
    gs__sep_sample s;
} pivot;

static uint32_t find_pivots(const gs__sep_curve *cv, const gs__sep_sample *sm, const gs_mesh *m, pivot *piv)
{
    uint32_t n = cv->n_samples, np = 0;
    for (uint32_t k = 0; k < n; ++k) {
        const uint32_t *ck = m->tri + 3 * (size_t)sm[k].face;
        for (int j = 0; j < 3; ++j) {
            uint32_t v = ck[j];
            if (sm[k].bary[j] == 1.0 || !sharp_saddle(m, v)) continue;
            gs__sep_sample at_v = {sm[k].face, {0.0, 0.0, 0.0}, 0.0};
            at_v.bary[j] = 1.0;
            double best = sample_gap(m, &sm[k], &at_v), dn[2] = {INFINITY, INFINITY};
            int nearest = 1;
            for (int dir = -1; dir <= 1 && nearest; dir += 2)
                for (uint32_t step = 1; step < n && nearest; ++step) {
                    int64_t i = (int64_t)k + dir * (int64_t)step;
                    if (cv->closed) i = ((i % (int64_t)n) + n) % (int64_t)n;
                    else if (i < 0 || i >= (int64_t)n) break;
                    if ((uint32_t)i == k) break;
                    double d = sample_gap(m, &sm[i], &at_v);
                    if (step == 1) dn[dir > 0] = d;
                    const uint32_t *ci = m->tri + 3 * (size_t)sm[i].face;
                    int corner = ci[0] == v ? 0 : ci[1] == v ? 1 : ci[2] == v ? 2 : -1;
                    if (corner < 0) break;
                    if (sm[i].bary[corner] == 1.0 || d < best || (d == best && (uint32_t)i < k)) nearest = 0;
                }
            if (!nearest || !(best > 0.0)) continue;
            /* between k and its nearer neighbour (a path's ends: the one it has) */
            int after = dn[1] < dn[0];
            if (!cv->closed && k == 0) after = 1;
            if (!cv->closed && k == n - 1) after = 0;
            if (!cv->closed && n < 2) continue;
            uint32_t pos = after ? k : (k == 0 ? n - 1 : k - 1);
            piv[np].at = pos, piv[np++].s = at_v;
            break;
        }
    }
    /* in order of position (a few: insertion sort); one per gap */
    for (uint32_t i = 1; i < np; ++i)
        for (uint32_t j = i; j > 0 && piv[j - 1].at > piv[j].at; --j) {
            pivot x = piv[j];
            piv[j] = piv[j - 1], piv[j - 1] = x;
        }
    uint32_t w = 0;
    for (uint32_t i = 0; i < np; ++i)
        if (!w || piv[w - 1].at != piv[i].at) piv[w++] = piv[i];
    return w;
}

/* The vertex of pivot p (the corner of its face with weight 1). */
static uint32_t pivot_vertex(const gs_mesh *m, const gs__sep_sample *p)
{
    uint32_t v = 0;
    for (int j = 0; j < 3; ++j)
        if (p->bary[j] == 1.0) v = m->tri[3 * (size_t)p->face + j];
    return v;
}

/* Whether sample a's face has the vertex of pivot p as a corner. */
static int has_corner(const gs_mesh *m, const gs__sep_sample *a, const gs__sep_sample *p)
{
    uint32_t v = pivot_vertex(m, p);
    const uint32_t *c = m->tri + 3 * (size_t)a->face;
    return c[0] == v || c[1] == v || c[2] == v;
}

/* Point t of the way from sample a to pivot p, in a's face (which has p's
 * vertex as a corner). */
static gs__sep_sample toward(const gs_mesh *m, const gs__sep_sample *a, const gs__sep_sample *p, double t)
{
    uint32_t v = pivot_vertex(m, p);
    gs__sep_sample x = *a;
    const uint32_t *c = m->tri + 3 * (size_t)a->face;
    for (int j = 0; j < 3; ++j) x.bary[j] = (1.0 - t) * a->bary[j] + (c[j] == v ? t : 0.0);
    return x;
}

/* Curve cv's samples with its pivots inserted into out (NULL: only
 * counted) and where its pieces must end into cut (with out): the curve
 * makes a detour from sample k straight to the vertex and on to sample
 * k + 1, both legs inside faces around the vertex, sampled about as densely
 * as the curve there (its gap k, k + 1), so that its functions are as
 * smooth in the arc parameter as elsewhere; the arc parameters after it
 * grow by the detour. The pieces end at the vertex (cut). (Ending them at
 * the detour's two ends too cost a plate 15% more bytes for 0.02 points
 * of p99.9.) Pivots whose two samples do not both lie in faces around the
 * vertex are left out. Returns the count. */
static uint32_t with_pivots(const gs__sep_curve *cv, const gs__sep_sample *sm, const gs_mesh *m, const pivot *piv,
                            uint32_t np, gs__sep_sample *out, uint8_t *cut, double *length)
{
    uint32_t n = cv->n_samples, q = 0, os = 0;
    double shift = 0.0;
    for (uint32_t k = 0; k < n; ++k) {
        if (out) out[os] = sm[k], out[os].s += shift, cut[os] = 0;
        os++;
        while (q < np && piv[q].at < k) q++;
        if (q >= np || piv[q].at != k) continue;
        const gs__sep_sample *nx = k + 1 < n ? &sm[k + 1] : &sm[0], *p = &piv[q].s;
        if (!has_corner(m, &sm[k], p) || !has_corner(m, nx, p)) continue;
        double old = k + 1 < n ? sm[k + 1].s - sm[k].s : cv->length - sm[k].s;
        double g0 = sample_gap(m, &sm[k], p), g1 = sample_gap(m, p, nx), h = old > 0.0 ? old : g0 + g1;
        uint32_t m0 = (uint32_t)ceil(g0 / h), m1 = (uint32_t)ceil(g1 / h);
        m0 = m0 < 1 ? 1 : (m0 > 64 ? 64 : m0), m1 = m1 < 1 ? 1 : (m1 > 64 ? 64 : m1);
        double s0 = sm[k].s + shift;
        for (uint32_t i = 1; i < m0; ++i, ++os)
            if (out) out[os] = toward(m, &sm[k], p, (double)i / m0), out[os].s = s0 + g0 * i / m0, cut[os] = 0;
        if (out) out[os] = *p, out[os].s = s0 + g0, cut[os] = 1;
        os++;
        for (uint32_t i = m1 - 1; i >= 1; --i, ++os)
            if (out) out[os] = toward(m, nx, p, (double)i / m1), out[os].s = s0 + g0 + g1 * (m1 - i) / m1, cut[os] = 0;
        shift += g0 + g1 - old;
    }
    if (length) *length = cv->length + shift;
    return os;
}

/* Insert each curve's pivots (find_pivots, with_pivots); *cut: per new
 * sample, 1 where a piece must end (caller frees). */
int gs__pipe_insert_pivots(gs__tree *t, const gs_mesh *m, uint8_t **cut, gs_error *err)
{
    uint32_t maxn = 0;
    *cut = NULL;
    for (uint32_t c = 0; c < t->n_curves; ++c) maxn = t->curves[c].n_samples > maxn ? t->curves[c].n_samples : maxn;
    pivot *piv = gs__malloc((size_t)maxn + 1, sizeof *piv);
    if (!piv) return gs__fail(err, GS_ENOMEM, "out of memory placing pivots");
    size_t total = 0;
    for (uint32_t c = 0; c < t->n_curves; ++c) {
        const gs__sep_curve *cv = &t->curves[c];
        const gs__sep_sample *sm = t->samples + cv->sample_start;
        total += with_pivots(cv, sm, m, piv, find_pivots(cv, sm, m, piv), NULL, NULL, NULL);
    }
    if (total > UINT32_MAX) {
        free(piv);
        return gs__fail(err, GS_ELIMIT, "too many separator samples");
    }
    gs__sep_sample *out = gs__malloc(total ? total : 1, sizeof *out);
    *cut = gs__malloc(total ? total : 1, 1);
    if (!out || !*cut) {
        free(piv), free(out), free(*cut);
        *cut = NULL;
        return gs__fail(err, GS_ENOMEM, "out of memory placing pivots");
    }
    uint32_t os = 0;
    for (uint32_t c = 0; c < t->n_curves; ++c) {
        gs__sep_curve *cv = &t->curves[c];
        const gs__sep_sample *sm = t->samples + cv->sample_start;
        double len;
        uint32_t k = with_pivots(cv, sm, m, piv, find_pivots(cv, sm, m, piv), out + os, *cut + os, &len);
        cv->sample_start = os, cv->n_samples = k, cv->length = len;
        os += k;
    }
    free(piv);
    free(t->samples);
    t->samples = out;
    t->n_samples = os;
    return GS_OK;
}

/* The piece ends of curve cv (sample positions; a loop's run past n - 1
 * wraps): its cuts (cut non-NULL: cut[k] for its sample k; a path's ends
 * are ends anyway) and, between them, equal splits into runs of at most
 * `piece` intervals. Returns the number of ends (pieces + 1), written to
 * ends (room for n_samples + 2). A loop without cuts nor splits: 1 (it
 * stays one loop). */
static uint32_t piece_ends(const gs__sep_curve *cv, const uint8_t *cut, uint32_t piece, uint32_t *ends)
{
    uint32_t n = cv->n_samples, iv = cv->closed ? n : n - 1, np = 0, first = GS_NONE;
    for (uint32_t k = cv->closed ? 0 : 1; cut && k < (cv->closed ? n : n - 1); ++k)
        if (cut[k]) {
            if (first == GS_NONE) first = k;
            np++;
        }
    uint32_t ne = 0, a = cv->closed && np ? first : 0;
    ends[ne++] = a;
    for (uint32_t k = a + 1; k <= a + iv; ++k) {
        if (k < a + iv && !(np && cut[k % n])) continue;
        uint32_t b = ends[ne - 1], len = k - b; /* run [b, k]: split equally */
        uint32_t q = len > piece ? (len + piece - 1) / piece : 1;
        for (uint32_t r = 1; r <= q; ++r) ends[ne++] = b + (uint32_t)((uint64_t)len * r / q);
    }
    return cv->closed && !np && ne == 2 ? 1 : ne;
}

/* Split every curve (of the nodes i with only[i] != 0; only NULL: all) of
 * more than `piece0` sample intervals into paths of
 * at most that many (as equal as they can be; consecutive pieces share
 * their end sample, a loop's last piece ends at its first sample), and
 * (cut non-NULL: 1 per sample where a piece must end) at its pivots
 * (insert_pivots; a loop with one becomes a path from it to itself): each
 * piece is a curve of the same separator, so that every path still
 * crosses one, and each vertex's function on a short piece is smooth at low
 * degree where one series over a long curve cannot follow the sharp dip of
 * a vertex near it. Renumbers the curves, the nodes' curve ranges and
 * prefixes. GS_ENOMEM leaves the tree as it was. */
int gs__pipe_split_curves(gs__tree *t, uint32_t piece0, const uint8_t *only, const uint8_t *cut, gs_error *err)
{
    if (!piece0) return GS_OK;
    uint32_t nc = 0, ns = 0, maxn = 0;
    for (uint32_t c = 0; c < t->n_curves; ++c) maxn = t->curves[c].n_samples > maxn ? t->curves[c].n_samples : maxn;
    uint32_t *ends = gs__malloc((size_t)maxn + 2, sizeof *ends);
    if (!ends) return gs__fail(err, GS_ENOMEM, "out of memory splitting curves");
    for (uint32_t c = 0; c < t->n_curves; ++c) {
        const gs__sep_curve *cv = &t->curves[c];
        uint32_t piece = !only || only[cv->node] ? piece0 : UINT32_MAX;
        uint32_t ne = piece_ends(cv, cut ? cut + cv->sample_start : NULL, piece, ends);
        uint32_t k = ne == 1 ? 1 : ne - 1;
        nc += k;
        ns += ne == 1 ? cv->n_samples : (ends[ne - 1] - ends[0]) + k;
    }
    if (nc == t->n_curves) {
        free(ends);
        return GS_OK;
    }
    gs__sep_curve *curves = gs__malloc(nc, sizeof *curves);
    gs__sep_sample *samples = gs__malloc(ns, sizeof *samples);
    if (!curves || !samples) {
        free(curves);
        free(samples);
        free(ends);
        return gs__fail(err, GS_ENOMEM, "out of memory splitting curves");
    }
    uint32_t oc = 0, os = 0;
    for (uint32_t i = 0; i < t->n_nodes; ++i) {
        gs__tree_node *nd = &t->nodes[i];
        uint32_t first = oc;
        uint32_t piece = !only || only[i] ? piece0 : UINT32_MAX;
        for (uint32_t c = nd->curve_start; c < nd->curve_start + nd->n_curves; ++c) {
            const gs__sep_curve *cv = &t->curves[c];
            const gs__sep_sample *sm = t->samples + cv->sample_start;
            uint32_t n = cv->n_samples, ne = piece_ends(cv, cut ? cut + cv->sample_start : NULL, piece, ends);
            if (ne == 1 || (ne == 2 && !cv->closed)) {
                curves[oc] = *cv;
                curves[oc++].sample_start = os;
                memcpy(samples + os, sm, n * sizeof *samples);
                os += n;
                continue;
            }
            for (uint32_t q = 0; q + 1 < ne; ++q) {
                uint32_t a = ends[q], b = ends[q + 1];
                double s0 = sm[a % n].s + (a >= n ? cv->length : 0.0);
                curves[oc] = *cv;
                curves[oc].closed = 0;
                curves[oc].sample_start = os;
                curves[oc].n_samples = b - a + 1;
                for (uint32_t j = a; j <= b; ++j) {
                    gs__sep_sample x = sm[j % n];
                    x.s = (j >= n ? x.s + cv->length : x.s) - s0;
                    samples[os++] = x;
                }
                curves[oc].length = samples[os - 1].s;
                oc++;
            }
        }
        nd->curve_start = first;
        nd->n_curves = oc - first;
    }
    free(ends);
    for (uint32_t i = 0; i < t->n_nodes; ++i) {
        gs__tree_node *nd = &t->nodes[i];
        nd->curve_prefix = nd->parent == GS_NONE ? 0
                                                 : t->nodes[nd->parent].curve_prefix + t->nodes[nd->parent].n_curves;
    }
    free(t->curves);
    free(t->samples);
    t->curves = curves;
    t->samples = samples;
    t->n_curves = nc;
    t->n_samples = ns;
    return GS_OK;
}
