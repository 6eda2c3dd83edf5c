/* within.c - neighbourhoods from the database: every vertex within a radius
 * of x (gs_db_within), the k nearest to x among candidates (gs_db_nearest).
 *
 * Whole subtrees of the bisection tree are pruned with lower bounds on
 * their vertices' database distances, derived from what the file stores:
 *  - a separator bound: a vertex y outside x's subtree at node A (their
 *    lowest common ancestor) is answered as the minimum over the curves of
 *    A and its ancestors of min_u f_x + f_y, each at least the two stored
 *    minima m_x + m_y (the query's quick reject); so every y under a node N
 *    is at least min over those curves of m_x + (the least m_y under N);
 *  - a Euclidean bound: answers are never below the straight distance, so
 *    every y under N is at least |x - c_N| - r_N (N's bounding sphere);
 *  - the separator bound is not used where a vertex may be one of x's near
 *    pairs (within the radius of section 'near_pairs'), whose stored exact
 *    distances can be below it.
 * The least minima and the spheres of every node (the "neighbourhood
 * bounds") are computed from the file on first use, in one pass over the
 * vertices' minima, and kept with the database (db->derived) until
 * gs_db_free. Vertices that survive the bounds are answered by a query
 * source (query_internal.h), so every distance returned is
 * gs_db_distance's, bit for bit: the answer equals the thresholded field. */
#include "query_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the neighbourhood bounds ---------------------------------------- */

typedef struct nbr_index {
    gs__db_derived head;
    uint32_t *child;  /* 2 per node (GS_NONE: none)                          */
    uint32_t *vstart; /* n_nodes + 1: leaf L's vertices are                  */
    uint32_t *verts;  /*   verts[vstart[L] .. vstart[L+1]), increasing ids     */
    uint64_t *moff;   /* n_nodes: node N's least minima: mins[moff[N] + k],  */
    float *mins;      /*   k < curve_prefix(N) (+inf: no vertex under N      */
                      /*   reaches the curve)                                */
    double *sphere;   /* 4 per node: centre, radius of the vertices under N  */
                      /*   (radius -1: none)                                 */
} nbr_index;

static void nbr_free(gs__db_derived *h)
{
    nbr_index *ix = (nbr_index *)h;
    if (!ix) return;
    free(ix->child), free(ix->vstart), free(ix->verts), free(ix->moff), free(ix->mins), free(ix->sphere);
    free(ix);
}

static nbr_index *nbr_build(const gs_db *db)
{
    const uint32_t nn = db->n_nodes, nv = db->nv;
    const gs__db_node *nodes = db->nodes;
    nbr_index *ix = gs__calloc(1, sizeof *ix);
    if (!ix) return NULL;
    ix->head.free = nbr_free;
    ix->child = gs__malloc(2 * (size_t)nn, sizeof *ix->child);
    ix->vstart = gs__calloc((size_t)nn + 1, sizeof *ix->vstart);
    ix->verts = gs__malloc(nv ? nv : 1, sizeof *ix->verts);
    ix->moff = gs__malloc((size_t)nn + 1, sizeof *ix->moff);
    ix->sphere = gs__malloc(4 * (size_t)nn, sizeof *ix->sphere);
    double *box = gs__malloc(6 * (size_t)nn, sizeof *box);
    if (!ix->child || !ix->vstart || !ix->verts || !ix->moff || !ix->sphere || !box) goto fail;
    /* children, leaf vertex lists */
    for (size_t i = 0; i < 2 * (size_t)nn; ++i) ix->child[i] = GS_NONE;
    for (uint32_t n = 1; n < nn; ++n) {
        uint32_t p = nodes[n].parent;
        ix->child[2 * (size_t)p + (ix->child[2 * (size_t)p] != GS_NONE)] = n;
    }
    for (uint32_t y = 0; y < nv; ++y)
        if (db->leaf[y] != GS_NONE) ix->vstart[db->leaf[y] + 1]++;
    for (uint32_t n = 0; n < nn; ++n) ix->vstart[n + 1] += ix->vstart[n];
    {
        uint32_t *pos = gs__malloc((size_t)nn, sizeof *pos);
        if (!pos) goto fail;
        memcpy(pos, ix->vstart, (size_t)nn * sizeof *pos);
        for (uint32_t y = 0; y < nv; ++y)
            if (db->leaf[y] != GS_NONE) ix->verts[pos[db->leaf[y]]++] = y;
        free(pos);
    }
    /* least minima: leaves from their vertices' records, then each node
     * from its children (a child's functions extend its parent's) */
    uint64_t total = 0;
    for (uint32_t n = 0; n < nn; ++n) ix->moff[n] = total, total += nodes[n].curve_prefix;
    ix->moff[nn] = total;
    ix->mins = gs__malloc(total ? total : 1, sizeof *ix->mins);
    if (!ix->mins) goto fail;
    for (uint64_t i = 0; i < total; ++i) ix->mins[i] = INFINITY;
    for (uint32_t y = 0; y < nv; ++y) {
        uint32_t l = db->leaf[y];
        if (l == GS_NONE) continue;
        const unsigned char *end, *rec = gs__db_record(db, y, &end);
        const float *m = (const float *)(const void *)rec;
        float *t = ix->mins + ix->moff[l];
        for (uint32_t k = 0; k < nodes[l].curve_prefix; ++k)
            if (!(m[k] >= t[k])) t[k] = m[k] == m[k] ? m[k] : -INFINITY; /* NaN (a corrupt file): no bound */
    }
    for (uint32_t n = nn; n-- > 1;) {
        uint32_t p = nodes[n].parent;
        float *t = ix->mins + ix->moff[p];
        const float *c = ix->mins + ix->moff[n];
        for (uint32_t k = 0; k < nodes[p].curve_prefix; ++k)
            if (c[k] < t[k]) t[k] = c[k];
    }
    /* bounding boxes bottom-up, spheres around their centres */
    for (uint32_t n = 0; n < nn; ++n)
        for (int a = 0; a < 3; ++a) box[6 * (size_t)n + a] = INFINITY, box[6 * (size_t)n + 3 + a] = -INFINITY;
    for (uint32_t y = 0; y < nv; ++y) {
        uint32_t l = db->leaf[y];
        if (l == GS_NONE) continue;
        const double *p = db->xyz + 3 * (size_t)y;
        double *b = box + 6 * (size_t)l;
        for (int a = 0; a < 3; ++a) b[a] = fmin(b[a], p[a]), b[3 + a] = fmax(b[3 + a], p[a]);
    }
    for (uint32_t n = nn; n-- > 1;) {
        double *b = box + 6 * (size_t)nodes[n].parent, *c = box + 6 * (size_t)n;
        for (int a = 0; a < 3; ++a) b[a] = fmin(b[a], c[a]), b[3 + a] = fmax(b[3 + a], c[a]);
    }
    for (uint32_t n = 0; n < nn; ++n) {
        double *s = ix->sphere + 4 * (size_t)n, *b = box + 6 * (size_t)n;
        for (int a = 0; a < 3; ++a) s[a] = 0.5 * (b[a] + b[3 + a]);
        s[3] = -1.0;
    }
    for (uint32_t y = 0; y < nv; ++y) { /* a leaf's sphere holds its vertices */
        if (db->leaf[y] == GS_NONE) continue;
        const double *p = db->xyz + 3 * (size_t)y;
        double *s = ix->sphere + 4 * (size_t)db->leaf[y];
        double dx = p[0] - s[0], dy = p[1] - s[1], dz = p[2] - s[2], d = sqrt(dx * dx + dy * dy + dz * dz);
        if (d > s[3]) s[3] = d;
    }
    for (uint32_t n = nn; n-- > 1;) { /* a node's sphere holds its children's */
        const double *c = ix->sphere + 4 * (size_t)n;
        double *s = ix->sphere + 4 * (size_t)nodes[n].parent;
        if (c[3] < 0.0) continue;
        double dx = c[0] - s[0], dy = c[1] - s[1], dz = c[2] - s[2], d = sqrt(dx * dx + dy * dy + dz * dz) + c[3];
        if (d > s[3]) s[3] = d;
    }
    free(box);
    return ix;
fail:
    free(box);
    nbr_free(&ix->head);
    return NULL;
}

/* The database's bounds, built on first use (by one thread; another that
 * races builds its own and frees it). */
static const nbr_index *nbr_get(const gs_db *db)
{
    gs_db *w = (gs_db *)db; /* derived data only: the file is never written */
    gs__db_derived *h = __atomic_load_n(&w->derived, __ATOMIC_ACQUIRE);
    if (h) return (const nbr_index *)h;
    nbr_index *ix = nbr_build(db);
    if (!ix) return NULL;
    gs__db_derived *expected = NULL;
    if (!__atomic_compare_exchange_n(&w->derived, &expected, &ix->head, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
        nbr_free(&ix->head);
        return (const nbr_index *)expected;
    }
    return ix;
}

/* ---- lower bounds ----------------------------------------------------- */

/* The bounds are lowered a little so that rounding never prunes a vertex
 * the query answers within the radius: the stored minima are at most the
 * functions' values but the minimiser may stop a few ulps lower, and the
 * sphere's distances are rounded. */
#define BOUND_REL 1e-6

typedef struct source {
    const gs_db *db;
    const nbr_index *ix;
    gs__qsrc *q;
    uint32_t x, lx;
    const float *mx; /* x's minima */
    double slack;    /* absolute: 1e-9 of the mesh's size */
} source;

/* min over the functions k < nk of m_x^k + t[k]. */
static double minima_bound(const float *mx, const float *t, uint32_t nk)
{
    double b = INFINITY;
    for (uint32_t k = 0; k < nk; ++k) {
        double v = (double)mx[k] + (double)t[k];
        if (v != v) return -INFINITY; /* a NaN minimum (a corrupt file): no bound */
        if (v < b) b = v;
    }
    return b;
}

/* Whether a vertex at least e from x in space may be one of x's near pairs
 * (section 'near_pairs': exact distances below the separators' answers, so
 * the minima bound does not hold for them; they lie within its radius). */
static int near_possible(const source *s, double e)
{
    return s->db->near.radius2 > 0.0 && (e <= 0.0 || e * e < s->db->near.radius2);
}

static double lowered(const source *s, double b)
{
    return b * (1.0 - BOUND_REL) - s->slack;
}

/* Lower bound on the distance from x to every vertex under node n, whose
 * lowest common ancestor with x's leaf is a (n not on x's root path). */
static double node_bound(const source *s, uint32_t n, uint32_t a)
{
    const double *c = s->ix->sphere + 4 * (size_t)n, *p = s->db->xyz + 3 * (size_t)s->x;
    if (c[3] < 0.0) return INFINITY; /* no vertex under n */
    double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
    double e = sqrt(dx * dx + dy * dy + dz * dz) - c[3];
    uint32_t nk = s->db->nodes[a].curve_prefix + s->db->nodes[a].n_curves;
    double m = near_possible(s, e) ? -INFINITY : minima_bound(s->mx, s->ix->mins + s->ix->moff[n], nk);
    return lowered(s, e > m ? e : m);
}

/* The straight distance from x to y, lowered. */
static double euclid_bound(const source *s, uint32_t y)
{
    const double *q = s->db->xyz + 3 * (size_t)y, *p = s->db->xyz + 3 * (size_t)s->x;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return lowered(s, sqrt(dx * dx + dy * dy + dz * dz));
}

/* Both bounds for one vertex y under such a node. */
static double vertex_bound(const source *s, uint32_t y, uint32_t a)
{
    const double *q = s->db->xyz + 3 * (size_t)y, *p = s->db->xyz + 3 * (size_t)s->x;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    double e = sqrt(dx * dx + dy * dy + dz * dz);
    const unsigned char *end, *rec = gs__db_record(s->db, y, &end);
    uint32_t nk = s->db->nodes[a].curve_prefix + s->db->nodes[a].n_curves;
    double m = near_possible(s, e) ? -INFINITY : minima_bound(s->mx, (const float *)(const void *)rec, nk);
    return lowered(s, e > m ? e : m);
}

static int source_init(source *s, const gs_db *db, uint32_t x, const char *fn, gs_error *err)
{
    memset(s, 0, sizeof *s);
    s->db = db, s->x = x, s->lx = db->leaf[x];
    if (s->lx == GS_NONE) return GS_OK;
    s->ix = nbr_get(db);
    s->q = s->ix ? gs__qsrc_create(db, x) : NULL;
    if (!s->q) return gs__fail(err, GS_ENOMEM, "%s: out of memory for vertex %u's bounds", fn, x);
    s->mx = gs__qsrc_minima(s->q);
    const double *c = s->ix->sphere; /* the root's sphere: the mesh's size */
    s->slack = 1e-9 * (fabs(c[0]) + fabs(c[1]) + fabs(c[2]) + (c[3] > 0.0 ? c[3] : 0.0));
    return GS_OK;
}

/* ---- results ---------------------------------------------------------- */

typedef struct hit {
    double d;
    uint32_t id;
} hit;

typedef struct hits {
    hit *h;
    size_t n, cap;
} hits;

static int hits_add(hits *r, uint32_t id, double d)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        hit *h = gs__realloc(r->h, cap, sizeof *h);
        if (!h) return 0;
        r->h = h, r->cap = cap;
    }
    r->h[r->n].d = d, r->h[r->n].id = id;
    r->n++;
    return 1;
}

static int by_distance(const void *pa, const void *pb)
{
    const hit *a = pa, *b = pb;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* ---- within ----------------------------------------------------------- */

/* Every vertex y with d(x, y) <= r into *res (unsorted). 0: out of memory. */
static int collect(source *s, double r, hits *res)
{
    /* a curve whose bound exceeds cut answers more than r (lowered()) */
    const double cut = (r + s->slack) / (1.0 - BOUND_REL);
    if (s->lx == GS_NONE) return hits_add(res, s->x, 0.0);
    const nbr_index *ix = s->ix;
    /* a stack of (node, its lowest common ancestor with x's leaf; GS_NONE:
     * the node is on x's root path) */
    size_t cap = 64, top = 0;
    uint32_t *st = gs__malloc(2 * cap, sizeof *st);
    if (!st) return 0;
    st[top++] = 0, st[top++] = GS_NONE;
    int ok = 1;
    while (top && ok) {
        uint32_t a = st[--top], n = st[--top];
        if (a != GS_NONE && node_bound(s, n, a) > r) continue;
        const uint32_t *ch = ix->child + 2 * (size_t)n;
        if (ch[0] == GS_NONE) { /* a leaf */
            for (uint32_t i = ix->vstart[n]; i < ix->vstart[n + 1] && ok; ++i) {
                uint32_t y = ix->verts[i];
                double d;
                if (a == GS_NONE) d = gs__qsrc_distance(s->q, y); /* x's own leaf */
                else if (euclid_bound(s, y) > r) continue;
                else d = gs__qsrc_cross_cut(s->q, y, n, a, cut); /* the minima's bound inside */
                if (d <= r && d < INFINITY) ok = hits_add(res, y, d);
            }
            continue;
        }
        for (int c = 0; c < 2 && ch[c] != GS_NONE; ++c) {
            if (top + 2 > 2 * cap) {
                uint32_t *t = gs__realloc(st, 4 * cap, sizeof *st);
                if (!t) {
                    ok = 0;
                    break;
                }
                st = t, cap *= 2;
            }
            uint32_t cn = ch[c];
            st[top++] = cn;
            st[top++] = a != GS_NONE ? a : (gs__qsrc_ancestor(s->q, cn) == cn ? GS_NONE : n);
        }
    }
    free(st);
    return ok;
}

static int neighbors_make(hits *res, gs_neighbors **out)
{
    gs_neighbors *nb = gs__calloc(1, sizeof *nb);
    if (!nb) return 0;
    nb->n = res->n;
    nb->ids = gs__malloc(res->n ? res->n : 1, sizeof *nb->ids);
    nb->dist = gs__malloc(res->n ? res->n : 1, sizeof *nb->dist);
    if (!nb->ids || !nb->dist) {
        gs_neighbors_free(nb);
        return 0;
    }
    for (size_t i = 0; i < res->n; ++i) nb->ids[i] = res->h[i].id, nb->dist[i] = res->h[i].d;
    *out = nb;
    return 1;
}

void gs_neighbors_free(gs_neighbors *nb)
{
    if (!nb) return;
    free(nb->ids);
    free(nb->dist);
    free(nb);
}

static int check_radius(double r, const char *fn, gs_error *err)
{
    if (!(r >= 0.0)) return gs__fail(err, GS_EARG, "%s: radius %g is not a number >= 0", fn, r);
    return GS_OK;
}

int gs_db_within(const gs_db *db, uint32_t x, double r, gs_neighbors **out, gs_error *err)
{
    if (out) *out = NULL;
    if (!db || !out) return gs__fail(err, GS_EARG, "gs_db_within: NULL argument");
    if (x >= db->nv) return gs__fail(err, GS_EARG, "gs_db_within: vertex %u >= n_vertices %u", x, db->nv);
    int rc = check_radius(r, "gs_db_within", err);
    if (rc) return rc;
    source s;
    if ((rc = source_init(&s, db, x, "gs_db_within", err))) return rc;
    hits res = {0};
    int ok = collect(&s, r, &res);
    gs__qsrc_free(s.q);
    if (ok) {
        qsort(res.h, res.n, sizeof *res.h, by_distance);
        ok = neighbors_make(&res, out);
    }
    free(res.h);
    return ok ? GS_OK : gs__fail(err, GS_ENOMEM, "gs_db_within: out of memory (vertex %u, radius %g)", x, r);
}

static int by_id(const void *pa, const void *pb)
{
    const hit *a = pa, *b = pb;
    return (a->id > b->id) - (a->id < b->id);
}

int gs__db_within_row(const gs_db *db, uint32_t x, double r, uint32_t **ids, double **dist, size_t *n,
                      gs_error *err)
{
    *ids = NULL, *dist = NULL, *n = 0;
    source s;
    int rc = source_init(&s, db, x, "gs_db_radius_matrix", err);
    if (rc) return rc;
    hits res = {0};
    int ok = collect(&s, r, &res);
    gs__qsrc_free(s.q);
    if (ok && res.n) {
        qsort(res.h, res.n, sizeof *res.h, by_id);
        *ids = gs__malloc(res.n, sizeof **ids);
        *dist = gs__malloc(res.n, sizeof **dist);
        ok = *ids && *dist;
        for (size_t i = 0; ok && i < res.n; ++i) (*ids)[i] = res.h[i].id, (*dist)[i] = res.h[i].d;
        if (ok) *n = res.n;
        else free(*ids), free(*dist), *ids = NULL, *dist = NULL;
    }
    free(res.h);
    return ok ? GS_OK : gs__fail(err, GS_ENOMEM, "gs_db_radius_matrix: out of memory (vertex %u, radius %g)", x, r);
}

/* ---- the k nearest among candidates ------------------------------------ */

/* Candidates in increasing order of a lower bound; each answered until the
 * bound exceeds the k-th smallest distance found. */
typedef struct cand {
    double lb;
    uint32_t id;
} cand;

static int by_bound(const void *pa, const void *pb)
{
    const cand *a = pa, *b = pb;
    if (a->lb != b->lb) return a->lb < b->lb ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* Max-heap of the k best (by_distance order) hits so far. */
static void heap_sift_down(hit *h, size_t n, size_t i)
{
    for (;;) {
        size_t l = 2 * i + 1, r = l + 1, m = i;
        if (l < n && by_distance(&h[l], &h[m]) > 0) m = l;
        if (r < n && by_distance(&h[r], &h[m]) > 0) m = r;
        if (m == i) return;
        hit t = h[i];
        h[i] = h[m], h[m] = t;
        i = m;
    }
}

static void heap_push(hit *h, size_t *n, hit v)
{
    size_t i = (*n)++;
    h[i] = v;
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (by_distance(&h[p], &h[i]) >= 0) break;
        hit t = h[i];
        h[i] = h[p], h[p] = t;
        i = p;
    }
}

int gs_db_nearest(const gs_db *db, uint32_t x, const uint32_t *candidates, size_t n_candidates, size_t k,
                  gs_neighbors **out, gs_error *err)
{
    if (out) *out = NULL;
    if (!db || !out || (n_candidates && !candidates)) return gs__fail(err, GS_EARG, "gs_db_nearest: NULL argument");
    if (x >= db->nv) return gs__fail(err, GS_EARG, "gs_db_nearest: vertex %u >= n_vertices %u", x, db->nv);
    for (size_t i = 0; i < n_candidates; ++i)
        if (candidates[i] >= db->nv)
            return gs__fail(err, GS_EARG, "gs_db_nearest: candidate %zu is vertex %u >= n_vertices %u", i,
                            candidates[i], db->nv);
    source s;
    int rc = source_init(&s, db, x, "gs_db_nearest", err);
    if (rc) return rc;
    cand *c = gs__malloc(n_candidates ? n_candidates : 1, sizeof *c);
    hit *h = gs__malloc(k < n_candidates ? k + 1 : n_candidates + 1, sizeof *h);
    hits res = {0};
    int ok = c && h;
    for (size_t i = 0; ok && i < n_candidates; ++i) {
        uint32_t y = candidates[i], ly = db->leaf[y];
        c[i].id = y;
        if (y == x || s.lx == GS_NONE || ly == GS_NONE || ly == s.lx) c[i].lb = y == x ? 0.0 : -INFINITY;
        else c[i].lb = vertex_bound(&s, y, gs__qsrc_ancestor(s.q, ly));
        if (c[i].lb != c[i].lb) c[i].lb = -INFINITY; /* a corrupt minimum: answer it */
    }
    size_t nh = 0;
    if (ok) qsort(c, n_candidates, sizeof *c, by_bound);
    for (size_t i = 0; ok && i < n_candidates && k; ++i) {
        if (i && c[i].id == c[i - 1].id) continue; /* a repeated candidate */
        if (nh == k && c[i].lb > h[0].d) break; /* every other one is farther */
        hit v;
        v.id = c[i].id;
        v.d = s.q ? gs__qsrc_distance(s.q, v.id) : (v.id == x ? 0.0 : INFINITY);
        if (v.d != v.d) v.d = INFINITY; /* corrupt: never among the nearest */
        if (nh < k) heap_push(h, &nh, v);
        else if (by_distance(&v, &h[0]) < 0) h[0] = v, heap_sift_down(h, nh, 0);
    }
    if (ok) {
        qsort(h, nh, sizeof *h, by_distance);
        res.h = h, res.n = nh;
        ok = neighbors_make(&res, out);
    }
    gs__qsrc_free(s.q);
    free(c);
    free(h);
    return ok ? GS_OK : gs__fail(err, GS_ENOMEM, "gs_db_nearest: out of memory (%zu candidates)", n_candidates);
}
