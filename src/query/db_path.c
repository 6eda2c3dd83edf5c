/* db_path.c - geodesic paths from a database (doc/paths.md, "From a
 * database"): a path between two vertices or surface points of the mesh the
 * database was built from, without solving a field.
 * One file (about 2,350 lines) on purpose: the four stages below share one
 * path context (the descent's distance cache, the sleeve, the unfolding)
 * and each hands the next its half-built state; split, every part would
 * export that context.
 *
 * 1. Descent along the valley. The points p of the shortest path are where
 *    g(p) = d(X, p) + d(p, Y) is smallest (= d(X, Y)); elsewhere g grows
 *    with the square of the distance to the path. From a corner of Y's
 *    face the path walks the mesh's edges to a corner of X's face: at each
 *    vertex v, to the neighbour n of smallest g(n) among those strictly
 *    closer to X than v (database distances to a corner of each end's
 *    face). Following the valley floor of g keeps the walk within about an
 *    edge of the shortest path where following the slope of d(X, .) alone
 *    drifts with the fitted functions' slope errors (on bunny-5k 1% of the
 *    paths then ended 1-2% long, on another local geodesic); far from
 *    both ends, where that floor is flat across the path, only among the
 *    neighbours that come steeply closer (STEEP). A vertex
 *    without a closer neighbour (a fitted function's dip) escapes to the
 *    nearest vertex that is closer (Dijkstra on the edges, a few thousand
 *    vertices at most; else A* to X, Euclidean heuristic, for the rest).
 *    The distances come from the two ends' kept query sources (gs__qsrc:
 *    each end's functions decoded once), bit for bit gs_db_distance's
 *    (a neighbour's d(X, .) asked with a cut at d(X, v): above it, only
 *    known to be).
 * 2. Sleeve. The vertex path becomes a strip of faces ("sleeve"): around
 *    each vertex, the faces on the side of the smaller angle between the
 *    edges it arrives and leaves by.
 * 3. Shortening. The sleeve is unfolded into the plane and the shortest
 *    path inside it found by the funnel algorithm (Lee & Preparata): a
 *    polyline that bends only at sleeve vertices. At a bend vertex v whose
 *    angle on the far side (v's total angle minus the path's angle on the
 *    sleeve's side) is below pi, the path is shortened by going round v on
 *    that side: the sleeve's faces at v are replaced by v's other faces
 *    (the extrinsic counterpart of Sharp & Crane 2020's edge flips). Repeat
 *    until no such vertex is left: the path is then locally shortest (a
 *    geodesic: straight in every face and across every edge, bending only
 *    at saddle or boundary vertices, with at least pi on each side); or
 *    until it has settled (after 16 rounds, 8 rounds gain less than 5e-4
 *    of its length: a walk far off the geodesic over a nearly flat
 *    stretch would slide across it one vertex per round for a hundred
 *    rounds).
 *
 * The result is a real path on the surface, so it is never shorter than
 * the exact distance; the descent puts it in the shortest path's
 * neighbourhood, and the shortening makes it the geodesic there.
 * The database is only read; every call allocates its own work space:
 * thread-safe. */
#include "../db/db_internal.h"
#include "../geodesic/geodesic_internal.h"
#include "../core/idmap.h"
#include "../mesh/mesh_internal.h"
#include "query_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- points -------------------------------------------------------------- */

enum { Q_VERTEX, Q_EDGE, Q_FACE };

/* A surface point: vertex a; (1 - t) a + t b on edge (a, b); or bary in
 * face f. seg: the face of the segment leaving it. */
typedef struct qpt {
    int type;
    uint32_t a, b, f;
    double t, bary[3];
    uint32_t seg;
} qpt;

typedef struct p2 {
    double x, y;
} p2;

static inline double cross3(p2 o, p2 a, p2 b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

static inline int eq2(p2 a, p2 b)
{
    return a.x == b.x && a.y == b.y;
}

/* A bend of the funnel's path: a sleeve vertex (v, at funnel portal idx)
 * or an end (v = GS_NONE); seen: the last portal the funnel had read when
 * it placed it. */
typedef struct apex {
    p2 p;
    uint32_t v, idx, seen;
} apex;

/* How sleeve face i joins face i - 1 (sd[i], i >= 1): the corner hk of
 * face i - 1 whose half-edge h they share, its twin's corner ok in face i,
 * the third vertex of face i in the edge's frame (placement), the edge's
 * ends (lv = h's end, rv = its start). lv == GS_NONE: not known yet. */
typedef struct sdesc {
    p2 C;
    uint32_t lv, rv;
    uint8_t hk, ok;
} sdesc;

/* A funnel portal: its left and right end (2D, vertex ids). */
typedef struct portal {
    p2 l, r;
    uint32_t lv, rv;
} portal;

#define PC_SIZE 4096 /* a power of two */
struct placed {
    uint32_t h;
    p2 xy;
};

typedef struct ctx {
    const gs_db *db;
    const gs__topo *t;
    gs_error *err;
    /* the database distance to the descent's target vertex, cached */
    uint32_t target, origin;
    gs__qsrc *src[2]; /* the target's and the origin's functions, decoded once (NULL until asked) */
    int src_borrowed[2];
    const struct ctx *donor; /* a finished run between the same ends, or NULL: its distances are reused */
    gs__idmap dmap;
    double *dval;
    size_t nd, dcap;
    /* the vertex path */
    uint32_t *vp;
    size_t nvp, vpcap;
    /* the sleeve (and a second buffer to rebuild it) */
    uint32_t *sl;
    size_t nsl, slcap;
    sdesc *sd; /* by sleeve position, kept through the shortening's changes */
    size_t sdcap;
    /* a round's changes (shorten): faces a..b become faces ef[off..off+n) */
    struct sedit {
        size_t a, b, off, n;
    } *ed;
    size_t ned, edcap;
    uint32_t *ef, *sl2;
    size_t nef, efcap, sl2cap;
    sdesc *sd2;
    size_t sd2cap;
    /* unfolding: 2D corners of each sleeve face (by corner 0..2) */
    p2 *uv;
    size_t uvcap;
    portal *fp;
    size_t fpcap;
    /* half-edges' third vertices placed in the edge's frame (unfold), a
     * direct-mapped cache by half-edge id */
    struct placed *pc;
    apex *ap;
    size_t nap, apcap;
    /* output points */
    qpt *q;
    size_t nq, qcap;
    /* A* */
    gs__idmap amap;
    double *ag;
    uint32_t *aparent, *anode;
    uint8_t *aclosed;
    size_t na, acap[4];
    double *heapk;
    uint32_t *heapv;
    size_t nheap, heapcap, heapvcap;
} ctx;

static void ctx_free(ctx *c)
{
    gs__idmap_free(&c->dmap);
    gs__idmap_free(&c->amap);
    free(c->pc);
    for (int k = 0; k < 2; ++k)
        if (!c->src_borrowed[k]) gs__qsrc_free(c->src[k]);
    free(c->sd), free(c->sd2), free(c->sl2), free(c->ed), free(c->ef);
    free(c->dval), free(c->vp), free(c->sl), free(c->uv), free(c->fp), free(c->ap), free(c->q);
    free(c->ag), free(c->aparent), free(c->anode), free(c->aclosed), free(c->heapk), free(c->heapv);
}

static int oom(ctx *c)
{
    return gs__fail(c->err, GS_ENOMEM, "gs_db_path: out of memory");
}

static double dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static const double *vpos(const ctx *c, uint32_t v)
{
    return c->t->xyz + 3 * (size_t)v;
}

/* The mesh must be the database's: every vertex the path visits is where
 * the database has it. */
static int check_vertex(ctx *c, uint32_t v)
{
    const double *a = vpos(c, v), *b = c->db->xyz + 3 * (size_t)v;
    if (memcmp(a, b, 3 * sizeof *a))
        return gs__fail(c->err, GS_EARG,
                        "gs_db_path: the mesh is not the database's: vertex %u is at (%.17g, %.17g, %.17g) in the "
                        "mesh, (%.17g, %.17g, %.17g) in the database",
                        v, a[0], a[1], a[2], b[0], b[1], b[2]);
    return GS_OK;
}

/* d(target, v) (which = 0) or d(origin, v) (which = 1) from the database:
 * gs_db_distance's answer, bit for bit, from the end's functions decoded
 * once (gs__qsrc). With a cut below +inf, the query skips the curves whose
 * lower bound exceeds it: the answer is exact if at most cut, else only
 * known to exceed cut, and cached negated (-answer, see dist_above). */
static int end_distance(ctx *c, int which, uint32_t v, double cut, double *out)
{
    uint32_t e = which ? c->origin : c->target;
    const struct ctx *o = c->donor;
    int w = o ? (o->target == e ? 0 : o->origin == e ? 1 : -1) : -1; /* the donor's column of e */
    if (w >= 0) {
        uint32_t s = gs__idmap_get(&o->dmap, v);
        if (s != GS_NONE && o->dval[2 * s + w] >= 0) { /* known exactly */
            *out = o->dval[2 * s + w];
            return GS_OK;
        }
        if (!c->src[which] && o->src[w]) c->src[which] = o->src[w], c->src_borrowed[which] = 1;
    }
    if (!c->src[which] && !(c->src[which] = gs__qsrc_create(c->db, e))) return oom(c);
    gs__qsrc *q = c->src[which];
    double d;
    uint32_t lx = gs__qsrc_leaf(q), ly = v < c->db->nv ? c->db->leaf[v] : GS_NONE;
    if (cut < INFINITY && v != e && lx != GS_NONE && ly != GS_NONE && ly != lx) {
        d = gs__qsrc_cross_cut(q, v, ly, gs__qsrc_ancestor(q, ly), cut);
        if (d > cut) d = -d; /* only known to exceed cut */
    } else {
        d = gs__qsrc_distance(q, v);
    }
    if (d != d)
        return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: the database answers NaN for vertices %u and %u", e, v);
    *out = d;
    return GS_OK;
}

/* A cached distance: exact (>= 0), only known to exceed the cut it was
 * asked with (< 0: -x is above that cut, and at least the distance), or not
 * asked (NaN); dist_above(x): x if exact, else a value above that cut. */
static inline double dist_above(double x)
{
    return fabs(x);
}

/* d(target, v) from the database, cached (with d(origin, v), NaN until
 * asked); exact. */
static int dist_to_target(ctx *c, uint32_t v, double *out)
{
    uint32_t s = gs__idmap_get(&c->dmap, v);
    if (s != GS_NONE && c->dval[2 * s] >= 0) {
        *out = c->dval[2 * s];
        return GS_OK;
    }
    double d;
    int rc = s == GS_NONE ? check_vertex(c, v) : GS_OK;
    if (!rc) rc = end_distance(c, 0, v, INFINITY, &d);
    if (rc) return rc;
    if (s == GS_NONE) {
        if (gs__grow((void **)&c->dval, &c->dcap, 2 * c->nd + 2, sizeof *c->dval) ||
            gs__idmap_put(&c->dmap, v, (uint32_t)c->nd))
            return oom(c);
        s = (uint32_t)c->nd++;
        c->dval[2 * s + 1] = NAN;
    }
    c->dval[2 * s] = d;
    *out = d;
    return GS_OK;
}

/* The distances to the target (which = 0) or to the origin (which = 1) of
 * the n vertices v[] into the cache: exact with cut = +inf, else those
 * above cut only known to be (cached negated; one known so stays so: the
 * walk's cuts only decrease). Their records are requested from memory
 * first, all of them together: a query walks its target's record from the
 * start to the blocks it needs (on homer-60k about 6 cache lines, 370
 * bytes, on average). */
#define MAX_FAN 256
#define RECORD_LINES 6
static int fetch(ctx *c, const uint32_t *v, uint32_t n, int which, double cut)
{
    uint32_t miss[MAX_FAN], slot[MAX_FAN], m = 0;
    const gs_db *db = c->db;
    for (uint32_t j = 0; j < n; ++j) {
        uint32_t s = gs__idmap_get(&c->dmap, v[j]);
        double known = s != GS_NONE ? c->dval[2 * s + which] : NAN;
        if (cut < INFINITY ? known == known : known >= 0) continue;
        if (s == GS_NONE) {
            if (gs__grow((void **)&c->dval, &c->dcap, 2 * c->nd + 2, sizeof *c->dval) ||
                gs__idmap_put(&c->dmap, v[j], (uint32_t)c->nd))
                return oom(c);
            s = (uint32_t)c->nd++;
            c->dval[2 * s] = c->dval[2 * s + 1] = NAN;
        }
        miss[m] = v[j], slot[m++] = s;
        /* what the query and the check read first, requested together */
        __builtin_prefetch(db->leaf + v[j]), __builtin_prefetch(db->index + v[j]);
        __builtin_prefetch(db->xyz + 3 * (size_t)v[j]), __builtin_prefetch(c->t->xyz + 3 * (size_t)v[j]);
    }
    for (uint32_t j = 0; j < m; ++j) { /* the records, up to RECORD_LINES lines each */
        const unsigned char *end, *p = gs__db_record(db, miss[j], &end);
        for (const unsigned char *r = p; r < end && r < p + 64 * RECORD_LINES; r += 64) __builtin_prefetch(r);
    }
    for (uint32_t j = 0; j < m; ++j) {
        double d;
        int rc = c->dval[2 * slot[j]] != c->dval[2 * slot[j]] && c->dval[2 * slot[j] + 1] != c->dval[2 * slot[j] + 1]
                     ? check_vertex(c, miss[j])
                     : GS_OK;
        if (!rc) rc = end_distance(c, which, miss[j], cut, &d);
        if (rc) return rc;
        c->dval[2 * slot[j] + which] = d;
    }
    return GS_OK;
}

static int push_vertex(ctx *c, uint32_t v)
{
    if (gs__grow((void **)&c->vp, &c->vpcap, c->nvp + 1, sizeof *c->vp)) return oom(c);
    c->vp[c->nvp++] = v;
    return GS_OK;
}

/* ---- A* on the edge graph (the descent's fallback) ----------------------- */

static int heap_push(ctx *c, double k, uint32_t v)
{
    if (gs__grow((void **)&c->heapk, &c->heapcap, c->nheap + 1, sizeof *c->heapk) ||
        gs__grow((void **)&c->heapv, &c->heapvcap, c->nheap + 1, sizeof *c->heapv))
        return GS_ENOMEM;
    size_t i = c->nheap++;
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (c->heapk[p] <= k) break;
        c->heapk[i] = c->heapk[p], c->heapv[i] = c->heapv[p];
        i = p;
    }
    c->heapk[i] = k, c->heapv[i] = v;
    return GS_OK;
}

static uint32_t heap_pop(ctx *c)
{
    uint32_t top = c->heapv[0];
    double k = c->heapk[--c->nheap];
    uint32_t v = c->heapv[c->nheap];
    size_t i = 0, n = c->nheap;
    for (;;) {
        size_t l = 2 * i + 1, m = i;
        double mk = k;
        if (l < n && c->heapk[l] < mk) m = l, mk = c->heapk[l];
        if (l + 1 < n && c->heapk[l + 1] < mk) m = l + 1;
        if (m == i) break;
        c->heapk[i] = c->heapk[m], c->heapv[i] = c->heapv[m];
        i = m;
    }
    if (n) c->heapk[i] = k, c->heapv[i] = v;
    return top;
}

/* A* node of vertex v (created on first sight). */
static int anode(ctx *c, uint32_t v, uint32_t *slot)
{
    uint32_t s = gs__idmap_get(&c->amap, v);
    if (s == GS_NONE) {
        if (gs__grow((void **)&c->ag, &c->acap[0], c->na + 1, sizeof *c->ag) ||
            gs__grow((void **)&c->aparent, &c->acap[1], c->na + 1, sizeof *c->aparent) ||
            gs__grow((void **)&c->anode, &c->acap[2], c->na + 1, sizeof *c->anode) ||
            gs__grow((void **)&c->aclosed, &c->acap[3], c->na + 1, 1))
            return GS_ENOMEM;
        s = (uint32_t)c->na++;
        c->ag[s] = INFINITY, c->aparent[s] = GS_NONE, c->anode[s] = v, c->aclosed[s] = 0;
        if (gs__idmap_put(&c->amap, v, s)) return GS_ENOMEM;
    }
    *slot = s;
    return GS_OK;
}

/* One edge search from the vertex path's last vertex, appending the
 * vertices of the path it finds (*found: 0 if it finds none). to !=
 * GS_NONE: A* to `to` (Euclidean heuristic: admissible and consistent).
 * to == GS_NONE: Dijkstra to the nearest vertex whose distance to the
 * target is below dv, within ESCAPE_MAX vertices (escape, below). */
#define ESCAPE_MAX 4096
static int edge_search(ctx *c, uint32_t to, double dv, int *found_it)
{
    const gs__topo *t = c->t;
    uint32_t from = c->vp[c->nvp - 1], s;
    c->na = 0, c->nheap = 0;
    *found_it = 0;
    if (c->amap.cap) memset(c->amap.key, 0xff, c->amap.cap * sizeof *c->amap.key), c->amap.n = 0;
    if (anode(c, from, &s)) return oom(c);
    c->ag[s] = 0;
    if (heap_push(c, to == GS_NONE ? 0 : dist3(vpos(c, from), vpos(c, to)), s)) return oom(c);
    uint32_t found = GS_NONE, pops = 0;
    while (c->nheap && (to != GS_NONE || pops < ESCAPE_MAX)) {
        uint32_t a = heap_pop(c);
        if (c->aclosed[a]) continue;
        c->aclosed[a] = 1, ++pops;
        uint32_t v = c->anode[a];
        if (v == to) {
            found = a;
            break;
        }
        if (to == GS_NONE && a != s) {
            double d;
            int rc = dist_to_target(c, v, &d);
            if (rc) return rc;
            if (d < dv) {
                found = a;
                break;
            }
        }
        double g = c->ag[a];
        for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1]; ++i) {
            uint32_t h = t->vc[i];
            uint32_t nb[2] = {t->tri[gs__next(h)], t->tri[gs__prev(h)]};
            for (int k = 0; k < 2; ++k) {
                uint32_t b;
                if (anode(c, nb[k], &b)) return oom(c);
                double ng = g + dist3(vpos(c, v), vpos(c, nb[k]));
                if (c->aclosed[b] || ng >= c->ag[b]) continue;
                c->ag[b] = ng, c->aparent[b] = a;
                if (heap_push(c, to == GS_NONE ? ng : ng + dist3(vpos(c, nb[k]), vpos(c, to)), b)) return oom(c);
            }
        }
    }
    if (found == GS_NONE) return GS_OK;
    size_t n0 = c->nvp, k = 0;
    for (uint32_t a = found; a != s; a = c->aparent[a]) ++k;
    if (gs__grow((void **)&c->vp, &c->vpcap, n0 + k, sizeof *c->vp)) return oom(c);
    c->nvp = n0 + k;
    for (uint32_t a = found; a != s; a = c->aparent[a]) c->vp[n0 + --k] = c->anode[a];
    *found_it = 1;
    return GS_OK;
}

/* Append a shortest edge path from the vertex path's last vertex to `to`;
 * *found: 0 if they are not connected. */
static int astar(ctx *c, uint32_t to, int *found_it)
{
    return edge_search(c, to, 0.0, found_it);
}

/* The descent is at a vertex v without a neighbour closer to the target
 * (a dip of the fitted functions, dv = d(target, v)): append the edge
 * path to the nearest vertex that is closer than v (*found: 0 if none
 * within ESCAPE_MAX vertices). The descent goes on from there: it stays
 * strictly closer than dv, so it never comes back to this dip. */
static int escape(ctx *c, double dv, int *found_it)
{
    return edge_search(c, GS_NONE, dv, found_it);
}

/* ---- 1. descent ------------------------------------------------------- */

/* Far from both ends (more than STEEP_FROM edges: steps taken, and d(X, v)
 * over the edges' mean length), the valley's floor is flat across the path
 * (g grows with the square of the offset, over the ends' distances) and
 * the fitted functions' errors decide among the closer neighbours: there
 * the walk takes only those that come closer to X by at least STEEP of
 * their edge's length, if any (on homer-60k's longest paths 16% fewer
 * queries and 12% fewer shortening rounds, and the paths as short; nearer
 * the ends, and on coarse meshes, the floor decides). */
#define STEEP_FROM 20
#define STEEP 0.5

/* Extend the vertex path (its first vertex in place) down the valley to a
 * vertex of targets[0..nt); a vertex without a neighbour closer to X hands
 * over to A*. */
static int descend(ctx *c, const uint32_t *targets, int nt)
{
    const gs__topo *t = c->t;
    for (;;) {
        uint32_t v = c->vp[c->nvp - 1];
        for (int k = 0; k < nt; ++k)
            if (v == targets[k]) return GS_OK;
        double dv, best = INFINITY, dir[3] = {0, 0, 0};
        uint32_t bn = GS_NONE;
        int rc = dist_to_target(c, v, &dv);
        if (rc) return rc;
        if (c->nvp > 1) /* the last step's direction: neighbours behind it come last */
            for (int k = 0; k < 3; ++k) dir[k] = vpos(c, v)[k] - vpos(c, c->vp[c->nvp - 2])[k];
        for (int pass = 0; pass < 2 && bn == GS_NONE; ++pass) {
            uint32_t cand[MAX_FAN], nc = 0;
            for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1]; ++i) {
                uint32_t h = t->vc[i];
                uint32_t nb[2] = {t->tri[gs__next(h)], t->tri[gs__prev(h)]};
                for (int k = 0; k < 2; ++k) {
                    const double *q = vpos(c, nb[k]), *p = vpos(c, v);
                    double ahead = (q[0] - p[0]) * dir[0] + (q[1] - p[1]) * dir[1] + (q[2] - p[2]) * dir[2];
                    if ((ahead >= 0) == (pass == 1)) continue;
                    uint32_t j = 0;
                    while (j < nc && cand[j] != nb[k]) ++j;
                    if (j == nc && nc < MAX_FAN) cand[nc++] = nb[k], __builtin_prefetch(t->vc_start + nb[k]);
                }
            }
            /* d(X, .) of them all, then d(., Y) of those closer to X: each in one batch */
            if ((rc = fetch(c, cand, nc, 0, dv))) return rc;
            uint32_t closer[MAX_FAN], ncl = 0;
            for (uint32_t j = 0; j < nc; ++j)
                if (dist_above(c->dval[2 * gs__idmap_get(&c->dmap, cand[j])]) < dv) closer[ncl++] = cand[j];
            if (ncl > 1 && c->nvp > STEEP_FROM) { /* far from both ends: the steep ones, if any */
                uint32_t nst = 0;
                double len[MAX_FAN], mean = 0;
                for (uint32_t j = 0; j < ncl; ++j) len[j] = dist3(vpos(c, v), vpos(c, closer[j])), mean += len[j];
                if (dv > STEEP_FROM * mean / ncl) {
                    for (uint32_t j = 0; j < ncl; ++j)
                        if (dv - c->dval[2 * gs__idmap_get(&c->dmap, closer[j])] >= STEEP * len[j]) closer[nst++] = closer[j];
                    if (nst) ncl = nst; /* (none: closer[] untouched) */
                }
            }
            /* the next vertex's fan, requested while the queries run
             * (its offsets were requested with the candidates) */
            for (uint32_t j = 0; j < ncl; ++j) __builtin_prefetch(t->vc + t->vc_start[closer[j]]);
            if (ncl == 1) { /* the only way on: its d(., Y) is not needed */
                bn = closer[0];
                break;
            }
            if ((rc = fetch(c, closer, ncl, 1, INFINITY))) return rc;
            for (uint32_t j = 0; j < ncl; ++j) /* ... and the fan's corners */
                for (uint32_t i = t->vc_start[closer[j]]; i < t->vc_start[closer[j] + 1]; ++i)
                    __builtin_prefetch(t->tri + t->vc[i]);
            for (uint32_t j = 0; j < ncl; ++j) {
                uint32_t sl = gs__idmap_get(&c->dmap, closer[j]);
                double g = c->dval[2 * sl] + c->dval[2 * sl + 1];
                if (g < best) best = g, bn = closer[j];
            }
        }
        if (bn == GS_NONE) {
            int found;
            if ((rc = escape(c, dv, &found))) return rc;
            if (found) continue;
            if ((rc = astar(c, c->target, &found))) return rc;
            if (!found)
                return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: vertex %u is not connected to vertex %u", v,
                                c->target);
            return GS_OK;
        }
        if ((rc = push_vertex(c, bn))) return rc;
    }
}

/* Cut the loops out of the vertex path (an escape or A* may come back to a
 * vertex it passed): each vertex once, in the order of its last visit's
 * way out. */
static int remove_loops(ctx *c)
{
    gs__idmap seen = {0};
    size_t k = 0;
    for (size_t i = 0; i < c->nvp; ++i) {
        uint32_t v = c->vp[i], at = gs__idmap_get(&seen, v);
        if (at != GS_NONE && at < k && c->vp[at] == v) {
            k = at + 1; /* back to v's first visit: drop the loop */
            continue;
        }
        if (gs__idmap_put(&seen, v, (uint32_t)k)) {
            gs__idmap_free(&seen);
            return oom(c);
        }
        c->vp[k++] = v;
    }
    c->nvp = k;
    gs__idmap_free(&seen);
    return GS_OK;
}

/* ---- 2. the sleeve ------------------------------------------------------- */

enum { ES_NONE, ES_FACE, ES_EDGE };

typedef struct endspec {
    int type;
    uint32_t x; /* the face, or the edge's other vertex */
} endspec;

static uint32_t corner_at(const gs__topo *t, uint32_t f, uint32_t v)
{
    for (uint32_t k = 0; k < 3; ++k)
        if (t->tri[3 * f + k] == v) return 3 * f + k;
    return GS_NONE;
}

static int face_has(const gs__topo *t, uint32_t f, uint32_t v)
{
    return corner_at(t, f, v) != GS_NONE;
}

/* Faces around v from `in` to `out`, turning one way: dir 0 leaves each
 * face by its half-edge h (v -> next), dir 1 by prev(h) (prev -> v). At
 * most cap faces into buf; returns their count, 0 if that way meets the
 * boundary or does not arrive; *ang: the sum of their angles at v. */
static uint32_t rotate_run(const gs__topo *t, uint32_t v, endspec in, endspec out, int dir, uint32_t *buf,
                           uint32_t cap, double *ang)
{
    uint32_t h = GS_NONE;
    if (in.type == ES_FACE) {
        h = corner_at(t, in.x, v);
    } else {
        for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1] && h == GS_NONE; ++i) {
            uint32_t k = t->vc[i];
            if (t->tri[dir == 0 ? gs__prev(k) : gs__next(k)] == in.x) h = k;
        }
    }
    if (h == GS_NONE) return 0;
    double a = 0;
    uint32_t n = 0;
    for (;;) {
        if (n >= cap) return 0;
        buf[n++] = h / 3;
        a += t->angle[h];
        if (out.type == ES_FACE ? h / 3 == out.x : t->tri[dir == 0 ? gs__next(h) : gs__prev(h)] == out.x) break;
        uint32_t o = t->opp[dir == 0 ? h : gs__prev(h)];
        if (o == GS_NONE) return 0;
        h = dir == 0 ? gs__next(o) : o;
    }
    *ang = a;
    return n;
}

/* The side of vertex vp[i] the shortest path passes, judged from the
 * chord between the vertex path's vertices CHORD_SPAN before and after it:
 * +1 if the chord passes among the faces run[0..n) (one side of v), -1 if
 * on the other side, 0 if it passes (nearly) through v. */
#define CHORD_SPAN 4
static int chord_side(const ctx *c, size_t i, const uint32_t *run, uint32_t n)
{
    const gs__topo *t = c->t;
    const double *v = vpos(c, c->vp[i]);
    const double *P = vpos(c, c->vp[i >= CHORD_SPAN ? i - CHORD_SPAN : 0]);
    const double *N = vpos(c, c->vp[i + CHORD_SPAN < c->nvp ? i + CHORD_SPAN : c->nvp - 1]);
    double d[3], w[3], dd = 0, wd = 0;
    for (int k = 0; k < 3; ++k) d[k] = N[k] - P[k], w[k] = v[k] - P[k], dd += d[k] * d[k], wd += w[k] * d[k];
    if (!(dd > 0)) return 0;
    double tt = wd / dd, sv[3], s2 = 0, o[3] = {0, 0, 0}, e2 = 0;
    tt = tt < 0 ? 0 : tt > 1 ? 1 : tt;
    for (int k = 0; k < 3; ++k) sv[k] = P[k] + tt * d[k] - v[k], s2 += sv[k] * sv[k];
    for (uint32_t j = 0; j < n; ++j) {
        const uint32_t *T = t->tri + 3 * (size_t)run[j];
        for (int k = 0; k < 3; ++k)
            o[k] += (t->xyz[3 * (size_t)T[0] + k] + t->xyz[3 * (size_t)T[1] + k] + t->xyz[3 * (size_t)T[2] + k]) / 3 - v[k];
    }
    for (int k = 0; k < 3; ++k) e2 += o[k] * o[k];
    double dot = o[0] * sv[0] + o[1] * sv[1] + o[2] * sv[2];
    if (!(fabs(dot) > 0.1 * sqrt(s2 * e2))) return 0; /* through v, or across: undecided */
    return dot > 0 ? 1 : -1;
}

/* Append face f to the sleeve, dropping a repeat and undoing a step back
 * (f, g, f -> f). */
static int sleeve_push(ctx *c, uint32_t f)
{
    if (c->nsl && c->sl[c->nsl - 1] == f) return GS_OK;
    if (c->nsl >= 2 && c->sl[c->nsl - 2] == f) {
        c->nsl--;
        return GS_OK;
    }
    if (gs__grow((void **)&c->sl, &c->slcap, c->nsl + 1, sizeof *c->sl)) return oom(c);
    c->sl[c->nsl++] = f;
    return GS_OK;
}

/* The sleeve of the vertex path vp[0..nvp) from X (in: X's face, or none
 * when X is vp[0]) to Y (out: likewise). */
static int build_sleeve(ctx *c, endspec xin, endspec yout)
{
    const gs__topo *t = c->t;
    c->nsl = 0;
    uint32_t buf[2][512];
    for (size_t i = 0; i < c->nvp; ++i) {
        uint32_t v = c->vp[i];
        /* what the runs round the vertices ahead read, requested in stages
         * (each needs the one before): their faces, then the faces' twins,
         * corners and angles */
        if (i + 8 < c->nvp) __builtin_prefetch(t->vc_start + c->vp[i + 8]);
        if (i + 4 < c->nvp) __builtin_prefetch(t->vc + t->vc_start[c->vp[i + 4]]);
        if (i + 2 < c->nvp) {
            uint32_t w = c->vp[i + 2];
            for (uint32_t k = t->vc_start[w]; k < t->vc_start[w + 1]; ++k) {
                uint32_t h = t->vc[k];
                __builtin_prefetch(t->opp + h), __builtin_prefetch(t->tri + h), __builtin_prefetch(t->angle + h);
            }
        }
        endspec in = i ? (endspec){ES_EDGE, c->vp[i - 1]} : xin;
        endspec out = i + 1 < c->nvp ? (endspec){ES_EDGE, c->vp[i + 1]} : yout;
        if (in.type == ES_NONE && out.type == ES_FACE) {
            int rc = sleeve_push(c, out.x);
            if (rc) return rc;
            continue;
        }
        if (in.type == ES_FACE && out.type == ES_NONE) {
            int rc = sleeve_push(c, in.x);
            if (rc) return rc;
            continue;
        }
        if (in.type == ES_NONE || out.type == ES_NONE) continue; /* the next or previous run holds v */
        uint32_t val = t->vc_start[v + 1] - t->vc_start[v], cap = val + 1 < 512 ? val + 1 : 512;
        /* the side of v that the chord over a few vertices passes, else the
         * side of the smaller angle (the other way round v only if needed) */
        double a0 = INFINITY, a1 = INFINITY;
        uint32_t n0 = rotate_run(t, v, in, out, 0, buf[0], cap, &a0), n1 = 0;
        int side = n0 ? chord_side(c, i, buf[0], n0) : 0;
        if (side <= 0) n1 = rotate_run(t, v, in, out, 1, buf[1], cap, &a1);
        if (!n0) a0 = INFINITY;
        if (!n1) a1 = INFINITY;
        if (!n0 && !n1)
            return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: no faces around vertex %u join the path's edges", v);
        int k = side > 0 || !n1 ? 0 : !n0 || side < 0 ? 1 : a0 <= a1 ? 0 : 1;
        uint32_t n = k ? n1 : n0;
        for (uint32_t j = 0; j < n; ++j) {
            int rc = sleeve_push(c, buf[k][j]);
            if (rc) return rc;
        }
    }
    if (!c->nsl && c->nvp == 2) { /* two vertices: a face of their edge */
        uint32_t v = c->vp[0], u = c->vp[1];
        for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1] && !c->nsl; ++i) {
            uint32_t h = t->vc[i];
            if (t->tri[gs__next(h)] == u || t->tri[gs__prev(h)] == u) {
                int rc = sleeve_push(c, h / 3);
                if (rc) return rc;
            }
        }
    }
    if (!c->nsl) return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: empty strip of faces");
    return GS_OK;
}

/* ---- 3. unfolding, funnel, shortening ------------------------------------ */

static p2 point2(const ctx *c, const qpt *q, size_t i)
{
    const gs__topo *t = c->t;
    uint32_t f = c->sl[i];
    const p2 *u = c->uv + 3 * i;
    if (q->type == Q_VERTEX) return u[corner_at(t, f, q->a) % 3];
    if (q->type == Q_EDGE) {
        p2 a = u[corner_at(t, f, q->a) % 3], b = u[corner_at(t, f, q->b) % 3];
        return (p2){(1 - q->t) * a.x + q->t * b.x, (1 - q->t) * a.y + q->t * b.y};
    }
    return (p2){q->bary[0] * u[0].x + q->bary[1] * u[1].x + q->bary[2] * u[2].x,
                q->bary[0] * u[0].y + q->bary[1] * u[1].y + q->bary[2] * u[2].y};
}

/* The area of a triangle with sides a, b, c (Kahan's stable Heron
 * formula: no trigonometry, accurate for slivers). */
static double tri_area(double a, double b, double c)
{
    double t;
    if (a < b) t = a, a = b, b = t;
    if (a < c) t = a, a = c, c = t;
    if (b < c) t = b, b = c, c = t;
    double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
    return 0.25 * sqrt(p > 0 ? p : 0);
}

/* The third vertex of half-edge o's face in o's frame: (along o from its
 * start, to the right of it), in units of o's length (a square root and
 * divisions: cached). */
static int placement(ctx *c, uint32_t o, p2 *out)
{
    if (!c->pc) {
        if (!(c->pc = gs__malloc(PC_SIZE, sizeof *c->pc))) return oom(c);
        for (uint32_t i = 0; i < PC_SIZE; ++i) c->pc[i].h = GS_NONE;
    }
    struct placed *e = &c->pc[o & (PC_SIZE - 1)];
    if (e->h != o) {
        const gs__topo *t = c->t;
        double L = t->len[o], r = t->len[gs__next(o)], q = t->len[gs__prev(o)];
        e->h = o;
        e->xy = (p2){(r * r - q * q + L * L) / (2 * L * L), 2 * tri_area(L, r, q) / (L * L)};
    }
    *out = e->xy;
    return GS_OK;
}

/* The joins of the faces this many positions ahead are requested from
 * memory while the current ones are placed (a join reads the two faces'
 * twins and the next face's edge lengths: scattered, most often missed in
 * the caches). */
#define UNFOLD_AHEAD 8

/* Unfold the sleeve into the plane (one chain: every face shares its edge's
 * two points with the previous one) and fill the funnel's portals
 * fp[1..m-1]; fp[0] and fp[m] are the ends. Faces before `from` are where
 * the last call put them (the sleeve unchanged up to there). */
static int unfold(ctx *c, const qpt *x, const qpt *y, size_t from)
{
    const gs__topo *t = c->t;
    size_t m = c->nsl;
    if (gs__grow((void **)&c->uv, &c->uvcap, 3 * m, sizeof *c->uv) ||
        gs__grow((void **)&c->fp, &c->fpcap, m + 1, sizeof *c->fp))
        return oom(c);
    uint32_t f = c->sl[0];
    p2 *u = c->uv;
    if (from == 0) {
        double a = t->angle[3 * f], l = t->len[3 * f + 2];
        u[0] = (p2){0, 0};
        u[1] = (p2){t->len[3 * f], 0};
        u[2] = (p2){l * cos(a), l * sin(a)};
    }
    if (gs__grow((void **)&c->sd, &c->sdcap, m, sizeof *c->sd)) return oom(c);
    if (from == 0)
        for (size_t i = 0; i < m; ++i) c->sd[i].lv = GS_NONE;
    for (size_t i = from ? from - 1 : 0; i + 1 < m; ++i) {
        sdesc *D = &c->sd[i + 1];
        if (i + 1 + UNFOLD_AHEAD < m && c->sd[i + 1 + UNFOLD_AHEAD].lv == GS_NONE) { /* a join to find ahead */
            uint32_t g = c->sl[i + 1 + UNFOLD_AHEAD];
            __builtin_prefetch(t->opp + 3 * (size_t)g), __builtin_prefetch(t->len + 3 * (size_t)g);
        }
        if (D->lv == GS_NONE) { /* how face i + 1 joins face i */
            uint32_t g = c->sl[i + 1], h = GS_NONE;
            f = c->sl[i];
            for (uint32_t k = 3 * f; k < 3 * f + 3; ++k)
                if (t->opp[k] != GS_NONE && t->opp[k] / 3 == g) h = k;
            if (h == GS_NONE)
                return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: faces %u and %u of the strip share no edge", f, g);
            uint32_t o = t->opp[h];
            if (placement(c, o, &D->C)) return oom(c);
            D->hk = (uint8_t)(h % 3), D->ok = (uint8_t)(o % 3);
            D->lv = t->tri[gs__next(h)], D->rv = t->tri[h];
        }
        static const uint8_t nx[3] = {1, 2, 0}, pv[3] = {2, 0, 1};
        p2 A = c->uv[3 * i + D->hk], B = c->uv[3 * i + nx[D->hk]], C = D->C;
        p2 *w = c->uv + 3 * (i + 1);
        w[D->ok] = B;
        w[nx[D->ok]] = A;
        /* C to the right of A -> B: its foot along AB, its height (in units of |AB|) */
        double dx = B.x - A.x, dy = B.y - A.y;
        w[pv[D->ok]] = (p2){A.x + C.x * dx + C.y * dy, A.y + C.x * dy - C.y * dx};
        c->fp[i + 1] = (portal){B, A, D->lv, D->rv};
    }
    p2 s = point2(c, x, 0), e = point2(c, y, m - 1);
    c->fp[0] = (portal){s, s, GS_NONE, GS_NONE};
    c->fp[m] = (portal){e, e, GS_NONE, GS_NONE};
    return GS_OK;
}

static int push_apex(ctx *c, p2 p, uint32_t v, uint32_t idx, uint32_t seen)
{
    if (v != GS_NONE && c->nap && c->ap[c->nap - 1].v == v && eq2(c->ap[c->nap - 1].p, p)) {
        c->ap[c->nap - 1].idx = idx, c->ap[c->nap - 1].seen = seen;
        return GS_OK;
    }
    if (gs__grow((void **)&c->ap, &c->apcap, c->nap + 1, sizeof *c->ap)) return oom(c);
    c->ap[c->nap++] = (apex){p, v, idx, seen};
    return GS_OK;
}

/* The shortest path inside the unfolded sleeve (the "simple stupid funnel"
 * form of Lee & Preparata's funnel algorithm): its bends into c->ap.
 * Portals before `from` are the last call's: its bends placed having read
 * only those are kept, and the scan goes on from the last of them (the
 * funnel restarts at every bend it places: what follows depends only on
 * that bend and the portals after it, so the bends are the same as a scan
 * from the start would place). */
static int funnel(ctx *c, size_t from)
{
    uint32_t m = (uint32_t)c->nsl;
    const portal *fp = c->fp;
    int rc;
    size_t k = from && c->nap ? c->nap - 1 : 0;
    while (k > 0 && c->ap[k].seen >= from) --k;
    if (k == 0) {
        c->nap = 0;
        if ((rc = push_apex(c, fp[0].l, GS_NONE, 0, 0))) return rc;
    }
    c->nap = k + 1;
    p2 ap = c->ap[k].p, left = ap, right = ap;
    uint32_t ai = c->ap[k].idx, li = ai, ri = ai, seen = c->ap[k].seen;
    for (uint32_t i = ai + 1; i <= m; ++i) {
        if (i > seen) seen = i;
        p2 l = fp[i].l, r = fp[i].r;
        if (cross3(ap, right, r) >= 0) {
            if (eq2(ap, right) || eq2(ap, left) || eq2(r, left) || cross3(ap, left, r) < 0) {
                right = r, ri = i;
            } else { /* r crosses the left side: its point is a bend */
                if ((rc = push_apex(c, left, fp[li].lv, li, seen))) return rc;
                ap = left, ai = li;
                right = left = ap, ri = li = ai;
                i = ai;
                continue;
            }
        }
        if (cross3(ap, left, l) <= 0) {
            if (eq2(ap, left) || eq2(ap, right) || eq2(l, right) || cross3(ap, right, l) > 0) {
                left = l, li = i;
            } else {
                if ((rc = push_apex(c, right, fp[ri].rv, ri, seen))) return rc;
                ap = right, ai = ri;
                right = left = ap, ri = li = ai;
                i = ai;
                continue;
            }
        }
    }
    return push_apex(c, fp[m].l, GS_NONE, m, m);
}

static double angle2(p2 o, p2 a, p2 b)
{
    double ax = a.x - o.x, ay = a.y - o.y, bx = b.x - o.x, by = b.y - o.y;
    return atan2(fabs(ax * by - ay * bx), ax * bx + ay * by);
}

/* Sleeve face i's edge at v that it does not share with sleeve face j:
 * its other end (vertex id) and the half-edge to cross to leave by it. */
static uint32_t outer_edge(const ctx *c, size_t i, size_t j, uint32_t v, uint32_t *cross_h)
{
    const gs__topo *t = c->t;
    uint32_t h = corner_at(t, c->sl[i], v), g = c->sl[j];
    if (t->opp[h] != GS_NONE && t->opp[h] / 3 == g) { /* shared: h's edge; outer: prev(h) */
        *cross_h = gs__prev(h);
        return t->tri[gs__prev(h)];
    }
    *cross_h = h;
    return t->tri[gs__next(h)];
}

/* Bend ap[j] (a vertex v): if the angle on the far side of v is below pi
 * (or `force`), the sleeve's faces at v (positions a..b, b below *limit)
 * are to be replaced by v's other faces (a change recorded for
 * apply_edits; the sleeve is left as it is); *limit = a. *done: 1 if so. */
static int flip_at(ctx *c, size_t j, int force, uint32_t xv, uint32_t yv, size_t *limit, int *done)
{
    const gs__topo *t = c->t;
    const apex *A = &c->ap[j];
    uint32_t v = A->v;
    *done = 0;
    if (v == GS_NONE || v == xv || v == yv || (t->vflag[v] & (GS_V_BOUNDARY | GS_V_NONMANIFOLD))) return GS_OK;
    if (A->idx == 0 || A->idx >= c->nsl) return GS_OK;
    size_t a = A->idx - 1, b = A->idx;
    if (!face_has(t, c->sl[a], v) || !face_has(t, c->sl[b], v)) return GS_OK;
    while (a > 0 && face_has(t, c->sl[a - 1], v)) --a;
    while (b + 1 < c->nsl && face_has(t, c->sl[b + 1], v)) ++b;
    if (b >= *limit) return GS_OK;
    uint32_t ha, hb;
    uint32_t wa = outer_edge(c, a, a + 1, v, &ha), wb = outer_edge(c, b, b - 1, v, &hb);
    (void)hb;
    if (!force) {
        double alpha = 0;
        for (size_t i = a; i <= b; ++i) alpha += t->angle[corner_at(t, c->sl[i], v)];
        const p2 *ua = c->uv + 3 * a, *ub = c->uv + 3 * b;
        p2 va = ua[corner_at(t, c->sl[a], v) % 3], vb = ub[corner_at(t, c->sl[b], v) % 3];
        double gp = angle2(va, ua[corner_at(t, c->sl[a], wa) % 3], c->ap[j - 1].p);
        double gn = angle2(vb, ub[corner_at(t, c->sl[b], wb) % 3], c->ap[j + 1].p);
        double beta = alpha - gp - gn, far = t->vangle[v] - beta;
        if (!(far < M_PI * (1 - 1e-12))) return GS_OK;
    }
    /* the other way round v, from sleeve face a to sleeve face b */
    uint32_t val = t->vc_start[v + 1] - t->vc_start[v], buf[512], n = 0;
    if (val >= 511) return GS_OK;
    uint32_t h = corner_at(t, c->sl[a], v);
    int dir = ha == h ? 0 : 1, ok = 0;
    buf[n++] = c->sl[a];
    for (uint32_t s = 0; s <= val; ++s) {
        uint32_t o = t->opp[dir == 0 ? h : gs__prev(h)];
        if (o == GS_NONE) break;
        h = dir == 0 ? gs__next(o) : o;
        buf[n++] = h / 3;
        if (h / 3 == c->sl[b]) {
            ok = 1;
            break;
        }
    }
    if (!ok || (b - a + 1) + n - 2 != val) return GS_OK; /* the two ways must split v's faces */
    if (gs__grow((void **)&c->ed, &c->edcap, c->ned + 1, sizeof *c->ed) ||
        gs__grow((void **)&c->ef, &c->efcap, c->nef + n, sizeof *c->ef))
        return oom(c);
    c->ed[c->ned++] = (struct sedit){a, b, c->nef, n};
    memcpy(c->ef + c->nef, buf, n * sizeof *c->ef);
    c->nef += n;
    *limit = a;
    *done = 1;
    return GS_OK;
}

/* Make a round's changes (recorded back to front: positions in the
 * sleeve before them) in one pass into the second buffers, and swap. */
static int apply_edits(ctx *c)
{
    size_t nn = c->nsl;
    for (size_t e = 0; e < c->ned; ++e) nn += c->ed[e].n - (c->ed[e].b - c->ed[e].a + 1);
    if (gs__grow((void **)&c->sl2, &c->sl2cap, nn, sizeof *c->sl2) ||
        gs__grow((void **)&c->sd2, &c->sd2cap, nn, sizeof *c->sd2))
        return oom(c);
    size_t k = 0, pos = 0;
    for (size_t e = c->ned; e-- > 0;) {
        const struct sedit *E = &c->ed[e];
        memcpy(c->sl2 + k, c->sl + pos, (E->a - pos) * sizeof *c->sl);
        memcpy(c->sd2 + k, c->sd + pos, (E->a - pos) * sizeof *c->sd);
        k += E->a - pos;
        /* faces a and b stay: their joins with the faces before and after */
        memcpy(c->sl2 + k, c->ef + E->off, E->n * sizeof *c->sl);
        c->sd2[k] = c->sd[E->a];
        for (size_t i = 1; i < E->n; ++i) c->sd2[k + i].lv = GS_NONE;
        k += E->n;
        pos = E->b + 1;
    }
    memcpy(c->sl2 + k, c->sl + pos, (c->nsl - pos) * sizeof *c->sl);
    memcpy(c->sd2 + k, c->sd + pos, (c->nsl - pos) * sizeof *c->sd);
    k += c->nsl - pos;
    uint32_t *ts = c->sl;
    size_t tc = c->slcap;
    c->sl = c->sl2, c->slcap = c->sl2cap, c->sl2 = ts, c->sl2cap = tc;
    sdesc *td = c->sd;
    tc = c->sdcap;
    c->sd = c->sd2, c->sdcap = c->sd2cap, c->sd2 = td, c->sd2cap = tc;
    c->nsl = k;
    return GS_OK;
}

/* Undo the steps back (f, g, f) that changes may have made; returns the
 * first position changed (nsl if none). */
static size_t sleeve_tidy(ctx *c)
{
    size_t n = c->nsl, k = 0, first = n, last = 0; /* last: the position the last face kept had */
    for (size_t i = 0; i < n; ++i) {
        uint32_t f = c->sl[i];
        if (k && c->sl[k - 1] == f) {
            if (k < first) first = k;
            last = i;
            continue;
        }
        if (k >= 2 && c->sl[k - 2] == f) {
            --k;
            if (k < first) first = k;
            last = i;
            continue;
        }
        /* its join with the face before it is known if they were neighbours */
        sdesc D = c->sd[i];
        if (k && last + 1 != i) D.lv = GS_NONE;
        c->sl[k] = f, c->sd[k++] = D;
        last = i;
    }
    c->nsl = k;
    return first;
}

/* One round of shortening: every bend vertex with less than pi on the far
 * side gets the sleeve round that side (back to front, runs that do not
 * overlap). *nflips: the number of changes; *first: the first sleeve
 * position changed. */
static int shorten(ctx *c, uint32_t xv, uint32_t yv, uint32_t *nflips, size_t *first)
{
    size_t limit = c->nsl;
    *nflips = 0;
    c->ned = c->nef = 0;
    for (size_t j = c->nap - 1; j-- > 1;) {
        int done, rc = flip_at(c, j, 0, xv, yv, &limit, &done);
        if (rc) return rc;
        *nflips += (uint32_t)done;
    }
    *first = limit;
    if (*nflips) {
        int rc = apply_edits(c);
        if (rc) return rc;
        size_t f = sleeve_tidy(c);
        if (f < *first) *first = f;
    }
    return GS_OK;
}

/* The length of the funnel's path. */
static double funnel_length(const ctx *c)
{
    double l = 0;
    for (size_t j = 0; j + 1 < c->nap; ++j) {
        double dx = c->ap[j + 1].p.x - c->ap[j].p.x, dy = c->ap[j + 1].p.y - c->ap[j].p.y;
        l += sqrt(dx * dx + dy * dy);
    }
    return l;
}

/* Unfold, funnel and shorten until locally shortest, or until it has
 * settled: from round SETTLE_FROM on, once the last SETTLE_ROUNDS rounds
 * together shortened it by less than SETTLE_GAIN of its length (a path
 * far off the geodesic over a nearly flat stretch slides across it one
 * vertex per bend and round, for a hundred rounds on homer-60k's longest
 * paths, gaining about 1e-5 of its length per round); *len: the length. */
#define SETTLE_FROM 16
#define SETTLE_ROUNDS 8
#define SETTLE_GAIN 5e-4
static int converge(ctx *c, const qpt *x, const qpt *y, uint32_t xv, uint32_t yv, double *len)
{
    size_t max_rounds = 64 + 4 * c->nsl, from = 0;
    double hist[SETTLE_ROUNDS]; /* the length of the last rounds, by round modulo SETTLE_ROUNDS */
    int rc;
    for (size_t round = 0;; ++round) {
        uint32_t nf;
        if ((rc = unfold(c, x, y, from)) || (rc = funnel(c, from))) return rc;
        if (round >= max_rounds) break;
        double l = funnel_length(c);
        if (round >= SETTLE_FROM && hist[round % SETTLE_ROUNDS] - l < SETTLE_GAIN * l) break;
        hist[round % SETTLE_ROUNDS] = l;
        if ((rc = shorten(c, xv, yv, &nf, &from))) return rc;
        if (!nf) break;
    }
    *len = funnel_length(c);
    return GS_OK;
}

/* ---- output --------------------------------------------------------------- */

static int same_q(const qpt *a, const qpt *b)
{
    if (a->type != b->type) return 0;
    if (a->type == Q_VERTEX) return a->a == b->a;
    if (a->type == Q_EDGE)
        return (a->a == b->a && a->b == b->b && a->t == b->t) || (a->a == b->b && a->b == b->a && a->t == 1 - b->t);
    return a->f == b->f && !memcmp(a->bary, b->bary, sizeof a->bary);
}

/* Append q reached from the last point by a segment in face g. */
static int add_q(ctx *c, qpt q, uint32_t g)
{
    if (q.type == Q_EDGE && q.t <= 0) q = (qpt){Q_VERTEX, q.a, GS_NONE, GS_NONE, 0, {0, 0, 0}, GS_NONE};
    if (q.type == Q_EDGE && q.t >= 1) q = (qpt){Q_VERTEX, q.b, GS_NONE, GS_NONE, 0, {0, 0, 0}, GS_NONE};
    if (c->nq && same_q(&c->q[c->nq - 1], &q)) {
        c->q[c->nq - 1].seg = g;
        return GS_OK;
    }
    if (gs__grow((void **)&c->q, &c->qcap, c->nq + 1, sizeof *c->q)) return oom(c);
    if (c->nq) c->q[c->nq - 1].seg = g;
    q.seg = g;
    c->q[c->nq++] = q;
    return GS_OK;
}

/* The points of the funnel's path: X, its crossing with every portal, Y. */
static int trace_points(ctx *c, const qpt *x, const qpt *y)
{
    size_t m = c->nsl;
    c->nq = 0;
    int rc = add_q(c, *x, c->sl[0]);
    if (rc) return rc;
    size_t j = 0; /* the segment ap[j] -> ap[j+1] holds portal i */
    for (uint32_t i = 1; i < m; ++i) {
        while (j + 2 < c->nap && c->ap[j + 1].idx < i) ++j;
        const portal *P = &c->fp[i];
        const apex *A = &c->ap[j], *B = &c->ap[j + 1];
        qpt q;
        if (A->v != GS_NONE && ((P->lv == A->v && eq2(P->l, A->p)) || (P->rv == A->v && eq2(P->r, A->p)))) {
            q = (qpt){Q_VERTEX, A->v, GS_NONE, GS_NONE, 0, {0, 0, 0}, GS_NONE};
        } else if (B->v != GS_NONE && ((P->lv == B->v && eq2(P->l, B->p)) || (P->rv == B->v && eq2(P->r, B->p)))) {
            q = (qpt){Q_VERTEX, B->v, GS_NONE, GS_NONE, 0, {0, 0, 0}, GS_NONE};
        } else { /* the line A -> B meets the portal r -> l at r + s (l - r) */
            double dx = B->p.x - A->p.x, dy = B->p.y - A->p.y;
            double ex = P->l.x - P->r.x, ey = P->l.y - P->r.y;
            double den = ex * dy - ey * dx, s = 0.5;
            if (den != 0) s = ((A->p.x - P->r.x) * dy - (A->p.y - P->r.y) * dx) / den;
            if (!(s >= 0)) s = 0;
            if (s > 1) s = 1;
            q = (qpt){Q_EDGE, P->rv, P->lv, GS_NONE, s, {0, 0, 0}, GS_NONE};
        }
        if ((rc = add_q(c, q, c->sl[i - 1]))) return rc;
    }
    return add_q(c, *y, c->sl[m - 1]);
}

static int bary_of(const gs__topo *t, const qpt *q, uint32_t g, double b[3])
{
    b[0] = b[1] = b[2] = 0;
    if (q->type == Q_FACE) {
        if (q->f != g) return -1;
        memcpy(b, q->bary, sizeof q->bary);
        return 0;
    }
    uint32_t ca = corner_at(t, g, q->a);
    if (ca == GS_NONE) return -1;
    if (q->type == Q_VERTEX) {
        b[ca % 3] = 1;
        return 0;
    }
    uint32_t cb = corner_at(t, g, q->b);
    if (cb == GS_NONE) return -1;
    b[ca % 3] = 1 - q->t;
    b[cb % 3] = q->t;
    return 0;
}

static int make_path(ctx *c, gs_path **out)
{
    const gs__topo *t = c->t;
    size_t n = c->nq;
    double *xyz = gs__malloc(3 * n, sizeof *xyz), *bary = gs__malloc(3 * n, sizeof *bary);
    uint32_t *face = gs__malloc(n, sizeof *face);
    if (!xyz || !bary || !face) {
        free(xyz), free(bary), free(face);
        return oom(c);
    }
    double len = 0;
    for (size_t i = 0; i < n; ++i) {
        uint32_t g = i + 1 < n || n == 1 ? c->q[i].seg : c->q[i - 1].seg;
        face[i] = g;
        double *b = bary + 3 * i;
        if (bary_of(t, &c->q[i], g, b)) {
            free(xyz), free(bary), free(face);
            return gs__fail(c->err, GS_EINTERNAL, "gs_db_path: point %zu is not in face %u", i, g);
        }
        const uint32_t *T = t->tri + 3 * (size_t)g;
        for (int k = 0; k < 3; ++k)
            xyz[3 * i + k] = b[0] * t->xyz[3 * (size_t)T[0] + k] + b[1] * t->xyz[3 * (size_t)T[1] + k] +
                             b[2] * t->xyz[3 * (size_t)T[2] + k];
        if (i) len += dist3(xyz + 3 * i - 3, xyz + 3 * i);
    }
    return gs__path_adopt((uint32_t)n, xyz, face, bary, len, out, c->err);
}

/* A path this much longer than the database's d(X, Y) is checked: beyond
 * the database's usual errors (exact fields; approximate ones err more). */
#define CHECK_TOL_EXACT 0.01
/* ... and first, a little longer, also traced from the other end */
#define REVERSE_TOL_EXACT 0.005
#define REVERSE_TOL_APPROX 0.01
#define CHECK_TOL_APPROX 0.02
#define CORRIDOR_TOL 0.01   /* the database's error allowed for in the corridor */
/* ... and already at the reverse tolerance when the two walks found
 * different paths (two routes) and the corridor is small (an exact solve
 * of this many vertices costs about a millisecond): on rough and
 * near-symmetric meshes the database errs by up to 2% and a path around
 * the other side of a bump can be 1-1.5% longer than the exact distance
 * but less than 1% longer than the database's. */
#define SMALL_CORRIDOR 300
/* ... but where their lengths differ by less than the shortening's
 * settling tolerance (converge: 8 rounds gaining less than 5e-4 of the
 * length), only if the corridor is cheap: the walks may have ended on one
 * route (bunny-5k: 4 of its 13 corridors, all of 160-260 vertices), or
 * not (a coarse torus: two walks 0.17 edges apart, 4e-4 apart in length,
 * the exact path 1.3% shorter round the other side of the tube). */
#define ROUTE_GAP 5e-4
#define CHEAP_CORRIDOR 100
/* ... and on a rough stretch of surface: where the walk's vertices have
 * an angle defect |2 pi - angle sum| of at least ROUGH_DEFECT radians on
 * average and at least ROUGH_MEDIAN at half of them (bumps and spikes a
 * few edges wide all along; smooth meshes: means of 0.003-0.05; bunny-5k's
 * ears, fandisk's corners: means up to 0.25 but medians mostly below 0.08,
 * 3 walks in 1,000 pass both; bumpy, spiky and noisy meshes: means of
 * 0.12-0.8, medians 0.09-0.85), the database's fits err by up to 2.6% and
 * cannot tell the two sides of a bump apart, so the corridor is solved
 * whenever the path is not shorter than the database's distance, and where
 * the mean is at least ROUGH_STRONG whatever the lengths (sphere-spiky2:
 * a path 2.4% longer than the exact distance was 0.2% shorter than the
 * database's; on the milder meshes every path over 1% was at least 0.2%
 * longer than it), up to ROUGH_CORRIDOR vertices (about 4 ms); and so
 * from a mean of ROUGH_MILD and a share of ROUGH_MILD_SHARE where the
 * defects are noise, not curvature: they differ from the mean of their
 * neighbours' by ROUGH_NOISE on average (sphere-bumpy's paths 1.1-1.2%
 * over the exact distance: means 0.107-0.118, shares 0.52-0.59, noise
 * 0.13-0.15; bunny-5k's walks: noise 0.045 at the median, 0.12 at the
 * 99th percentile, smooth meshes' below 0.03). This and the checks below
 * read the walk's shape only on walks of MIN_SHARE_WALK interior vertices
 * or more (the shares of shorter ones are noise themselves). */
#define ROUGH_DEFECT 0.12
#define ROUGH_MEDIAN 0.08
#define ROUGH_STRONG 0.2
#define ROUGH_CORRIDOR 2000
#define ROUGH_MILD 0.105
#define ROUGH_MILD_SHARE 0.45
#define ROUGH_NOISE 0.125
#define MIN_SHARE_WALK 10
/* ... and, whatever the mean, from NOISY_LONGER over the database's
 * distance up to NOISY_CORRIDOR vertices where the noise is ROUGH_NOISE
 * or more (a sphere of 642 vertices moved radially by up to 4-5%: paths
 * 1.0-1.4% over the exact distance with means of 0.096-0.14, noise
 * 0.14-0.16, 0.45-0.5% over the database's distance; none of 2,000 walks
 * on bunny-5k, spot, homer or fandisk). */
#define NOISY_LONGER 0.003
#define NOISY_CORRIDOR 300
/* ... and, for a surface-point end, already at the reverse tolerance up to
 * POINT_CORRIDOR vertices (about a millisecond): the database's distance
 * between surface points interpolates its corners' (points.c) and errs
 * more, high as often as low, and the walks run between corners: on
 * torus-thin, sphere-bumpy and knot-fat, point paths 1-1.5% longer than
 * the exact distance round the other side of the tube or a bump that all
 * three walks took were 0.7-1% longer than the database's distance. */
#define POINT_CORRIDOR 500
/* ... where the walk's vertices have a mean angle defect of at least
 * POINT_DEFECT (two locally shortest paths enclose curvature: none where
 * the walk runs flat, as on a plane with holes or a cube's faces; 0.03 on
 * torus-thin's walks, 0.05-0.1 on knot-fat's and the bumpy spheres', up
 * to 0.01 on homer-60k's) */
#define POINT_DEFECT 0.02
/* ... and, up to ANISO_CORRIDOR vertices, from ANISO_LONGER over the
 * database's distance where at least ANISO_SHARE of the walk's vertices
 * have an edge ANISO_RATIO times as long as another of theirs: long thin
 * triangles (knot-fat, a tube of 24 x 60 vertices, triangles about 4.4
 * times as long as wide), where the walk along the edges can follow the
 * other side of the tube while the database's distance errs 0.3-0.8% high
 * (every path over 1% in 10,000 vertex pairs and 4,000 point pairs: the
 * path 0.25-1% longer than that distance, where no other check fires).
 * Walks on meshes of rounder triangles pass few such vertices (bunny-5k,
 * spot, homer, fandisk, homer-60k: 1-2 walks in 2,000 at ANISO_SHARE and
 * longer than ANISO_LONGER; knot-fat: nearly all walks). Only where the
 * walk is curved (a mean defect of POINT_DEFECT or more: two routes
 * enclose curvature): a flat or gently curved mesh of thin triangles
 * (aniso40: triangles 35 times as long as wide, mean defects below
 * 0.007, paths within 0.4%) does not need it. */
#define ANISO_RATIO 3.0
#define ANISO_SHARE 0.7
#define ANISO_LONGER 0.003 /* (for a surface-point end: any length above it) */
#define ANISO_CORRIDOR 600
/* ... and, up to POINT_CORRIDOR vertices, from SADDLE_LONGER where at
 * least SADDLE_SHARE of the walk's vertices are saddles (an angle sum
 * above 2 pi + SADDLE_DEFECT) and SADDLE_ANISO have such long edges: a
 * walk along the inner side of such a tube, where the edges along it are
 * shorter (3 of knot-fat's paths over 1% that the rule above misses:
 * 97-100% saddles, 65-68% such vertices; bunny-5k's walks: none in
 * 2,200, the closest 88% and 53%). */
#define SADDLE_DEFECT 0.02
#define SADDLE_SHARE 0.9
#define SADDLE_ANISO 0.6
#define SADDLE_LONGER 0.003
/* ... and, whatever else, on a coarse mesh: where the corridor (as
 * estimated, corridor_size) holds at most COARSE_WIDTH vertices per vertex
 * of the walk (the database's 1% corridor only a few edges wide) on a
 * curved walk (a mean defect of POINT_DEFECT or more). Routes an edge or
 * two apart (the two sides of a vertex or a bump) then differ by about the
 * database's error, and the walk cannot tell them apart (sphere:3 with
 * +-5% sine bumps: paths 1.04-1.27% longer than the exact distance, walks
 * of 7-19 vertices and corridors of 44-150, 6-8 per vertex; bunny-5k:
 * 11.7 at the first percentile, none of 2,200 sampled paths on
 * homer-60k); and there the exact solve costs about as much as the walk. */
#define COARSE_WIDTH 8
/* ... and, up to ROUGH_CORRIDOR vertices, whatever the length, where the
 * mesh's connectivity is irregular: IRREGULAR_SAMPLE vertices spread over
 * it have, on average, IRREGULAR_MESH or more edges more or fewer than 6
 * (random edge flips, tools/unseen_meshes.py's flipped()). There the
 * database's distance errs high by up to 1.6% (spot with half its edges
 * tried for flips: +1.58% where the same pair on spot errs +0.43%) while
 * the sums d(X, v) + d(v, Y) at the walk's vertices err either way, and
 * the walk, forced along the long flipped edges, can end round the wrong
 * saddle: paths 1.0-1.9% longer than the exact distance that were at most
 * 0.9% longer than the database's distance, or shorter, 1 to 3 in 10,000
 * on spot, bunny-5k, homer, fandisk and rocker-arm with 10-50% of their
 * edges tried for flips (samples 1.1-1.7). No length rule tells them from
 * the other paths there (nearly every path is longer than the least sum
 * along its walk), nor does the walk's own neighbourhood (such paths'
 * walks had neighbours 1.03-1.6 edges off 6 on average, bunny-5k's walks
 * up to 2.2). Meshes whose irregular triangles are their own stay below:
 * bunny-5k, a decimated mesh, 0.86; rocker-arm 0.80; spot, homer,
 * fandisk, homer-60k 0.17-0.26. Masked grids and plates whose alternating
 * diagonals give valences of 4 and 8 take the exact solve too (time, not
 * length). */
#define IRREGULAR_MESH 1.0
#define IRREGULAR_SAMPLE 256
/* ... and up to IRREGULAR_CORRIDOR vertices from NOISY_LONGER over the
 * database's distance (flipped homer: a path between surface points 1.02%
 * over the exact distance, 0.47% over the database's, its corridor 2,467
 * vertices). */
#define IRREGULAR_CORRIDOR 5000

/* ---- the check: a path much longer than the database's distance -------- */

/* The longest edge at vertex v: no point of v's faces is farther from v. */
static double longest_edge(const gs__topo *t, uint32_t v)
{
    double m = 0;
    for (uint32_t j = t->vc_start[v]; j < t->vc_start[v + 1]; ++j) {
        uint32_t h = t->vc[j];
        m = fmax(m, fmax(t->len[h], t->len[gs__prev(h)]));
    }
    return m;
}

/* Of the n vertices v[], those with d(X, v) + d(v, Y) (the database's,
 * c's two ends) at most thr plus twice their longest edge appended to the
 * vertex path c->vp (d(v, Y) asked only where d(X, v) is that small). */
static int corridor_batch(ctx *c, const uint32_t *v, uint32_t n, double thr)
{
    uint32_t near[MAX_FAN], nn = 0;
    double reach[MAX_FAN];
    int rc = fetch(c, v, n, 0, INFINITY);
    if (rc) return rc;
    for (uint32_t j = 0; j < n; ++j) {
        reach[nn] = thr + 2 * longest_edge(c->t, v[j]);
        if (c->dval[2 * gs__idmap_get(&c->dmap, v[j])] <= reach[nn]) near[nn++] = v[j];
    }
    if (nn && (rc = fetch(c, near, nn, 1, INFINITY))) return rc;
    for (uint32_t j = 0; j < nn && !rc; ++j) {
        uint32_t sl = gs__idmap_get(&c->dmap, near[j]);
        if (c->dval[2 * sl] + c->dval[2 * sl + 1] <= reach[j]) rc = push_vertex(c, near[j]);
    }
    return rc;
}

/* The path is longer than the database's distance d by more than the
 * database's errors usually are (the descent then followed another
 * route's valley: a coarse mesh next to the path, a fitted function's
 * error): the exact shortest path inside the corridor that holds the
 * shortest path as far as the database can tell, the vertices v with
 * d(X, v) + d(v, Y) at most d plus CORRIDOR_TOL (at most the path's
 * length; plus the ends' offsets and twice v's longest edge: every corner
 * of every face that a path within that bound crosses), grown from the
 * vertex path; the faces at them form a patch, solved exactly
 * (gs_solver_path). *out: that path if shorter, else untouched. */
static int corridor(ctx *c, const gs_mesh *mesh, const gs_source *x, const gs_source *y, double len, double d,
                    double slack, gs_path **out)
{
    const gs__topo *t = c->t;
    double bound = d * (1 + CORRIDOR_TOL); /* the shortest path, for the database (if its error is below the tolerance) */
    double thr = (bound < len ? bound : len) + slack; /* plus twice the vertex's longest edge (longest_edge) */
    /* flood: c->vp grows into the corridor's vertices (amap: seen) */
    c->na = 0;
    if (c->amap.cap) memset(c->amap.key, 0xff, c->amap.cap * sizeof *c->amap.key), c->amap.n = 0;
    uint32_t slot;
    for (size_t i = 0; i < c->nvp; ++i)
        if (anode(c, c->vp[i], &slot)) return oom(c);
    size_t nseed = c->nvp;
    c->nvp = 0;
    for (size_t i = 0; i < nseed; ++i)
        if (c->aclosed[i] == 0) c->aclosed[i] = 1, c->vp[c->nvp++] = c->anode[i];
    /* the unseen neighbours of the next vertices in the queue, a batch of
     * about half MAX_FAN at a time (fetch: their records requested from
     * memory together), those in the corridor queued */
    uint32_t cand[MAX_FAN], nc = 0;
    for (size_t q = 0;;) {
        if (q < c->nvp && nc <= MAX_FAN / 2) {
            uint32_t v = c->vp[q++];
            for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1]; ++i) {
                uint32_t h = t->vc[i];
                uint32_t nb[2] = {t->tri[gs__next(h)], t->tri[gs__prev(h)]};
                for (int k = 0; k < 2; ++k) {
                    if (gs__idmap_get(&c->amap, nb[k]) != GS_NONE) continue;
                    if (anode(c, nb[k], &slot)) return oom(c);
                    if (nc == MAX_FAN) {
                        int rc = corridor_batch(c, cand, nc, thr);
                        if (rc) return rc;
                        nc = 0;
                    }
                    cand[nc++] = nb[k];
                }
            }
            continue;
        }
        if (!nc) break;
        int rc = corridor_batch(c, cand, nc, thr);
        if (rc) return rc;
        nc = 0;
    }
    /* the faces at the corridor's vertices, and the ends' faces */
    gs__idmap fmap = {0};
    uint32_t *faces = NULL;
    size_t nf = 0, fcap = 0;
    int rc = GS_OK;
    for (size_t q = 0; q < c->nvp + 2 && !rc; ++q) {
        const gs_source *e = q == c->nvp ? x : y;
        uint32_t v = q < c->nvp ? c->vp[q] : e->face == GS_NONE ? e->vertex : GS_NONE;
        uint32_t i0 = 0, i1 = 1, one = q < c->nvp ? GS_NONE : e->face;
        if (v != GS_NONE) i0 = t->vc_start[v], i1 = t->vc_start[v + 1];
        for (uint32_t i = i0; i < i1 && !rc; ++i) {
            uint32_t f = v != GS_NONE ? t->vc[i] / 3 : one;
            if (f == GS_NONE || gs__idmap_get(&fmap, f) != GS_NONE) continue;
            if (gs__grow((void **)&faces, &fcap, nf + 1, sizeof *faces) || gs__idmap_put(&fmap, f, (uint32_t)nf))
                rc = oom(c);
            else
                faces[nf++] = f;
        }
    }
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    gs_path *p = NULL;
    if (!rc) rc = gs_patch_create(mesh, faces, (uint32_t)nf, &patch, c->err);
    if (!rc) rc = gs_solver_create(patch, GS_METHOD_EXACT, &solver, c->err);
    gs_source lx = *x, ly = *y;
    for (int k = 0; k < 2 && !rc; ++k) {
        gs_source *e = k ? &ly : &lx;
        if (e->face == GS_NONE) e->vertex = gs_patch_vertex_from_mesh(patch, e->vertex);
        else e->face = gs__idmap_get(&fmap, e->face);
    }
    /* bounded by the path's length: only a shorter one is wanted */
    if (!rc) rc = gs__solver_path_bounded(solver, &lx, &ly, len, &p, c->err);
    uint32_t n = gs_path_num_points(p);
    if (!rc && n && gs_path_length(p) < len) { /* in mesh faces */
        double *xyz = gs__malloc(3 * (size_t)n, sizeof *xyz), *bary = gs__malloc(3 * (size_t)n, sizeof *bary);
        uint32_t *face = gs__malloc(n, sizeof *face);
        if (!xyz || !bary || !face) {
            free(xyz), free(bary), free(face);
            rc = oom(c);
        } else {
            memcpy(xyz, gs_path_xyz(p), 3 * (size_t)n * sizeof *xyz);
            memcpy(bary, gs_path_bary(p), 3 * (size_t)n * sizeof *bary);
            for (uint32_t i = 0; i < n; ++i) face[i] = gs_patch_face_to_mesh(patch, gs_path_faces(p)[i]);
            gs_path *r = NULL;
            rc = gs__path_adopt(n, xyz, face, bary, gs_path_length(p), &r, c->err);
            if (!rc) gs_path_free(*out), *out = r;
        }
    }
    gs_path_free(p);
    gs_solver_free(solver);
    gs_patch_free(patch);
    gs__idmap_free(&fmap);
    free(faces);
    return rc;
}

/* About how many vertices the corridor of a path of length len between
 * ends at database distance d holds: the ellipse of the points whose
 * distances to the two ends sum to at most the corridor's bound (foci
 * min(d, len) apart), over the area per vertex of an equilateral mesh of
 * the mesh's mean edge length. */
static double corridor_size(const gs_mesh *mesh, double len, double d)
{
    double thr = fmin(d * (1 + CORRIDOR_TOL), len) + 2 * mesh->report.max_edge, e = mesh->report.mean_edge;
    double a = 0.5 * thr, f = 0.5 * fmin(d, len);
    return M_PI * a * sqrt(fmax(a * a - f * f, 0)) / (0.5 * sqrt(3.0) * e * e);
}

/* The shape of the surface along the walk c->vp, over its interior
 * (non-boundary) vertices: their number, their mean angle defect
 * |2 pi - angle sum|, the share with ROUGH_MEDIAN or more and the share
 * of saddles (SADDLE_DEFECT). */
typedef struct walk_shape {
    size_t n;
    double mean, big, saddles;
} walk_shape;

static walk_shape shape_of(const ctx *c)
{
    const gs__topo *t = c->t;
    walk_shape w = {0, 0, 0, 0};
    for (size_t i = 0; i < c->nvp; ++i) {
        uint32_t v = c->vp[i];
        if (t->vflag[v] & (GS_V_BOUNDARY | GS_V_UNUSED)) continue;
        double k = 2 * M_PI - t->vangle[v];
        w.saddles += k <= -SADDLE_DEFECT, k = fabs(k);
        w.mean += k, ++w.n, w.big += k >= ROUGH_MEDIAN;
    }
    if (w.n) w.mean /= (double)w.n, w.big /= (double)w.n, w.saddles /= (double)w.n;
    return w;
}

/* How noisy the defects along the walk are: the mean over its interior
 * vertices of |defect - the mean defect of its interior neighbours|
 * (signed defects 2 pi - angle sum). */
static double walk_noise(const ctx *c)
{
    const gs__topo *t = c->t;
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < c->nvp; ++i) {
        uint32_t v = c->vp[i];
        if (t->vflag[v] & (GS_V_BOUNDARY | GS_V_UNUSED)) continue;
        double nb = 0;
        uint32_t m = 0;
        for (uint32_t j = t->vc_start[v]; j < t->vc_start[v + 1]; ++j) {
            uint32_t w = t->tri[gs__next(t->vc[j])];
            if (!(t->vflag[w] & (GS_V_BOUNDARY | GS_V_UNUSED))) nb += 2 * M_PI - t->vangle[w], ++m;
        }
        if (m) sum += fabs(2 * M_PI - t->vangle[v] - nb / m), ++n;
    }
    return n ? sum / (double)n : 0;
}

/* The mean |number of corners - 6| of IRREGULAR_SAMPLE interior vertices
 * spread evenly over the ids (every one on smaller meshes): the same
 * vertices on every call, so that they stay in the caches. */
static double mesh_valence(const gs__topo *t)
{
    double sum = 0;
    size_t n = 0;
    uint32_t step = t->nv > IRREGULAR_SAMPLE ? t->nv / IRREGULAR_SAMPLE : 1;
    for (uint32_t k = 0, v = 0; k < IRREGULAR_SAMPLE && v < t->nv; ++k, v += step) {
        if (t->vflag[v] & (GS_V_BOUNDARY | GS_V_UNUSED)) continue;
        sum += fabs((double)(t->vc_start[v + 1] - t->vc_start[v]) - 6), ++n;
    }
    return n ? sum / (double)n : 0;
}

/* The share of the walk's vertices whose longest edge is at least
 * ANISO_RATIO times their shortest. */
static double walk_anisotropy(const ctx *c)
{
    const gs__topo *t = c->t;
    size_t n = 0, thin = 0;
    for (size_t i = 0; i < c->nvp; ++i) {
        uint32_t v = c->vp[i];
        double lo = INFINITY, hi = 0;
        for (uint32_t j = t->vc_start[v]; j < t->vc_start[v + 1]; ++j) { /* the edges of its corners */
            uint32_t h = t->vc[j];
            lo = fmin(lo, fmin(t->len[h], t->len[gs__prev(h)]));
            hi = fmax(hi, fmax(t->len[h], t->len[gs__prev(h)]));
        }
        if (hi > 0) ++n, thin += hi >= ANISO_RATIO * lo;
    }
    return n ? (double)thin / (double)n : 0;
}

/* Whether the walk c->vp runs far off the database's shortest path: some
 * vertex v of it with d(X, v) + d(v, Y) (c's two ends, from the database)
 * above (1 + excess) d_ends. A vertex of a shortest path has no such
 * excess, up to the database's error; a walk round the wrong side of an
 * obstacle, locally shortest all along, has a band of them. */
static int walk_far_off(ctx *c, double d_ends, double excess, int *far)
{
    *far = 0;
    for (size_t i = 0; i < c->nvp && !*far; i += MAX_FAN) {
        uint32_t n = (uint32_t)(c->nvp - i < MAX_FAN ? c->nvp - i : MAX_FAN);
        int rc = fetch(c, c->vp + i, n, 0, INFINITY);
        if (!rc) rc = fetch(c, c->vp + i, n, 1, INFINITY);
        if (rc) return rc;
        for (uint32_t j = 0; j < n; ++j) {
            uint32_t s = gs__idmap_get(&c->dmap, c->vp[i + j]);
            if (c->dval[2 * s] + c->dval[2 * s + 1] > (1 + excess) * d_ends) *far = 1;
        }
    }
    return GS_OK;
}

/* A path end as the database's surface point. */
static void source_point(const gs__topo *t, const gs_source *s, gs_surface_point *p)
{
    if (s->face == GS_NONE) {
        *p = gs_surface_point_vertex(s->vertex);
        return;
    }
    const uint32_t *T = t->tri + 3 * (size_t)s->face;
    double b[3], sum = 0;
    for (int k = 0; k < 3; ++k) b[k] = s->bary[k] > 0 ? s->bary[k] : 0, sum += b[k];
    *p = gs_surface_point_make(T[0], T[1], T[2], b[0] / sum, b[1] / sum, b[2] / sum);
}

/* ---- entry points ------------------------------------------------------------ */

int gs_db_check_mesh(const gs_db *db, const gs_mesh *mesh, gs_error *err)
{
    if (!db || !mesh) return gs__fail(err, GS_EARG, "gs_db_check_mesh: NULL argument");
    if (mesh->nv != db->nv)
        return gs__fail(err, GS_EARG, "the mesh is not the database's: it has %u vertices, the database %u", mesh->nv,
                        db->nv);
    for (uint32_t v = 0; v < db->nv; ++v) {
        const double *a = mesh->xyz + 3 * (size_t)v, *b = db->xyz + 3 * (size_t)v;
        if (memcmp(a, b, 3 * sizeof *a))
            return gs__fail(err, GS_EARG,
                            "the mesh is not the database's: vertex %u is at (%.17g, %.17g, %.17g) in the mesh, "
                            "(%.17g, %.17g, %.17g) in the database",
                            v, a[0], a[1], a[2], b[0], b[1], b[2]);
        if ((db->leaf[v] == GS_NONE) != ((mesh->topo.vflag[v] & GS_V_UNUSED) != 0))
            return gs__fail(err, GS_EARG,
                            "the mesh is not the database's: vertex %u is used by %s face in the mesh, by %s in the "
                            "database",
                            v, db->leaf[v] == GS_NONE ? "a" : "no", db->leaf[v] == GS_NONE ? "none" : "some");
    }
    return GS_OK;
}

/* An end of the path as a point (a face point with one nonzero weight is
 * that vertex; with two, a point of that edge). */
static int end_point(const gs__topo *t, const gs_source *s, const char *name, qpt *q, gs_error *err)
{
    memset(q, 0, sizeof *q);
    q->seg = q->f = q->b = GS_NONE;
    if (s->face == GS_NONE) {
        if (s->vertex >= t->nv)
            return gs__fail(err, GS_EARG, "gs_db_path: %s: vertex %u out of range (%u vertices)", name, s->vertex,
                            t->nv);
        q->type = Q_VERTEX, q->a = s->vertex;
        return GS_OK;
    }
    if (s->face >= t->nf)
        return gs__fail(err, GS_EARG, "gs_db_path: %s: face %u out of range (%u faces)", name, s->face, t->nf);
    double b[3], sum = 0;
    for (int k = 0; k < 3; ++k) {
        b[k] = s->bary[k];
        if (!isfinite(b[k]) || b[k] < -1e-9)
            return gs__fail(err, GS_EARG, "gs_db_path: %s: barycentric coordinate %d is %g (must be >= 0)", name, k,
                            b[k]);
        b[k] = b[k] > 0 ? b[k] : 0;
        sum += b[k];
    }
    if (!(fabs(sum - 1.0) <= 1e-9))
        return gs__fail(err, GS_EARG, "gs_db_path: %s: barycentric coordinates sum to %.17g (must be 1)", name, sum);
    const uint32_t *T = t->tri + 3 * (size_t)s->face;
    int nz = 0, k1 = -1, k2 = -1;
    for (int k = 0; k < 3; ++k) {
        b[k] /= sum;
        if (b[k] > 0) {
            ++nz;
            if (k1 < 0) k1 = k;
            else k2 = k;
        }
    }
    if (nz == 1) {
        q->type = Q_VERTEX, q->a = T[k1];
    } else if (nz == 2) {
        q->type = Q_EDGE, q->a = T[k1], q->b = T[k2], q->t = b[k2] / (b[k1] + b[k2]), q->f = s->face;
    } else {
        q->type = Q_FACE, q->f = s->face;
        memcpy(q->bary, b, sizeof b);
    }
    return GS_OK;
}

static void q_position(const gs__topo *t, const qpt *q, double p[3])
{
    if (q->type != Q_VERTEX && q->type != Q_EDGE) {
        gs__face_point(t, q->f, q->bary, p);
        return;
    }
    for (int k = 0; k < 3; ++k)
        p[k] = q->type == Q_VERTEX ? t->xyz[3 * (size_t)q->a + k]
                                   : (1 - q->t) * t->xyz[3 * (size_t)q->a + k] + q->t * t->xyz[3 * (size_t)q->b + k];
}

/* The corners of a point's face that carry it (nonzero weight): vertex
 * ids into v, returns their count. */
static int carriers(const gs__topo *t, const qpt *q, uint32_t v[3])
{
    if (q->type == Q_VERTEX) return v[0] = q->a, 1;
    if (q->type == Q_EDGE) return v[0] = q->a, v[1] = q->b, 2;
    int n = 0;
    for (int k = 0; k < 3; ++k)
        if (q->bary[k] > 0) v[n++] = t->tri[3 * (size_t)q->f + k];
    return n;
}

/* A walk's vertices (Y first, loops removed) made a path: turned X first,
 * its sleeve built, shortened (*len: its length) and traced. */
static int finish(ctx *c, const qpt *qx, const qpt *qy, double *len)
{
    for (size_t i = 0, j = c->nvp - 1; i < j; ++i, --j) { /* X first */
        uint32_t s = c->vp[i];
        c->vp[i] = c->vp[j], c->vp[j] = s;
    }
    endspec xin = {ES_NONE, 0}, yout = {ES_NONE, 0};
    if (qx->type != Q_VERTEX) xin = (endspec){ES_FACE, qx->f};
    if (qy->type != Q_VERTEX) yout = (endspec){ES_FACE, qy->f};
    int rc = build_sleeve(c, xin, yout);
    uint32_t xv = qx->type == Q_VERTEX ? qx->a : GS_NONE, yv = qy->type == Q_VERTEX ? qy->a : GS_NONE;
    if (!rc) rc = converge(c, qx, qy, xv, yv, len);
    return rc ? rc : trace_points(c, qx, qy);
}

/* One path from X to Y (descent from Y's end, sleeve, shortening): its
 * points in c->q, *len its length. not_target, not_start: a corner of X's
 * and of Y's face not to take as the descent's target and start (another
 * walk's: GS_NONE for none; only for face and edge points). */
static int run(ctx *c, const qpt *qx, const qpt *qy, uint32_t not_target, uint32_t not_start, double *len)
{
    const gs_db *db = c->db;
    const gs__topo *t = c->t;
    uint32_t cx[3], cy[3];
    int ncx = carriers(t, qx, cx), ncy = carriers(t, qy, cy), rc = GS_OK;
    /* the descent's target: X's corner best placed towards Y's heaviest */
    uint32_t yh = cy[0];
    if (qy->type == Q_FACE) {
        int kb = 0;
        for (int k = 1; k < 3; ++k)
            if (qy->bary[k] > qy->bary[kb]) kb = k;
        yh = t->tri[3 * (size_t)qy->f + kb];
    } else if (qy->type == Q_EDGE) {
        yh = qy->t > 0.5 ? qy->b : qy->a;
    }
    double px[3], py[3];
    q_position(t, qx, px);
    q_position(t, qy, py);
    c->target = cx[0] != not_target ? cx[0] : cx[1];
    if (ncx > 1) {
        double best = INFINITY;
        for (int k = 0; k < ncx; ++k) {
            if (cx[k] == not_target) continue;
            double d = dist3(px, vpos(c, cx[k])) + gs_db_distance(db, cx[k], yh);
            if (d < best) best = d, c->target = cx[k];
        }
    }
    /* the targets: X itself, or the corners of its face */
    uint32_t targets[3];
    int nt = 0;
    if (qx->type == Q_VERTEX) targets[nt++] = qx->a;
    else
        for (int k = 0; k < 3; ++k) targets[nt++] = t->tri[3 * (size_t)qx->f + k];
    /* the start: Y itself, or its face's corner best placed towards X */
    uint32_t start = cy[0] != not_start ? cy[0] : cy[1];
    if (ncy > 1) {
        double best = INFINITY;
        for (int k = 0; k < ncy && !rc; ++k) {
            if (cy[k] == not_start) continue;
            double d;
            rc = dist_to_target(c, cy[k], &d);
            d += dist3(py, vpos(c, cy[k]));
            if (d < best) best = d, start = cy[k];
        }
    }
    c->origin = start;
    if (!rc) rc = push_vertex(c, start);
    if (!rc) rc = descend(c, targets, nt);
    if (!rc) rc = remove_loops(c);
    return rc ? rc : finish(c, qx, qy, len);
}

/* ---- a third walk, round the other side ---------------------------------- */

/* Both walks may follow one locally shortest route round the wrong side of
 * an obstacle (knot-fat, a fat torus-knot tube: 40 pairs in 2,000 1-1.5%
 * longer than the exact path but less than 1% longer than the database's
 * distance, the true path more than six rings away). The database knows
 * better at the walk's vertices: the sum d(X, v) + d(v, Y) is well above
 * d(X, Y) at some. A remedy much cheaper than the corridor's exact solve:
 * at a few rings round the walk, the vertex w where the database's
 * d(X, w) + d(w, Y) is least, and, if that is DETOUR_GAIN below the path's
 * length (the database sees a shorter path through w; bunny-5k: 3 of the
 * 64 paths checked have a waypoint below the length), a walk through it.
 * Called for when the path is longer than the database's distance by DETOUR_LONGER
 * and by DETOUR_EDGES mean edge lengths, and some vertex of the walk has a
 * sum above (1 + DETOUR_EXCESS) d(X, Y) (knot-fat's 40: at least 0.0057,
 * 0.11 and 0.014; bunny-5k: 1.8% of its paths pass all three, spot 0.9%,
 * homer-60k 0.8%, and then the sums rule out nearly every walk). */
#define DETOUR_EXCESS 0.014
#define DETOUR_LONGER 0.005
#define DETOUR_EDGES 0.1
#define DETOUR_GAIN 0.003

/* The waypoints: for each ring r of detour_rings round the walk c->vp (the
 * vertices r edges away from it; knot-fat, one ring alone: 4 rings leave
 * 16 of the 40, 8 rings 2, 10 none, 12 rings 31), the vertex of that ring
 * next to the walk's middle half with the least d(X, w) + d(w, Y) (c's two
 * ends) if below thr: w[k] and its sum s[k] (GS_NONE and infinity if none;
 * the straight lines to the ends rule out most without a query). c->vp is
 * kept. */
#define DETOUR_NRINGS 3
#define RINGS_AHEAD 8 /* the breadth-first search's prefetch distance, in queued vertices */
static const int detour_rings[DETOUR_NRINGS] = {5, 10, 15};
static int waypoints(ctx *c, double thr, uint32_t w[DETOUR_NRINGS], double s[DETOUR_NRINGS])
{
    const gs__topo *t = c->t;
    int rings[DETOUR_NRINGS];
    for (int k = 0; k < DETOUR_NRINGS; ++k) rings[k] = detour_rings[k], w[k] = GS_NONE, s[k] = INFINITY;
    int last = rings[DETOUR_NRINGS - 1];
    /* ring + 1 of each vertex reached (0: not yet), breadth first */
    uint8_t *seen = calloc(t->nv, 1);
    size_t nq = 0, qcap = 0, ocap = 0;
    uint32_t *queue = NULL, *from = NULL;
    int rc = GS_OK;
    if (!seen) return oom(c);
    for (size_t i = 0; i < c->nvp && !rc; ++i) {
        uint32_t v = c->vp[i];
        if (seen[v]) continue;
        if (gs__grow((void **)&queue, &qcap, nq + 1, sizeof *queue) || gs__grow((void **)&from, &ocap, nq + 1, sizeof *from))
            rc = oom(c);
        else
            seen[v] = 1, from[nq] = (uint32_t)i, queue[nq++] = v;
    }
    for (size_t q = 0; q < nq && !rc && seen[queue[q]] <= last; ++q) {
        /* the fans of the vertices next in the queue, requested from memory
         * ahead (thousands of vertices, scattered: most miss the caches) */
        if (q + 2 * RINGS_AHEAD < nq) __builtin_prefetch(t->vc_start + queue[q + 2 * RINGS_AHEAD]);
        if (q + RINGS_AHEAD < nq) __builtin_prefetch(t->vc + t->vc_start[queue[q + RINGS_AHEAD]]);
        if (q + RINGS_AHEAD / 2 < nq) {
            uint32_t u = queue[q + RINGS_AHEAD / 2];
            for (uint32_t i = t->vc_start[u]; i < t->vc_start[u + 1]; ++i) __builtin_prefetch(t->tri + t->vc[i]);
        }
        uint32_t v = queue[q], fan = t->vc_start[v + 1] - t->vc_start[v];
        if (gs__grow((void **)&queue, &qcap, nq + 2 * (size_t)fan, sizeof *queue) ||
            gs__grow((void **)&from, &ocap, nq + 2 * (size_t)fan, sizeof *from)) {
            rc = oom(c);
            break;
        }
        for (uint32_t i = t->vc_start[v]; i < t->vc_start[v + 1]; ++i) {
            uint32_t h = t->vc[i];
            uint32_t nb[2] = {t->tri[gs__next(h)], t->tri[gs__prev(h)]};
            for (int k = 0; k < 2; ++k) {
                if (seen[nb[k]]) continue;
                seen[nb[k]] = (uint8_t)(seen[v] + 1), from[nq] = from[q], queue[nq++] = nb[k];
            }
        }
    }
    /* the sums at the chosen rings, next to the walk's middle half */
    size_t lo = c->nvp / 4, hi = c->nvp - lo;
    const double *xp = vpos(c, c->target), *yp = vpos(c, c->origin); /* sums below the straight lines' are none */
    uint32_t cand[MAX_FAN], near[MAX_FAN];
    for (size_t q = 0; q < nq && !rc;) {
        uint32_t n = 0, nn = 0;
        for (; q < nq && n < MAX_FAN; ++q) {
            int k = 0, r = seen[queue[q]] - 1;
            while (k < DETOUR_NRINGS && rings[k] != r) ++k;
            if (k < DETOUR_NRINGS && from[q] >= lo && from[q] < hi &&
                dist3(vpos(c, queue[q]), xp) + dist3(vpos(c, queue[q]), yp) < thr)
                cand[n++] = queue[q];
        }
        rc = fetch(c, cand, n, 0, INFINITY);
        for (uint32_t j = 0; j < n && !rc; ++j)
            if (c->dval[2 * gs__idmap_get(&c->dmap, cand[j])] + dist3(vpos(c, cand[j]), yp) < thr) near[nn++] = cand[j];
        if (!rc) rc = fetch(c, near, nn, 1, INFINITY);
        for (uint32_t j = 0; j < nn && !rc; ++j) {
            uint32_t sl = gs__idmap_get(&c->dmap, near[j]);
            double g = c->dval[2 * sl] + c->dval[2 * sl + 1];
            int k = 0, r = seen[near[j]] - 1;
            while (rings[k] != r) ++k;
            if (g < thr && g < s[k]) s[k] = g, w[k] = near[j];
        }
    }
    free(seen), free(queue), free(from);
    return rc;
}

/* A walk from X to Y through vertex w (the descent from w to X, then from
 * Y's start corner to w; loops cut, sleeve, shortening): its points in
 * c->q, *len its length. base: the first walk (its ends' corners and
 * distances are reused). c: zeroed, freed by the caller. */
static int via(ctx *c, const ctx *base, const qpt *qx, const qpt *qy, uint32_t w, double *len)
{
    const gs__topo *t = c->t;
    uint32_t targets[3];
    int nt = 0, rc;
    if (qx->type == Q_VERTEX) targets[nt++] = qx->a;
    else
        for (int k = 0; k < 3; ++k) targets[nt++] = t->tri[3 * (size_t)qx->f + k];
    /* Y's start down to w */
    ctx d;
    memset(&d, 0, sizeof d);
    d.db = c->db, d.t = t, d.err = c->err, d.donor = base;
    d.target = w, d.origin = base->origin;
    rc = push_vertex(&d, base->origin);
    if (!rc) rc = descend(&d, &w, 1);
    /* w down to X */
    c->donor = base, c->target = base->target, c->origin = w;
    if (!rc) rc = push_vertex(c, w);
    if (!rc) rc = descend(c, targets, nt);
    if (!rc) { /* Y ... w ... X */
        size_t n = d.nvp + c->nvp - 1;
        if (gs__grow((void **)&d.vp, &d.vpcap, n, sizeof *d.vp)) rc = oom(c);
        else {
            memcpy(d.vp + d.nvp, c->vp + 1, (c->nvp - 1) * sizeof *c->vp);
            d.nvp = n;
            uint32_t *s = c->vp;
            size_t sc = c->vpcap;
            c->vp = d.vp, c->vpcap = d.vpcap, c->nvp = n;
            d.vp = s, d.vpcap = sc;
        }
    }
    ctx_free(&d);
    if (!rc) rc = remove_loops(c);
    return rc ? rc : finish(c, qx, qy, len);
}

static void reverse_points(ctx *c);
static int second_route(ctx *c, const qpt *qx, const qpt *qy, int reversed, double d, double *len, gs_path **out,
                        int open);

/* A walk through vertex w (via; c's ends qx, qy), *out replaced and *len
 * lowered if it is shorter. reversed: c runs from Y to X, *out from X to
 * Y. */
static int walk_via(const ctx *c, const qpt *qx, const qpt *qy, int reversed, uint32_t w, double *len, gs_path **out)
{
    ctx c3;
    memset(&c3, 0, sizeof c3);
    c3.db = c->db, c3.t = c->t, c3.err = c->err;
    double len3;
    int rc = via(&c3, c, qx, qy, w, &len3);
    if (!rc && len3 < *len) {
        gs_path *p = NULL;
        if (reversed) reverse_points(&c3);
        rc = make_path(&c3, &p);
        if (!rc) gs_path_free(*out), *out = p, *len = len3;
    }
    ctx_free(&c3);
    return rc;
}

/* The third walk (above) when the walk c's triangle excess calls for it:
 * *out replaced and *len lowered if it is shorter. reversed: c runs from
 * Y to X (qx, qy: c's ends, Y and X), *out from X to Y. */
static int detour(ctx *c, const gs_mesh *mesh, const qpt *qx, const qpt *qy, int reversed, double d, double *len,
                  gs_path **out)
{
    if (*len <= d * (1 + DETOUR_LONGER)) return GS_OK;
    if (*len - d < DETOUR_EDGES * mesh->report.mean_edge) return GS_OK;
    int far, rc = walk_far_off(c, gs_db_distance(c->db, c->target, c->origin), DETOUR_EXCESS, &far);
    if (rc || !far) return rc;
    uint32_t w[DETOUR_NRINGS];
    double sum[DETOUR_NRINGS], len0 = *len;
    if ((rc = waypoints(c, len0 * (1 - DETOUR_GAIN), w, sum))) return rc;
    for (int k = 0; k < DETOUR_NRINGS && !rc; ++k)
        if (w[k] != GS_NONE) rc = walk_via(c, qx, qy, reversed, w[k], len, out);
    /* and across the middle, beyond the path's own run */
    return rc ? rc : second_route(c, qx, qy, reversed, d, len, out, 1);
}

/* The points of a path from Y to X as the path from X to Y (each point with
 * the face of the segment that leaves it). */
static void reverse_points(ctx *c)
{
    size_t n = c->nq;
    for (size_t i = 0, j = n - 1; n && i < j; ++i, --j) {
        qpt s = c->q[i];
        c->q[i] = c->q[j], c->q[j] = s;
    }
    /* point i leaves by the segment that arrived at it: the next point's */
    for (size_t i = 0; i + 1 < n; ++i) c->q[i].seg = c->q[i + 1].seg;
    if (n > 1) c->q[n - 1].seg = c->q[n - 2].seg;
}

/* ---- a second route across the middle ----------------------------------- */

/* Both walks may follow one locally shortest route while another, across
 * the path's middle, is shorter by 1% or more, and no check above fires:
 * - round a tube (knot:300,6,0.1; knot:200,10,0.15): the shortest path
 *   winds round it one way, another locally shortest path the other way.
 *   Where the ends are nearly opposite, the two lengths differ by about as
 *   much as the database's distances err, and on a tube a few edges round
 *   the database ranks the windings wrongly by more (knot:200,10,0.15: its
 *   sums put the other winding 1.7% above the path's, which is 1% longer;
 *   paths 1.0-1.25% longer than the exact distance and 0.3-0.85% longer
 *   than the database's). The shortening keeps a path's winding (it moves
 *   the path one vertex at a time), so the other winding needs a walk of
 *   its own. Unrolled, a tube of girth C is a strip of width C, the path
 *   of length len offset y0 round it (y0 <= C), the other winding offset
 *   C - y0: that one is shorter only if y0 > C / 2, so only if
 *   C < SECOND_REACH len, and 1% shorter only if C >= TUBE_MIN len (the
 *   offsets' squares must differ by 2% of len squared); at the middle it
 *   passes the tube's far half.
 * - round the other side of a hill (peaks:50, 1.05%): the path's own
 *   middle lies outside the database's corridor (its sums there are more
 *   than CORRIDOR_TOL above the path's length), and a second run of the
 *   corridor crosses the middle farther out.
 * The plane across the path's middle cuts the surface in a curve
 * (cut_walk). Where it closes round a tube (as above, and at most
 * TUBE_EDGES edges round: on finer tubes the database ranks the windings
 * well, on homer-60k's body 16 walks round its other side in 2,200 paths
 * found none shorter) and the path is not shorter than the database's
 * distance (one 1% too long is not, where the database errs less than 1%
 * high), a walk (`via`) through the vertex of the curve's far half (a
 * quarter to three quarters of the way round) where the database's
 * d(X, v) + d(v, Y) is least, if within CORRIDOR_TOL of the path's length;
 * where it is open, with the detour's walks (detour: the path much longer
 * than the database's distance and off its shortest path) and where the
 * path's own crossing is outside the corridor, a walk through the vertex
 * of least sum past the path's own run below the corridor's bound, if
 * the database sees it shorter than the path. The shorter path is kept. */
#define CUT_KEEP 512 /* at most so many cut edges read each way */
#define SECOND_REACH 2.0 /* also the reach of the curve on an open cut */
#define TUBE_MIN 0.14
#define TUBE_EDGES 64

/* Which side of the plane n . x = o vertex v is on (on it: in front). */
static int cut_side(const gs__topo *t, const double n[3], double o, uint32_t v)
{
    const double *p = t->xyz + 3 * (size_t)v;
    return n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - o >= 0;
}

/* Where the plane n . x = o cuts half-edge h (its ends on either side). */
static void cut_point(const gs__topo *t, const double n[3], double o, uint32_t h, double x[3])
{
    const double *p = t->xyz + 3 * (size_t)t->tri[h], *q = t->xyz + 3 * (size_t)t->tri[gs__next(h)];
    double sp = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - o, sq = n[0] * q[0] + n[1] * q[1] + n[2] * q[2] - o;
    double u = sp != sq ? sp / (sp - sq) : 0;
    for (int k = 0; k < 3; ++k) x[k] = p[k] + u * (q[k] - p[k]);
}

/* The plane across the path c->q at its middle: through the point p at
 * half its length, normal n to the segment there (n . x = *o), in face
 * *f0. 0 if the path has no such segment. */
static int cut_plane(const ctx *c, double p[3], double n[3], double *o, uint32_t *f0)
{
    const gs__topo *t = c->t;
    double total = 0, a[3], b[3], s = 0;
    for (size_t i = 0; i + 1 < c->nq; ++i) {
        q_position(t, &c->q[i], a), q_position(t, &c->q[i + 1], b);
        total += dist3(a, b);
    }
    size_t i = 0;
    for (; i + 1 < c->nq; ++i) {
        q_position(t, &c->q[i], a), q_position(t, &c->q[i + 1], b);
        double l = dist3(a, b);
        if (s + l >= 0.5 * total && l > 0) break;
        s += l;
    }
    if (i + 1 >= c->nq || c->q[i].seg == GS_NONE) return 0;
    double l = dist3(a, b), u = fmin(fmax((0.5 * total - s) / l, 0), 1);
    *o = 0, *f0 = c->q[i].seg;
    for (int k = 0; k < 3; ++k) p[k] = a[k] + u * (b[k] - a[k]), n[k] = b[k] - a[k], *o += n[k] * p[k];
    return 1;
}

/* The curve in which that plane cuts the surface, marched from p face to
 * face (a vertex on the plane counts as in front of it: every face the
 * cut enters has exactly two cut edges), leaving f0 by its `side`-th cut
 * edge: the half-edges cut, in order, into hs (*nh, at most cap <=
 * CUT_KEEP; arc: how far along the curve),
 * until the curve has run `budget` long or left the ball (centre,
 * radius), meets the boundary, or closes (back in f0: returns 1, *girth
 * its length). */
static int cut_walk(const ctx *c, const double p[3], const double n[3], double o, uint32_t f0, int side, double budget,
                    const double centre[3], double radius, uint32_t cap, uint32_t *hs, double *arc, uint32_t *nh,
                    double *girth)
{
    const gs__topo *t = c->t;
    uint32_t h = GS_NONE;
    double x[3], prev[3], len;
    *nh = 0;
    for (uint32_t e = 3 * f0, k = 0; e < 3 * f0 + 3 && h == GS_NONE; ++e)
        if (cut_side(t, n, o, t->tri[e]) != cut_side(t, n, o, t->tri[gs__next(e)]) && k++ == (uint32_t)side) h = e;
    if (h == GS_NONE) return 0;
    cut_point(t, n, o, h, prev);
    len = dist3(p, prev);
    while (*nh < cap && len <= budget && dist3(prev, centre) <= radius) {
        arc[*nh] = len, hs[(*nh)++] = h;
        uint32_t e = t->opp[h], h2 = GS_NONE;
        if (e == GS_NONE) return 0;
        if (e / 3 == f0) {
            *girth = len + dist3(prev, p);
            return 1;
        }
        for (uint32_t k = e - e % 3; k < e - e % 3 + 3; ++k)
            if (k != e && cut_side(t, n, o, t->tri[k]) != cut_side(t, n, o, t->tri[gs__next(k)])) h2 = k;
        if (h2 == GS_NONE) return 0;
        cut_point(t, n, o, h2, x);
        len += dist3(prev, x);
        memcpy(prev, x, sizeof x);
        h = h2;
    }
    return 0;
}

/* The database's d(X, v) + d(v, Y) (c's two ends) at the start v of each
 * half-edge hs[0..nh) into val (arg: v), infinity where not below bound:
 * asked only where the straight distances to the ends sum below it, and
 * d(v, Y) only where d(X, v) + |v - Y| is below it. */
static int cut_sums(ctx *c, const uint32_t *hs, uint32_t nh, double bound, double *val, uint32_t *arg)
{
    const double *xp = vpos(c, c->target), *yp = vpos(c, c->origin);
    for (int which = 0; which < 2; ++which)
        for (uint32_t i = 0; i < nh;) {
            uint32_t v[MAX_FAN], m = 0;
            for (; i < nh && m < MAX_FAN; ++i) {
                uint32_t u = c->t->tri[hs[i]], sl = gs__idmap_get(&c->dmap, u);
                double e = which == 0 ? dist3(vpos(c, u), xp) : sl == GS_NONE ? INFINITY : c->dval[2 * sl];
                if (e + dist3(vpos(c, u), yp) < bound) v[m++] = u;
            }
            int rc = fetch(c, v, m, which, INFINITY);
            if (rc) return rc;
        }
    for (uint32_t i = 0; i < nh; ++i) {
        uint32_t u = c->t->tri[hs[i]], sl = gs__idmap_get(&c->dmap, u);
        double g = sl == GS_NONE || !(c->dval[2 * sl] >= 0 && c->dval[2 * sl + 1] >= 0)
                       ? INFINITY
                       : c->dval[2 * sl] + c->dval[2 * sl + 1];
        val[i] = g < bound ? g : INFINITY, arg[i] = g < bound ? u : GS_NONE;
    }
    return GS_OK;
}

/* The walk through a second route (above) when c's path (length *len, the
 * database's distance d) may have one: round a tube (open 0: from step 4
 * for every path) or across an open cut (open 1: from the detour). *out
 * replaced and *len lowered if it is shorter. reversed: c runs from Y to
 * X (qx, qy: c's ends, Y and X), *out from X to Y. */
static int second_route(ctx *c, const qpt *qx, const qpt *qy, int reversed, double d, double *len, gs_path **out,
                        int open)
{
    double p[3], n[3], o, centre[3];
    uint32_t f0;
    if (*len < d || !cut_plane(c, p, n, &o, &f0)) return GS_OK;
    double shift = d - gs_db_distance(c->db, c->target, c->origin), bound = *len * (1 + CORRIDOR_TOL) - shift;
    double g = INFINITY, girth = INFINITY;
    const double *xp = vpos(c, c->target), *yp = vpos(c, c->origin);
    for (int k = 0; k < 3; ++k) centre[k] = 0.5 * (xp[k] + yp[k]);
    /* the cut's edges, sums, vertices and lengths along it (a tube's on the stack) */
    size_t keep = open ? CUT_KEEP : TUBE_EDGES + 1;
    double local[2 * (TUBE_EDGES + 1)], *val = open ? malloc(keep * (2 * sizeof *val + 2 * sizeof(uint32_t))) : local;
    uint32_t local_hs[2 * (TUBE_EDGES + 1)];
    if (!val) return oom(c);
    double *arc = val + keep;
    uint32_t *hs = open ? (uint32_t *)(arc + keep) : local_hs, *arg = hs + keep, w = GS_NONE, nh;
    int rc = GS_OK;
    if (open) { /* only where the path's own crossing is outside the corridor */
        cut_walk(c, p, n, o, f0, 0, SECOND_REACH * *len, centre, 0.5 * bound, 1, hs, arc, &nh, &girth);
        if (nh && !(rc = cut_sums(c, hs, 1, bound, val, arg)) && val[0] < bound) nh = 0;
        if (rc || !nh) {
            free(val);
            return rc;
        }
    }
    for (int side = 0; side < 2 && !rc; ++side) {
        int closed = cut_walk(c, p, n, o, f0, side, SECOND_REACH * *len, centre, 0.5 * bound,
                              open ? CUT_KEEP : TUBE_EDGES + 1, hs, arc, &nh, &girth);
        if (closed == open) break;
        uint32_t i = 0, end = nh;
        if (closed) { /* a tube: its far half, if it is wide enough and coarse */
            if (girth < TUBE_MIN * *len || nh > TUBE_EDGES) break;
            while (i < nh && arc[i] < 0.25 * girth) ++i;
            while (end > i && arc[end - 1] > 0.75 * girth) --end;
        }
        if ((rc = cut_sums(c, hs + i, end - i, bound, val + i, arg + i))) break;
        if (!closed) /* past the path's own run below the bound */
            while (i < nh && val[i] < bound) ++i;
        for (; i < end; ++i)
            if (val[i] < g) g = val[i], w = arg[i];
        if (closed) break;
    }
    if (open) free(val);
    if (rc || w == GS_NONE || (open && !(g < *len - shift))) return rc;
    return walk_via(c, qx, qy, reversed, w, len, out);
}

/* Step 4's question: does the exact corridor check the path best found
 * (length len, the database's distance d)? gap: how far apart the walks'
 * lengths are when they found two routes (0: one route). Each rule above,
 * the walk's shape read only when the cheaper ones did not decide. */
static int wants_corridor(const ctx *best, const gs_mesh *mesh, double len, double d, double gap, int point_end,
                          int exact_db)
{
    if (len > d * (1 + (exact_db ? CHECK_TOL_EXACT : CHECK_TOL_APPROX))) return 1;
    double size = corridor_size(mesh, len, d), longer = len / d - 1;
    if (gap > 0 && size <= (gap > ROUTE_GAP * len ? SMALL_CORRIDOR : CHEAP_CORRIDOR)) return 1;
    walk_shape w = shape_of(best);
    if (point_end && len > d * (1 + (exact_db ? REVERSE_TOL_EXACT : REVERSE_TOL_APPROX)) && w.mean >= POINT_DEFECT &&
        size <= POINT_CORRIDOR)
        return 1;
    int counted = w.n >= MIN_SHARE_WALK;
    if (counted && w.mean >= POINT_DEFECT && size <= ANISO_CORRIDOR &&
        longer > (point_end ? 0 : fmin(ANISO_LONGER, SADDLE_LONGER))) {
        double thin = walk_anisotropy(best);
        if (thin >= ANISO_SHARE && longer > (point_end ? 0 : ANISO_LONGER)) return 1;
        if (thin >= SADDLE_ANISO && w.saddles >= SADDLE_SHARE && longer > SADDLE_LONGER && size <= POINT_CORRIDOR)
            return 1;
    }
    if (w.mean >= POINT_DEFECT && size <= COARSE_WIDTH * (double)best->nvp) return 1; /* coarse */
    if ((size <= ROUGH_CORRIDOR || (size <= IRREGULAR_CORRIDOR && longer > NOISY_LONGER)) &&
        mesh_valence(best->t) >= IRREGULAR_MESH)
        return 1; /* irregular */
    int corridor_ok = size <= ROUGH_CORRIDOR && (len >= d || w.mean >= ROUGH_STRONG);
    if (w.mean >= ROUGH_DEFECT && w.big >= 0.5) return corridor_ok; /* rough */
    int mild = counted && corridor_ok && w.mean >= ROUGH_MILD && w.big >= ROUGH_MILD_SHARE;
    int noisy_ok = counted && longer > NOISY_LONGER && size <= NOISY_CORRIDOR;
    return (mild || noisy_ok) && walk_noise(best) >= ROUGH_NOISE;
}

int gs_db_path(const gs_db *db, const gs_mesh *mesh, const gs_source *x, const gs_source *y, gs_path **out,
               gs_error *err)
{
    if (out) *out = NULL;
    if (!db || !mesh || !x || !y || !out) return gs__fail(err, GS_EARG, "gs_db_path: NULL argument");
    if (mesh->nv != db->nv)
        return gs__fail(err, GS_EARG, "gs_db_path: the mesh is not the database's: it has %u vertices, the database %u",
                        mesh->nv, db->nv);
    const gs__topo *t = &mesh->topo;
    qpt qx, qy;
    int rc = end_point(t, x, "X", &qx, err);
    if (!rc) rc = end_point(t, y, "Y", &qy, err);
    if (rc) return rc;
    ctx c;
    memset(&c, 0, sizeof c);
    c.db = db, c.t = t, c.err = err;
    uint32_t cx[3], cy[3];
    int ncx = carriers(t, &qx, cx), ncy = carriers(t, &qy, cy);
    for (int k = 0; k < ncx && !rc; ++k) rc = check_vertex(&c, cx[k]);
    for (int k = 0; k < ncy && !rc; ++k) rc = check_vertex(&c, cy[k]);
    if (rc) return rc;
    if (same_q(&qx, &qy) || (qx.type == Q_VERTEX && qy.type == Q_VERTEX && qx.a == qy.a)) {
        c.nq = 0;
        rc = add_q(&c, qx, qx.type == Q_VERTEX ? (t->vc_start[qx.a] < t->vc_start[qx.a + 1]
                                                      ? t->vc[t->vc_start[qx.a]] / 3
                                                      : GS_NONE)
                                               : qx.f != GS_NONE ? qx.f : GS_NONE);
        if (!rc && c.q[0].seg == GS_NONE) { /* an isolated vertex: no face to name */
            rc = gs__fail(err, GS_EARG, "gs_db_path: vertex %u is used by no face", qx.a);
        }
        if (!rc) rc = make_path(&c, out);
        ctx_free(&c);
        return rc;
    }
    /* unreachable (another component, or a vertex of no face): empty path */
    int reach = 1;
    for (int k = 0; k < ncx; ++k) reach &= db->leaf[cx[k]] != GS_NONE;
    for (int k = 0; k < ncy; ++k) reach &= db->leaf[cy[k]] != GS_NONE;
    if (reach && !isfinite(gs_db_distance(db, cx[0], cy[0]))) reach = 0;
    if (!reach) {
        rc = gs__path_adopt(0, NULL, NULL, NULL, INFINITY, out, err);
        return rc;
    }
    gs_surface_point sx, sy;
    source_point(t, x, &sx);
    source_point(t, y, &sy);
    double d = gs_db_point_distance(db, &sx, &sy), len, len1 = INFINITY, len2 = INFINITY, len3 = INFINITY;
    int exact_db = db->method == GS_METHOD_EXACT, point_end = qx.type != Q_VERTEX || qy.type != Q_VERTEX;
    double reverse_tol = exact_db ? REVERSE_TOL_EXACT : REVERSE_TOL_APPROX;
    ctx c2, c3;
    memset(&c2, 0, sizeof c2);
    memset(&c3, 0, sizeof c3);
    c2.db = db, c2.t = t, c2.err = err;
    c3.db = db, c3.t = t, c3.err = err;
    ctx *best = &c;
    rc = run(&c, &qx, &qy, GS_NONE, GS_NONE, &len);
    /* longer than the database's distance: also from the other end */
    if (!rc && len > d * (1 + reverse_tol)) {
        c2.donor = &c;
        rc = run(&c2, &qy, &qx, GS_NONE, GS_NONE, &len2);
        len1 = len;
        if (!rc && len2 < len) best = &c2, len = len2, reverse_points(&c2);
    }
    /* a surface-point end and both walks on one route: a third walk, from
     * the corners the first did not start from and head for. The walks
     * run between corners: from a point a corner's width off the one
     * taken, the shortest path can pass the other side of a bump or a
     * thin tube (sphere-bumpy, torus-thin: paths 1-1.3% longer than the
     * exact distance, below 1% over the database's, which errs high) */
    if (!rc && isfinite(len2) && point_end && fabs(len1 - len2) <= ROUTE_GAP * len) {
        c3.donor = &c;
        rc = run(&c3, &qy, &qx, qy.type == Q_VERTEX ? GS_NONE : c.origin, qx.type == Q_VERTEX ? GS_NONE : c.target,
                 &len3);
        if (!rc && len3 < len) best = &c3, len = len3, reverse_points(&c3);
    }
    if (!rc) rc = make_path(best, out);
    /* longer than the database's distance and the shorter walk far off the
     * database's shortest path: walks round the other side (knot-fat: of
     * 5 vertex pairs in 2,000 over 1%, 2 found where the other walk was
     * the shorter) */
    if (!rc) rc = best == &c2 ? detour(&c2, mesh, &qy, &qx, 1, d, &len, out) : detour(&c, mesh, &qx, &qy, 0, d, &len, out);
    /* on a tube: round its other side too */
    if (!rc)
        rc = best == &c ? second_route(&c, &qx, &qy, 0, d, &len, out, 0) : second_route(best, &qy, &qx, 1, d, &len, out, 0);
    /* still much longer (or the walks found two routes and the corridor is
     * small): the exact path inside the corridor of shorter ones */
    double lo = fmin(fmin(len1, len2), len3), hi = fmax(len1, len2);
    if (isfinite(len3)) hi = fmax(hi, len3);
    int two_routes = isfinite(len2) && hi - lo > 1e-9 * len;
    if (!rc && wants_corridor(best, mesh, len, d, two_routes ? hi - lo : 0, point_end, exact_db)) {
        double px[3], py[3];
        q_position(t, &qx, px);
        q_position(t, &qy, py);
        double slack = best == &c ? dist3(px, vpos(best, best->target)) + dist3(py, vpos(best, best->origin))
                                  : dist3(py, vpos(best, best->target)) + dist3(px, vpos(best, best->origin));
        rc = corridor(best, mesh, x, y, len, d, slack, out);
    }
    if (rc) gs_path_free(*out), *out = NULL;
    ctx_free(&c3);
    ctx_free(&c2);
    ctx_free(&c);
    return rc;
}
