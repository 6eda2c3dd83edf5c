/* query.c - online point-to-point queries (paper sec. 3.2, eq. 4-5, Theorem
 * 2.1): same leaf -> Euclidean (or the stored exact table); otherwise the
 * minimum over the curves of the common ancestors, with the quick reject on
 * the stored minima. The hot path: no allocation, no locks. */
#include "../db/db_internal.h"

#include <math.h>

#define FIELD_MAX_FUNS 512  /* x's decoded functions kept on the stack      */
#define FIELD_MAX_DEPTH 512 /* x's ancestors by depth kept on the stack     */

static double euclidean(const gs_db *db, uint32_t x, uint32_t y)
{
    const double *p = db->xyz + 3 * (size_t)x, *q = db->xyz + 3 * (size_t)y;
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
    if (db->leaf_dist) {
        uint64_t n = (uint64_t)db->leaf_vstart[l + 1] - db->leaf_vstart[l];
        return db->leaf_dist[db->leaf_dstart[l] + db->leaf_local[x] * n + db->leaf_local[y]];
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

/* Candidate curves of a query: the lower bound minval_x + minval_y of each
 * common curve, and the curve's function index. */
typedef struct candidate {
    double bound;
    uint64_t k;
    uint32_t curve;
} candidate;

#define MAX_CANDIDATES 64

/* Gather the common curves of `top` and its ancestors, bottom-up, sorted by
 * their quick-reject bound (stable: bottom-up order breaks ties). Visiting
 * the most promising curve first makes the quick reject skip more pair
 * minimisations than the paper's plain bottom-up order (bunny-5k: 1.41
 * instead of 2.05 per query) and gives the same minimum. Returns the number
 * gathered; *rest is the node where gathering stopped (GS_NONE: all). */
static uint32_t gather(const gs_db *db, const gs_db_fentry *ex, const gs_db_fentry *ey, uint32_t top,
                       candidate *c, uint32_t *rest)
{
    uint32_t n = 0, a = top;
    for (; a != GS_NONE; a = db->nodes[a].parent) {
        uint64_t k0 = db->nodes[a].curve_prefix, k1 = k0 + db->nodes[a].n_curves;
        if (n + (k1 - k0) > MAX_CANDIDATES) break;
        for (uint64_t k = k0; k < k1; ++k) {
            double b = ex[k].minval + ey[k].minval;
            uint32_t i = n++;
            for (; i > 0 && c[i - 1].bound > b; --i) c[i] = c[i - 1];
            c[i].bound = b, c[i].k = k, c[i].curve = db->nodes[a].curve_start + (uint32_t)(k - k0);
        }
    }
    *rest = a;
    return n;
}

/* min over the curve of f_x + f_y, from the query cache when it is there.
 * The two functions go in vertex-id order, so that d(x,y) == d(y,x). */
static double pair_min(const gs_db *db, uint32_t x, uint32_t y, uint64_t k, uint32_t curve,
                       const gs_fun *fx, const gs_fun *fy)
{
    uint32_t g = db->grid ? db->curve_grid[curve] : 0;
    if (x > y) {
        const gs_fun *t = fx;
        fx = fy, fy = t;
        uint32_t u = x;
        x = y, y = u;
    }
    if (!g) return gs_fun_pair_min(fx, fy, NULL);
    uint64_t ix = db->vdir[x].first_function + k, iy = db->vdir[y].first_function + k;
    return gs_fun_pair_min_grid(fx, fy, db->grid + db->grid_start[ix], db->grid + db->grid_start[iy], g,
                                db->umin[ix], db->umin[iy], NULL);
}

/* eq. 4-5 with the quick reject. fx: x's decoded functions, or NULL. The
 * two functions of a pair go to the minimiser in vertex-id order, so that
 * d(x,y) == d(y,x) bit for bit. */
static double cross_leaf(const gs_db *db, const gs_fun *fx, uint32_t x, uint32_t y, uint32_t top)
{
    const gs_db_fentry *ex = db->funs + db->vdir[x].first_function;
    const gs_db_fentry *ey = db->funs + db->vdir[y].first_function;
    candidate c[MAX_CANDIDATES];
    uint32_t rest, n = gather(db, ex, ey, top, c, &rest);
    double best = INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        if (c[i].bound >= best) break; /* sorted: all others rejected too (and unreachable) */
        gs_fun gx, gy;
        if (!fx) gs__db_fun(db, x, c[i].k, &gx);
        gs__db_fun(db, y, c[i].k, &gy);
        const gs_fun *a = fx ? &fx[c[i].k] : &gx;
        double d = pair_min(db, x, y, c[i].k, c[i].curve, a, &gy);
        if (d < best) best = d;
    }
    for (uint32_t a_node = rest; a_node != GS_NONE; a_node = db->nodes[a_node].parent) { /* > 64 curves: rare */
        uint64_t k0 = db->nodes[a_node].curve_prefix, k1 = k0 + db->nodes[a_node].n_curves;
        for (uint64_t k = k0; k < k1; ++k) {
            if (ex[k].minval + ey[k].minval >= best) continue;
            gs_fun gx, gy;
            if (!fx) gs__db_fun(db, x, k, &gx);
            gs__db_fun(db, y, k, &gy);
            const gs_fun *a = fx ? &fx[k] : &gx;
            double d = pair_min(db, x, y, k, db->nodes[a_node].curve_start + (uint32_t)(k - k0), a, &gy);
            if (d < best) best = d;
        }
    }
    return best;
}

double gs_db_distance(const gs_db *db, uint32_t x, uint32_t y)
{
    if (!db || x >= db->nv || y >= db->nv) return NAN;
    if (x == y) return 0.0;
    uint32_t lx = db->leaf[x], ly = db->leaf[y];
    if (lx == GS_NONE || ly == GS_NONE) return INFINITY;
    if (lx == ly) return same_leaf(db, lx, x, y);
    return at_least_euclidean(db, x, y, cross_leaf(db, NULL, x, y, lowest_common_ancestor(db->nodes, lx, ly)));
}

/* Out-of-range ids give NaN in out[] and GS_EARG naming the first one; the
 * other pairs are still answered. */
int gs_db_distances(const gs_db *db, const uint32_t *pairs, size_t n, double *out, gs_error *err)
{
    if (!db || (n && (!pairs || !out))) return gs__fail(err, GS_EARG, "gs_db_distances: NULL argument");
    size_t bad = SIZE_MAX;
    for (size_t i = 0; i < n; ++i) {
        out[i] = gs_db_distance(db, pairs[2 * i], pairs[2 * i + 1]);
        if (bad == SIZE_MAX && (pairs[2 * i] >= db->nv || pairs[2 * i + 1] >= db->nv)) bad = i;
    }
    if (bad != SIZE_MAX)
        return gs__fail(err, GS_EARG, "gs_db_distances: pair %zu (%u, %u) has a vertex id >= n_vertices %u", bad,
                        pairs[2 * bad], pairs[2 * bad + 1], db->nv);
    return GS_OK;
}

/* ---- fields: x's functions decoded once, its ancestors marked by depth ---- */

typedef struct field_ctx {
    const gs_db *db;
    uint32_t x, lx, depth_x;
    uint32_t anc[FIELD_MAX_DEPTH]; /* anc[d]: x's ancestor at depth d      */
    gs_fun fx[FIELD_MAX_FUNS];
} field_ctx;

static double field_cross(const field_ctx *c, uint32_t y, uint32_t ly)
{
    const gs_db *db = c->db;
    uint32_t a = ly;
    while (db->nodes[a].depth > c->depth_x || c->anc[db->nodes[a].depth] != a) a = db->nodes[a].parent;
    return at_least_euclidean(db, c->x, y, cross_leaf(db, c->fx, c->x, y, a));
}

static void field_fast(field_ctx *c, double *out)
{
    const gs_db *db = c->db;
    uint32_t nf = db->nodes[c->lx].curve_prefix;
    for (uint32_t k = 0; k < nf; ++k) gs__db_fun(db, c->x, k, &c->fx[k]);
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
    if (db->nodes[lx].curve_prefix > FIELD_MAX_FUNS || db->nodes[lx].depth >= FIELD_MAX_DEPTH) {
        for (uint32_t y = 0; y < db->nv; ++y) out[y] = gs_db_distance(db, x, y);
        return GS_OK;
    }
    field_ctx c; /* ~30 KB on the stack; no heap allocation */
    c.db = db;
    c.x = x;
    c.lx = lx;
    c.depth_x = db->nodes[lx].depth;
    field_fast(&c, out);
    return GS_OK;
}
