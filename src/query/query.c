/* query.c - online point-to-point queries (paper sec. 3.2, eq. 4-5, Theorem
 * 2.1): same leaf -> Euclidean (or the stored exact table); otherwise the
 * minimum over the curves of the common ancestors, with the quick reject on
 * the stored minima. The hot path: no allocation, no locks. */
#include "../db/db_internal.h"

#include <math.h>

#define FIELD_MAX_DEPTH 512 /* x's ancestors by depth kept on the stack     */

/* x's coordinates: large caches keep a copy in x's slot, which the query
 * reads anyway. */
static inline const double *coords(const gs_db *db, uint32_t x)
{
    return db->qlev ? db->qroot + (size_t)x * db->qslot + GS_QSLOT_XYZ : db->xyz + 3 * (size_t)x;
}

static double euclidean(const gs_db *db, uint32_t x, uint32_t y)
{
    const double *p = coords(db, x), *q = coords(db, y);
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* A geodesic is never shorter than the straight segment: the bound catches a
 * fitted function that dips too low. */
static double at_least_euclidean(const gs_db *db, uint32_t x, uint32_t y, double d)
{
    double e = euclidean(db, x, y);
    return d < e ? e : d;
}

static double same_leaf(const gs_db *db, uint32_t l, uint32_t x, uint32_t y)
{
    if (db->leaf_dist) { /* never below the straight segment, as cross-leaf answers */
        uint64_t n = (uint64_t)db->leaf_vstart[l + 1] - db->leaf_vstart[l];
        return at_least_euclidean(db, x, y, db->leaf_dist[db->leaf_dstart[l] + db->leaf_local[x] * n + db->leaf_local[y]]);
    }
    return euclidean(db, x, y);
}

/* Lowest common ancestor: parents have smaller depth (validated), so both
 * walks end at the root at the latest. */
static uint32_t lowest_common_ancestor(const gs_db_node *nodes, uint32_t a, uint32_t b)
{
    while (nodes[a].depth > nodes[b].depth) a = nodes[a].parent;
    while (nodes[b].depth > nodes[a].depth) b = nodes[b].parent;
    while (a != b) a = nodes[a].parent, b = nodes[b].parent;
    return a;
}

/* The lowest common ancestor of two different leaves from the slots'
 * headers: the first depth where their ancestors differ (both have the
 * root at depth 0); the tree walk when they agree down to GS_QANC - 1. */
static uint32_t lca_of_slots(const gs_db *db, const gs_qvert *hx, const gs_qvert *hy)
{
    for (uint32_t d = 1; d < GS_QANC; ++d)
        if (hx->anc[d] != hy->anc[d]) return hx->anc[d - 1];
    return lowest_common_ancestor(db->nodes, hx->leaf, hy->leaf);
}

/* Candidate curves of a query: the lower bound minval_x + minval_y of each
 * common curve, and the curve's function index. */
typedef struct candidate {
    double bound;
    uint32_t k, curve;
} candidate;

#define MAX_CANDIDATES 64

/* Gather the common curves of `top` and its ancestors, bottom-up, sorted by
 * their quick-reject bound (stable: bottom-up order breaks ties). Visiting
 * the most promising curve first makes the quick reject skip more pair
 * minimisations than the paper's plain bottom-up order (bunny-5k: 1.41
 * instead of 2.05 per query) and gives the same minimum. ex, ey: the two
 * vertices' entries (the file's, minval first, stride `stride` bytes, or
 * the cache's floats: flt). Returns the number gathered; *rest is the node
 * where gathering stopped (GS_NONE: all). */
static inline uint32_t gather_t(const gs_db *db, const char *ex, const char *ey, size_t stride, int flt, uint32_t top,
                                candidate *c, uint32_t *rest)
{
    uint32_t n = 0, a = top;
    for (; a != GS_NONE; a = db->nodes[a].parent) {
        uint32_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        if (n + (k1 - k0) > MAX_CANDIDATES) break;
        for (uint32_t k = k0; k < k1; ++k) {
            double b = flt ? (double)((const float *)ex)[k] + (double)((const float *)ey)[k]
                           : *(const double *)(ex + k * stride) + *(const double *)(ey + k * stride);
            uint32_t i = n++;
            for (; i > 0 && c[i - 1].bound > b; --i) c[i] = c[i - 1];
            c[i].bound = b, c[i].k = k, c[i].curve = db->nodes[a].curve_start + (k - k0);
        }
    }
    *rest = a;
    return n;
}

/* the file's entries (minval first, stride `stride` bytes) */
static uint32_t gather(const gs_db *db, const char *ex, const char *ey, size_t stride, uint32_t top, candidate *c,
                       uint32_t *rest)
{
    return gather_t(db, ex, ey, stride, 0, top, c, rest);
}

/* the cache's entries (floats) */
static uint32_t gather_cached(const gs_db *db, const float *ex, const float *ey, uint32_t top, candidate *c,
                              uint32_t *rest)
{
    return gather_t(db, (const char *)ex, (const char *)ey, sizeof(float), 1, top, c, rest);
}

/* ---- with the query cache (src/query/grid.c) ---- */

/* A vertex's view of the query cache (src/db/db_internal.h): its slot s
 * (header, the shallow curves' entries and records), its block b (all
 * entries, the other records), nf and ns. */
typedef struct qview {
    const double *s, *b;
    uint32_t nf, ns;
} qview;

static inline const double *slot_of(const gs_db *db, uint32_t x)
{
    return db->qroot + (size_t)x * db->qslot;
}

static inline qview view_of(const gs_db *db, uint32_t x)
{
    const double *s = slot_of(db, x);
    const gs_qvert *h = (const gs_qvert *)s;
    qview v = {s, db->qbuf + h->start, h->nf, db->qlev ? h->ns : 0};
    return v;
}

/* The record of function k (curve c) of a vertex: in the slot for the
 * shallow curves, else in the block. */
static inline const double *record_of(const gs_db *db, const qview *v, uint32_t k, uint32_t c)
{
    return k < v->ns ? v->s + gs__qrec_in_slot(db, c) : v->b + gs__qrec_in_block(db, v->nf, c);
}

/* The function of a record (reachable: minval finite); g its grid. */
static inline void cached_fun(const double *rec, uint32_t g, gs_fun *f)
{
    uint32_t m = gs__qrec_meta(rec);
    f->kind = GS_META_KIND(m);
    f->degree = GS_META_DEGREE(m);
    f->squared = GS_META_SQUARED(m);
    f->closed = GS_META_CLOSED(m);
    f->minval = rec[5];
    f->shift = rec[0];
    f->coef = gs__qrec_coef(rec, g);
}

/* The prefetch helpers are always inlined: GCC counts __builtin_prefetch
 * as free of side effects, so a helper left out of line is found "const"
 * or "pure" and its calls are deleted (GCC 12 -O2 removed every one). */
#if defined(__GNUC__)
#define PREFETCH_FN inline __attribute__((always_inline))
#else
#define PREFETCH_FN inline
#endif

static PREFETCH_FN void prefetch_lines(const void *p, size_t bytes)
{
    if (!bytes) return;
    const char *r = p, *e = r + bytes - 1;
    for (; r < e; r += 64) __builtin_prefetch(r);
    __builtin_prefetch(e);
}

/* Start fetching the record of curve c (not a shallow one: those come
 * with the slot) in a vertex's block: all its lines (head, grid and
 * coefficients), so that the coefficients arrive while the grid is
 * scanned. */
static PREFETCH_FN void prefetch_record(const gs_db *db, const qview *v, uint32_t c)
{
    /* small caches (qlev 0) keep every record in the block: no need to look
     * up the curve's depth */
    if (!db->qlev || db->nodes[db->curves[c].node].depth >= db->qlev)
        prefetch_lines(v->b + gs__qrec_in_block(db, v->nf, c), 8 * (size_t)db->qclen[c]);
}

/* min over curve c (function k) of f_x + f_y; x < y (the order of the two
 * functions makes d(x,y) == d(y,x) bit for bit). */
static double cached_pair(const gs_db *db, const qview *vx, const qview *vy, uint32_t k, uint32_t c)
{
    gs_fun fx, fy;
    const double *rx = record_of(db, vx, k, c), *ry = record_of(db, vy, k, c);
    uint32_t g = db->qgrid[c];
    cached_fun(rx, g, &fx), cached_fun(ry, g, &fy);
    if (!g) return gs_fun_pair_min(&fx, &fy, NULL);
    gs_fun_dip dx, dy;
    gs__qrec_dip(rx, &dx);
    gs__qrec_dip(ry, &dy);
    gs_fun_grid gx = gs__qrec_values(rx), gy = gs__qrec_values(ry);
    return gs_fun_pair_min_grid(&fx, &fy, &gx, &gy, g, &dx, &dy, NULL);
}

/* Start fetching what cross_cached reads beyond the slots' heads: the rest
 * of the slots (top below the root) and, for a top at least qlev deep, the
 * entries gather reads and the records of top's first curves, which hold
 * the minimum most often (they come while the entries arrive). Returns
 * whether top is that deep (its curves' entries are in the blocks). */
static PREFETCH_FN int prefetch_cross(const gs_db *db, const qview *vx, const qview *vy, uint32_t top)
{
    int deep = db->nodes[top].depth >= db->qlev;
    if (db->nodes[top].depth && db->qslot0 < db->qslot) /* below the root: the rest of the slots */
        prefetch_lines(vx->s + db->qslot0, 8 * (size_t)(db->qslot - db->qslot0)),
            prefetch_lines(vy->s + db->qslot0, 8 * (size_t)(db->qslot - db->qslot0));
    if (deep) { /* the entries of top's curves and its ancestors' */
        size_t ne = sizeof(float) * ((size_t)db->nodes[top].curve_prefix + db->nodes[top].n_curves);
        prefetch_lines(vx->b, ne), prefetch_lines(vy->b, ne);
    }
    for (uint32_t j = 0; deep && j < db->nodes[top].n_curves && j < 2; ++j) {
        uint32_t c = db->nodes[top].curve_start + j;
        prefetch_record(db, vx, c), prefetch_record(db, vy, c);
    }
    return deep;
}

/* eq. 4-5 with the quick reject, x < y. When the lowest common ancestor
 * is shallower than db->qlev, the slots hold all that is needed. */
static double cross_cached(const gs_db *db, uint32_t x, uint32_t y, uint32_t top)
{
    qview vx = view_of(db, x), vy = view_of(db, y);
    int deep = prefetch_cross(db, &vx, &vy, top);
    const float *ex = (const float *)(deep ? vx.b : vx.s + GS_QSLOT_HEAD);
    const float *ey = (const float *)(deep ? vy.b : vy.s + GS_QSLOT_HEAD);
    candidate c[MAX_CANDIDATES];
    uint32_t rest, n = gather_cached(db, ex, ey, top, c, &rest);
    if (n && db->curves[c[0].curve].node != top) prefetch_record(db, &vx, c[0].curve), prefetch_record(db, &vy, c[0].curve);
    double best = INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        if (c[i].bound >= best) break; /* sorted: all others rejected too (and unreachable) */
        if (i + 1 < n) prefetch_record(db, &vx, c[i + 1].curve), prefetch_record(db, &vy, c[i + 1].curve);
        double d = cached_pair(db, &vx, &vy, c[i].k, c[i].curve);
        if (d < best) best = d;
    }
    for (uint32_t a = rest; a != GS_NONE; a = db->nodes[a].parent) { /* > 64 curves: rare */
        uint32_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        for (uint32_t k = k0; k < k1; ++k) {
            if ((double)ex[k] + (double)ey[k] >= best) continue;
            double d = cached_pair(db, &vx, &vy, k, db->nodes[a].curve_start + (k - k0));
            if (d < best) best = d;
        }
    }
    return best;
}

/* ---- without it (absurdly deep trees): the file's sections ---- */

static double file_pair(const gs_db *db, uint32_t x, uint32_t y, uint32_t k)
{
    gs_fun fx, fy;
    gs__db_fun(db, x, k, &fx);
    gs__db_fun(db, y, k, &fy);
    return gs_fun_pair_min(&fx, &fy, NULL);
}

static double cross_file(const gs_db *db, uint32_t x, uint32_t y, uint32_t top)
{
    const gs_db_fentry *ex = db->funs + db->vdir[x].first_function;
    const gs_db_fentry *ey = db->funs + db->vdir[y].first_function;
    candidate c[MAX_CANDIDATES];
    uint32_t rest, n = gather(db, (const char *)ex, (const char *)ey, sizeof *ex, top, c, &rest);
    double best = INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        if (c[i].bound >= best) break;
        double d = file_pair(db, x, y, c[i].k);
        if (d < best) best = d;
    }
    for (uint32_t a = rest; a != GS_NONE; a = db->nodes[a].parent) {
        uint32_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        for (uint32_t k = k0; k < k1; ++k) {
            if (ex[k].minval + ey[k].minval >= best) continue;
            double d = file_pair(db, x, y, k);
            if (d < best) best = d;
        }
    }
    return best;
}

/* Cross-leaf distance of x != y (any order), top their leaves' lowest common
 * ancestor: the two go in vertex-id order so that d(x,y) == d(y,x). */
static double cross_leaf(const gs_db *db, uint32_t x, uint32_t y, uint32_t top)
{
    uint32_t lo = x < y ? x : y, hi = x < y ? y : x;
    double d = db->qbuf ? cross_cached(db, lo, hi, top) : cross_file(db, lo, hi, top);
    return at_least_euclidean(db, x, y, d);
}

/* With the query cache: start fetching the heads of x's and y's slots (their
 * addresses need no lookup) and, for small caches, the coordinates. */
static PREFETCH_FN void prefetch_slots(const gs_db *db, uint32_t x, uint32_t y)
{
    prefetch_lines(slot_of(db, x), 8 * (size_t)db->qslot0), prefetch_lines(slot_of(db, y), 8 * (size_t)db->qslot0);
    if (!db->qlev) __builtin_prefetch(db->xyz + 3 * (size_t)x), __builtin_prefetch(db->xyz + 3 * (size_t)y);
}

/* The batch's first stage: the first line of x's and y's slots, their
 * headers (nothing for an out-of-range id). */
static PREFETCH_FN void prefetch_headers(const gs_db *db, uint32_t x, uint32_t y)
{
    if (x < db->nv && y < db->nv) __builtin_prefetch(slot_of(db, x)), __builtin_prefetch(slot_of(db, y));
}

/* Header-only slots (qlev 0), different leaves: start fetching the blocks'
 * entries and root records. */
static PREFETCH_FN void prefetch_blocks(const gs_db *db, const gs_qvert *hx, const gs_qvert *hy)
{
    prefetch_lines(db->qbuf + hx->start, 8 * (gs__qent_doubles(hx->nf) + db->qhead));
    prefetch_lines(db->qbuf + hy->start, 8 * (gs__qent_doubles(hy->nf) + db->qhead));
}

static inline uint32_t lca_cached(const gs_db *db, const gs_qvert *hx, const gs_qvert *hy)
{
    return db->qlev ? lca_of_slots(db, hx, hy) : lowest_common_ancestor(db->nodes, hx->leaf, hy->leaf);
}

double gs_db_distance(const gs_db *db, uint32_t x, uint32_t y)
{
    if (!db || x >= db->nv || y >= db->nv) return NAN;
    if (x == y) return 0.0;
    if (!db->qbuf) {
        uint32_t lx = db->leaf[x], ly = db->leaf[y];
        if (lx == GS_NONE || ly == GS_NONE) return INFINITY;
        if (lx == ly) return same_leaf(db, lx, x, y);
        return cross_leaf(db, x, y, lowest_common_ancestor(db->nodes, lx, ly));
    }
    prefetch_slots(db, x, y);
    const gs_qvert *hx = (const gs_qvert *)slot_of(db, x), *hy = (const gs_qvert *)slot_of(db, y);
    uint32_t lx = hx->leaf, ly = hy->leaf;
    if (lx == GS_NONE || ly == GS_NONE) return INFINITY;
    if (lx == ly) return same_leaf(db, lx, x, y);
    if (!db->qlev) prefetch_blocks(db, hx, hy);
    return cross_leaf(db, x, y, lca_cached(db, hx, hy));
}

/* The batch's second stage for a pair whose slot headers were requested
 * earlier: the rest of the slot heads and, from the headers (there by now,
 * most often), what its query will read next (gs_db_distance's and
 * cross_cached's prefetches, done ahead). */
static PREFETCH_FN void prefetch_pair(const gs_db *db, uint32_t x, uint32_t y)
{
    if (x >= db->nv || y >= db->nv || x == y) return;
    prefetch_slots(db, x, y);
    const gs_qvert *hx = (const gs_qvert *)slot_of(db, x), *hy = (const gs_qvert *)slot_of(db, y);
    if (hx->leaf == GS_NONE || hy->leaf == GS_NONE || hx->leaf == hy->leaf) return;
    if (!db->qlev) prefetch_blocks(db, hx, hy);
    qview vx = view_of(db, x), vy = view_of(db, y);
    prefetch_cross(db, &vx, &vy, lca_cached(db, hx, hy));
}

/* Pipeline of the batch: while pair i is answered, the slot headers (one
 * line each) of pair i + 2 BATCH_AHEAD are requested, and pair i +
 * BATCH_AHEAD's second stage (prefetch_pair) runs: so a batch waits for
 * memory in parallel over several pairs, where a single query waits for
 * its misses one after the other. Requesting whole slot heads at the first
 * stage was slower (homer-960k: too many lines in flight at once). The
 * answers are gs_db_distance's, bit for bit (only prefetches are added). */
enum { BATCH_AHEAD = 4 };

/* Out-of-range ids give NaN in out[] and GS_EARG naming the first one; the
 * other pairs are still answered. */
int gs_db_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out, gs_error *err)
{
    if (!db || (n && (!pairs || !out))) return gs__fail(err, GS_EARG, "gs_db_distances: NULL argument");
    size_t bad = SIZE_MAX;
    const size_t a = BATCH_AHEAD;
    for (size_t i = 0; db->qbuf && i < 2 * a && i < n; ++i) prefetch_headers(db, pairs[2 * i], pairs[2 * i + 1]);
    for (size_t i = 0; i < n; ++i) {
        if (db->qbuf) {
            if (i + 2 * a < n) prefetch_headers(db, pairs[2 * (i + 2 * a)], pairs[2 * (i + 2 * a) + 1]);
            if (i + a < n) prefetch_pair(db, pairs[2 * (i + a)], pairs[2 * (i + a) + 1]);
        }
        out[i] = gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        if (bad == SIZE_MAX && (pairs[2 * i] >= db->nv || pairs[2 * i + 1] >= db->nv)) bad = i;
    }
    if (bad != SIZE_MAX)
        return gs__fail(err, GS_EARG, "gs_db_distances: pair %zu (%u, %u) has a vertex id >= n_vertices %u", bad,
                        pairs[2 * bad], pairs[2 * bad + 1], db->nv);
    return GS_OK;
}

/* ---- fields: x's ancestors marked by depth ---- */

typedef struct field_ctx {
    const gs_db *db;
    uint32_t x, lx, depth_x;
    uint32_t anc[FIELD_MAX_DEPTH]; /* anc[d]: x's ancestor at depth d      */
} field_ctx;

static double field_cross(const field_ctx *c, uint32_t y, uint32_t ly)
{
    const gs_db *db = c->db;
    uint32_t a = ly;
    while (db->nodes[a].depth > c->depth_x || c->anc[db->nodes[a].depth] != a) a = db->nodes[a].parent;
    return cross_leaf(db, c->x, y, a);
}

static void field_fast(field_ctx *c, double *out)
{
    const gs_db *db = c->db;
    for (uint32_t a = c->lx; a != GS_NONE; a = db->nodes[a].parent) c->anc[db->nodes[a].depth] = a;
    for (uint32_t y = 0; y < db->nv; ++y) {
        uint32_t ly = db->leaf[y];
        if (y == c->x) out[y] = 0.0;
        else if (ly == GS_NONE) out[y] = INFINITY;
        else if (ly == c->lx) out[y] = same_leaf(db, ly, c->x, y);
        else out[y] = field_cross(c, y, ly);
    }
}

int gs_db_field(const gs_db *db, uint32_t x, double *out, gs_error *err)
{
    if (!db || !out) return gs__fail(err, GS_EARG, "gs_db_field: NULL argument");
    if (x >= db->nv) return gs__fail(err, GS_EARG, "gs_db_field: vertex %u >= n_vertices %u", x, db->nv);
    uint32_t lx = db->leaf[x];
    if (lx == GS_NONE) {
        for (uint32_t y = 0; y < db->nv; ++y) out[y] = y == x ? 0.0 : INFINITY;
        return GS_OK;
    }
    if (db->nodes[lx].depth >= FIELD_MAX_DEPTH) {
        for (uint32_t y = 0; y < db->nv; ++y) out[y] = gs_db_distance(db, x, y);
        return GS_OK;
    }
    field_ctx c; /* ~2 KB on the stack; no heap allocation */
    c.db = db;
    c.x = x;
    c.lx = lx;
    c.depth_x = db->nodes[lx].depth;
    field_fast(&c, out);
    return GS_OK;
}
