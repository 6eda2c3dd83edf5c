/* path.c - exact geodesic paths: backtracking through what the exact solver
 * (exact.c) recorded for every vertex, the last straight piece of its
 * shortest path (gs__exact_trace).
 *
 * From a vertex v the record says where that piece starts: a neighbour along
 * an edge, the point source of v's own face, or the unfolded position S of a
 * window's source (a pseudo-source vertex or a point source) in the frame of
 * an edge of a face at v. The straight segment v -> S is walked through the
 * strip of faces it crosses, deciding every step by the side of the line
 * v -> S the next face's third vertex lies on (a fixed line: the walk cannot
 * wobble; the faces are unfolded with each entry edge's direction carried
 * by rotations). It ends where it meets a vertex (within 1e-9 of the face's
 * smallest height: S itself when the window came from a vertex, or a vertex
 * the line passes through), and the backtrack continues from that vertex's own record
 * (its distance is the rest of the path's length: it lies on a shortest
 * path), or in the face of the point source, where it ends.
 *
 * A surface-point target is reached from the best of: the window entering
 * its face that reaches it first (exact.c finds it during the solve), a
 * corner of its face, the point source in the same face. */
#include "geodesic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* a vertex closer than this many of its face's smallest heights to the
 * line is on it (and at least ON_LINE_ROUND times the line's length: what
 * rounding leaves of an exact hit) */
#define ON_LINE_REL 1e-9
#define ON_LINE_ROUND 1e-14

struct gs_path {
    uint32_t n;
    double length;
    double *xyz;
    uint32_t *face;
    double *bary;
};

uint32_t gs_path_num_points(const gs_path *p) { return p ? p->n : 0; }
double gs_path_length(const gs_path *p) { return p ? p->length : INFINITY; }
const double *gs_path_xyz(const gs_path *p) { return p && p->n ? p->xyz : NULL; }
const uint32_t *gs_path_faces(const gs_path *p) { return p && p->n ? p->face : NULL; }
const double *gs_path_bary(const gs_path *p) { return p && p->n ? p->bary : NULL; }

void gs_path_free(gs_path *p)
{
    if (!p) return;
    free(p->xyz);
    free(p->face);
    free(p->bary);
    free(p);
}

/* A path from its arrays (db_path.c): takes ownership of xyz, face and bary
 * (malloc'ed; freed on failure too). */
int gs__path_adopt(uint32_t n, double *xyz, uint32_t *face, double *bary, double length, gs_path **out,
                   gs_error *err)
{
    gs_path *p = gs__calloc(1, sizeof *p);
    if (!p) {
        free(xyz), free(face), free(bary);
        return gs__fail(err, GS_ENOMEM, "out of memory building a path");
    }
    p->n = n, p->xyz = xyz, p->face = face, p->bary = bary, p->length = length;
    *out = p;
    return GS_OK;
}

/* ---- points of a trace ---------------------------------------------------- */

enum { PT_VERTEX, PT_EDGE, PT_FACE };

typedef struct pt {
    int type;
    uint32_t a, b;   /* vertex; edge a -> b; face a */
    double t;        /* PT_EDGE: (1 - t) a + t b */
    double bary[3];  /* PT_FACE */
    uint32_t seg;    /* face holding the segment to the next point */
} pt;

typedef struct tracer {
    const gs__topo *t;
    const gs__exact_trace *tr;
    pt *p;
    size_t n, cap;
    uint64_t steps, max_steps;
    gs_error *err;
} tracer;

static int same_point(const pt *x, const pt *y)
{
    if (x->type != y->type) return 0;
    if (x->type == PT_VERTEX) return x->a == y->a;
    if (x->type == PT_EDGE) return (x->a == y->a && x->b == y->b && x->t == y->t);
    return x->a == y->a && !memcmp(x->bary, y->bary, sizeof x->bary);
}

/* Append point q, reached from the last point by a segment inside face g. */
static int add(tracer *c, pt q, uint32_t g)
{
    if (q.type == PT_EDGE) {
        if (q.t <= 0) q = (pt){PT_VERTEX, q.a, GS_NONE, 0, {0, 0, 0}, GS_NONE};
        else if (q.t >= 1) q = (pt){PT_VERTEX, q.b, GS_NONE, 0, {0, 0, 0}, GS_NONE};
    }
    if (c->n && same_point(&c->p[c->n - 1], &q)) return GS_OK;
    if (c->n == c->cap) {
        size_t nc = c->cap ? 2 * c->cap : 64;
        pt *np = gs__realloc(c->p, nc, sizeof *np);
        if (!np) return gs__fail(c->err, GS_ENOMEM, "out of memory tracing a path");
        c->p = np;
        c->cap = nc;
    }
    if (c->n) c->p[c->n - 1].seg = g;
    q.seg = g;
    c->p[c->n++] = q;
    return GS_OK;
}

static int add_vertex(tracer *c, uint32_t v, uint32_t g)
{
    return add(c, (pt){PT_VERTEX, v, GS_NONE, 0, {0, 0, 0}, GS_NONE}, g);
}

static int add_source_point(tracer *c, const gs_source *s)
{
    pt q = {PT_FACE, s->face, GS_NONE, 0, {s->bary[0], s->bary[1], s->bary[2]}, GS_NONE};
    return add(c, q, s->face);
}

/* ---- walking a straight segment ------------------------------------------ */

typedef struct v2 {
    double x, y;
} v2;

typedef struct line {
    v2 q0, d; /* start, unit direction towards S */
    double len;
} line;

static double side(const line *l, v2 p) { return l->d.x * (p.y - l->q0.y) - l->d.y * (p.x - l->q0.x); }

static double face_size(const gs__topo *t, uint32_t g)
{
    double a = t->len[3 * g], b = t->len[3 * g + 1], e = t->len[3 * g + 2];
    return fmax(a, fmax(b, e));
}

/* How near the line l a vertex of face g is on it: a share of the face's
 * smallest height, not of its longest edge, which on a needle (a graded
 * mesh's cells 1e-11 wide and 0.1 long) is wider than the face, so that
 * the walk took a vertex far along it for one on the line. */
static double line_tol(const gs__topo *t, uint32_t g, const line *l)
{
    uint32_t h = 3 * g;
    double area2 = t->len[h] * t->len[gs__prev(h)] * sin(t->angle[h]);
    return fmax(ON_LINE_REL * area2 / face_size(t, g), ON_LINE_ROUND * l->len);
}

/* Is S (unfolded) inside the face with corners P[0..2] (counter-clockwise)? */
static int inside(const v2 *P, v2 S, double tol)
{
    for (int i = 0; i < 3; ++i) {
        v2 a = P[i], b = P[(i + 1) % 3];
        double ex = b.x - a.x, ey = b.y - a.y, n = hypot(ex, ey);
        if (ex * (S.y - a.y) - ey * (S.x - a.x) < -tol * n) return 0;
    }
    return 1;
}

/* Walk the segment from q0 (a point of face h/3 in the frame of half-edge h,
 * the face on its y > 0 side) to S (sy <= 0, beyond h), the unfolded
 * position of a vertex (tag GS_NONE) or of point source src[tag]. On
 * return *next is the vertex the walk ended at (already appended), or
 * GS_NONE when it reached the point source (appended too). */
static int walk(tracer *c, v2 q0, uint32_t h, v2 S, uint32_t tag, uint32_t *next)
{
    const gs__topo *t = c->t;
    const gs_source *ps = tag != GS_NONE ? &c->tr->src[tag] : NULL;
    line l;
    l.q0 = q0;
    l.d.x = S.x - q0.x;
    l.d.y = S.y - q0.y;
    l.len = hypot(l.d.x, l.d.y);
    *next = GS_NONE;
    if (!(l.len > 0) || !isfinite(l.len))
        return gs__fail(c->err, GS_EINTERNAL, "path: degenerate window record at half-edge %u", h);
    l.d.x /= l.len;
    l.d.y /= l.len;
    uint32_t g = h / 3;
    double tol = line_tol(t, g, &l);
    uint32_t e = h;
    v2 PA = {0, 0}, PB = {t->len[h], 0};
    /* the unit direction PB -> PA of the entry edge, carried from face to
     * face by rotations through the corner angles: taken from PA - PB
     * instead, an edge 1e-11 long at coordinates ~0.1 (a graded mesh's
     * needles) would point 1e-6 rad off, and its far corner lie off the
     * line by more than the needle is wide */
    double ux = -1.0, uy = 0.0;
    double oA = side(&l, PA), oB = side(&l, PB);
    /* the first edge: the line may run through one of its ends */
    if (fabs(oA) <= tol || fabs(oB) <= tol || (oA > 0) == (oB > 0)) {
        uint32_t v = fabs(oA) <= fabs(oB) ? t->tri[e] : t->tri[gs__next(e)];
        *next = v;
        return add_vertex(c, v, g);
    }
    for (;;) {
        if (++c->steps > c->max_steps)
            return gs__fail(c->err, GS_EINTERNAL, "path: the walk did not end (lost at face %u)", g);
        uint32_t tw = t->opp[e];
        if (tw == GS_NONE) { /* rounding ran it into the boundary next to a vertex */
            uint32_t v = fabs(oA) <= fabs(oB) ? t->tri[e] : t->tri[gs__next(e)];
            *next = v;
            return add_vertex(c, v, g);
        }
        double tt = oA / (oA - oB);
        pt x = {PT_EDGE, t->tri[e], t->tri[gs__next(e)], tt, {0, 0, 0}, GS_NONE};
        int rc = add(c, x, g);
        if (rc) return rc;
        v2 X = {PA.x + tt * (PB.x - PA.x), PA.y + tt * (PB.y - PA.y)};
        double along = (X.x - l.q0.x) * l.d.x + (X.y - l.q0.y) * l.d.y;
        if (along > l.len * (1 + 1e-9) + tol)
            return gs__fail(c->err, GS_EINTERNAL, "path: the walk passed its end (at face %u)", g);
        /* into the twin's face: tri[tw] is PB, tri[next(tw)] is PA */
        g = tw / 3;
        tol = line_tol(t, g, &l);
        double lc = t->len[gs__prev(tw)], ca = cos(t->angle[tw]), sa = sin(t->angle[tw]);
        double bx = ca * ux - sa * uy, by = ca * uy + sa * ux; /* PB -> PC */
        v2 PC = {PB.x + lc * bx, PB.y + lc * by};
        if (ps && g == ps->face) {
            v2 P[3];
            P[tw % 3] = PB;
            P[(tw + 1) % 3] = PA;
            P[(tw + 2) % 3] = PC;
            if (inside(P, S, 1e-7 * face_size(t, g))) {
                *next = GS_NONE;
                return add_source_point(c, ps);
            }
        }
        double oC = side(&l, PC);
        if (fabs(oC) <= tol) {
            uint32_t v = t->tri[gs__prev(tw)];
            *next = v;
            return add_vertex(c, v, g);
        }
        /* new entry edge: A' = PB (oB), B' = PA (oA) */
        if ((oC > 0) == (oB > 0)) { /* C with A': leave by B' -> C */
            e = gs__next(tw);
            /* PC -> PA: PB -> PA turned by minus the angle at PA */
            double aa = t->angle[gs__next(tw)], c2 = cos(aa), s2 = sin(aa), nx = c2 * ux + s2 * uy;
            uy = c2 * uy - s2 * ux, ux = nx;
            PB = PC, oB = oC;
        } else { /* leave by C -> A' */
            e = gs__prev(tw);
            /* PB -> PC */
            ux = bx, uy = by;
            PA = PC, oA = oC;
        }
    }
}

/* Backtrack from vertex v (already appended) to a source. */
static int from_vertex(tracer *c, uint32_t v)
{
    const gs__topo *t = c->t;
    const gs__exact_trace *tr = c->tr;
    for (uint64_t guard = 0;; ++guard) {
        if (guard > (uint64_t)t->nv + 8)
            return gs__fail(c->err, GS_EINTERNAL, "path: the backtrack did not end (at vertex %u)", v);
        int rc;
        switch (tr->kind[v]) {
        case GS_EXTR_NONE:
            if (tr->dist[v] == 0) return GS_OK;
            return gs__fail(c->err, GS_EINTERNAL, "path: vertex %u has no record", v);
        case GS_EXTR_EDGE: {
            uint32_t cn = tr->ref[v], u = t->tri[cn];
            rc = add_vertex(c, u, cn / 3);
            if (rc) return rc;
            v = u;
            break;
        }
        case GS_EXTR_POINT: return add_source_point(c, &tr->src[tr->ref[v]]);
        case GS_EXTR_WINDOW: {
            uint32_t h = tr->ref[v], hp = gs__prev(h), nx;
            double lac = t->len[hp];
            v2 q0 = {lac * cos(t->angle[h]), lac * sin(t->angle[h])};
            v2 S = {tr->sxy[2 * (size_t)v], tr->sxy[2 * (size_t)v + 1]};
            rc = walk(c, q0, h, S, tr->tag[v], &nx);
            if (rc) return rc;
            if (nx == GS_NONE) return GS_OK;
            v = nx;
            break;
        }
        default: return gs__fail(c->err, GS_EINTERNAL, "path: bad record at vertex %u", v);
        }
    }
}

/* ---- the result ----------------------------------------------------------- */

static void position(const gs__topo *t, const pt *q, double out[3])
{
    const double *x = t->xyz;
    if (q->type == PT_VERTEX) {
        memcpy(out, x + 3 * (size_t)q->a, 3 * sizeof(double));
    } else if (q->type == PT_EDGE) {
        for (int k = 0; k < 3; ++k)
            out[k] = (1 - q->t) * x[3 * (size_t)q->a + k] + q->t * x[3 * (size_t)q->b + k];
    } else {
        gs__face_point(t, q->a, q->bary, out);
    }
}

static int bary_in(const gs__topo *t, const pt *q, uint32_t g, double b[3])
{
    const uint32_t *c = t->tri + 3 * (size_t)g;
    b[0] = b[1] = b[2] = 0;
    if (q->type == PT_FACE) {
        if (q->a != g) return -1;
        memcpy(b, q->bary, 3 * sizeof(double));
        return 0;
    }
    int ia = -1, ib = -1;
    for (int k = 0; k < 3; ++k) {
        if (c[k] == q->a) ia = k;
        if (q->type == PT_EDGE && c[k] == q->b) ib = k;
    }
    if (ia < 0 || (q->type == PT_EDGE && ib < 0)) return -1;
    if (q->type == PT_VERTEX) {
        b[ia] = 1;
    } else {
        b[ia] = 1 - q->t;
        b[ib] = q->t;
    }
    return 0;
}

/* The trace runs target -> source; the path is its reverse, each point with
 * the face of the segment that leaves it (the last: that of the one that
 * arrives). */
static int finish(tracer *c, gs_path **out)
{
    const gs__topo *t = c->t;
    gs_path *p = gs__calloc(1, sizeof *p);
    size_t n = c->n;
    if (p && n) {
        p->xyz = gs__malloc(3 * n, sizeof *p->xyz);
        p->bary = gs__malloc(3 * n, sizeof *p->bary);
        p->face = gs__malloc(n, sizeof *p->face);
    }
    if (!p || (n && (!p->xyz || !p->bary || !p->face))) {
        gs_path_free(p);
        return gs__fail(c->err, GS_ENOMEM, "out of memory building a path");
    }
    p->n = (uint32_t)n;
    p->length = n ? 0 : INFINITY;
    for (size_t i = 0; i < n; ++i) {
        const pt *q = &c->p[n - 1 - i];
        uint32_t g;
        if (n == 1) {
            g = q->type == PT_FACE ? q->a : t->vc[t->vc_start[q->a]] / 3;
        } else {
            g = i + 1 < n ? c->p[n - 2 - i].seg : c->p[0].seg;
        }
        p->face[i] = g;
        if (bary_in(t, q, g, p->bary + 3 * i)) {
            gs_path_free(p);
            return gs__fail(c->err, GS_EINTERNAL, "path: point %zu is not in face %u", i, g);
        }
        position(t, q, p->xyz + 3 * i);
        if (i) {
            const double *a = p->xyz + 3 * (i - 1), *b = p->xyz + 3 * i;
            p->length += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                              (a[2] - b[2]) * (a[2] - b[2]));
        }
    }
    *out = p;
    return GS_OK;
}

/* ---- entry points (solver.c hands over the exact state) ------------------- */

int gs__exact_trace_path(const gs__topo *t, const gs__exact_trace *tr, const gs_source *target, gs_path **out,
                         gs_error *err)
{
    tracer c = {t, tr, NULL, 0, 0, 0, 8 * (uint64_t)t->nf + 1024, err};
    int rc = GS_OK;
    if (target->face == GS_NONE) {
        uint32_t v = target->vertex;
        if (tr->dist[v] < INFINITY) {
            rc = add_vertex(&c, v, GS_NONE);
            if (!rc) rc = from_vertex(&c, v);
        }
    } else {
        /* the best way into the target's face */
        uint32_t ft = target->face;
        pt q = {PT_FACE, ft, GS_NONE, 0, {target->bary[0], target->bary[1], target->bary[2]}, GS_NONE};
        double pq[3];
        position(t, &q, pq);
        double best = INFINITY;
        int how = -1; /* 0..2 corner, 3 window, 4 + i point source i */
        for (int k = 0; k < 3; ++k) {
            uint32_t v = t->tri[3 * (size_t)ft + k];
            const double *x = t->xyz + 3 * (size_t)v;
            double d = tr->dist[v] + sqrt((x[0] - pq[0]) * (x[0] - pq[0]) + (x[1] - pq[1]) * (x[1] - pq[1]) +
                                          (x[2] - pq[2]) * (x[2] - pq[2]));
            if (d < best) best = d, how = k;
        }
        if (tr->target.face == ft && !memcmp(tr->target.bary, target->bary, sizeof target->bary) &&
            tr->target.dist < best)
            best = tr->target.dist, how = 3;
        for (uint32_t i = 0; i < tr->n_src; ++i)
            if (tr->src[i].face == ft) {
                pt s = {PT_FACE, ft, GS_NONE, 0, {tr->src[i].bary[0], tr->src[i].bary[1], tr->src[i].bary[2]},
                        GS_NONE};
                double ps[3];
                position(t, &s, ps);
                double d = sqrt((ps[0] - pq[0]) * (ps[0] - pq[0]) + (ps[1] - pq[1]) * (ps[1] - pq[1]) +
                                (ps[2] - pq[2]) * (ps[2] - pq[2]));
                if (d <= best) best = d, how = 4 + (int)i;
            }
        if (best < INFINITY) {
            rc = add(&c, q, ft);
            if (rc) {
            } else if (how < 3) {
                uint32_t v = t->tri[3 * (size_t)ft + how];
                rc = add_vertex(&c, v, ft);
                if (!rc) rc = from_vertex(&c, v);
            } else if (how == 3) {
                uint32_t h = tr->target.h, i = h % 3, nx;
                double len = t->len[h], lac = t->len[gs__prev(h)];
                double w1 = target->bary[(i + 1) % 3], w2 = target->bary[(i + 2) % 3];
                v2 q0 = {w1 * len + w2 * lac * cos(t->angle[h]), w2 * lac * sin(t->angle[h])};
                v2 S = {tr->target.sx, tr->target.sy};
                rc = walk(&c, q0, h, S, tr->target.tag, &nx);
                if (!rc && nx != GS_NONE) rc = from_vertex(&c, nx);
            } else {
                rc = add_source_point(&c, &tr->src[how - 4]);
            }
        }
    }
    if (!rc) rc = finish(&c, out);
    free(c.p);
    return rc;
}
