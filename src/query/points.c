/* points.c - distances between arbitrary surface points (a face's corners and
 * barycentric weights) from the database's vertex queries, by the planar
 * identity of the paper's sec. 4.2 (Rustamov et al. 2009) applied on both
 * sides. Uses only the public query functions and the stored positions. */
#include "../db/db_internal.h"
#include "../core/internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* A validated point: its n distinct corners of nonzero weight in increasing
 * id order, weights summing to 1. */
typedef struct spt {
    uint32_t n;
    uint32_t v[3];
    double w[3];
} spt;

/* Why a point is invalid (0: it is not), and which corner or weight. */
enum { PT_OK, PT_RANGE, PT_UNUSED, PT_NONFINITE, PT_NEGATIVE, PT_SUM };

gs_surface_point gs_surface_point_make(uint32_t v0, uint32_t v1, uint32_t v2, double w0, double w1, double w2)
{
    gs_surface_point p = {{v0, v1, v2}, {w0, w1, w2}};
    return p;
}

gs_surface_point gs_surface_point_vertex(uint32_t v)
{
    return gs_surface_point_make(v, v, v, 1.0, 0.0, 0.0);
}

int gs_surface_point_from_face(const gs_mesh *mesh, uint32_t face, double b0, double b1, double b2,
                               gs_surface_point *out, gs_error *err)
{
    if (!mesh || !out) return gs__fail(err, GS_EARG, "gs_surface_point_from_face: NULL argument");
    uint32_t nf = gs_mesh_num_faces(mesh);
    if (face >= nf) return gs__fail(err, GS_EARG, "face %u >= n_faces %u", face, nf);
    const uint32_t *t = gs_mesh_faces(mesh) + 3 * (size_t)face;
    *out = gs_surface_point_make(t[0], t[1], t[2], b0, b1, b2);
    return GS_OK;
}

const double *gs_db_positions(const gs_db *db)
{
    return db ? db->xyz : NULL;
}

static double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

static const double *pos(const gs_db *db, uint32_t v)
{
    return db->xyz + 3 * (size_t)v;
}

/* w[0] + w[1] + w[2] - 1 of the exact sum, whatever the order: each
 * addition's rounding error is kept (Knuth's two-sum) and s - 1 is exact
 * near 1 (Sterbenz). (Rounded, 0.5 + 0.5 + 1e-9 is 1 + 1.00000008e-9,
 * beyond a tolerance of 1e-9 that the exact sum meets.) NaN on overflow. */
static double sum_minus_one(const double *w)
{
    double s = 0.0, err = 0.0;
    for (int k = 0; k < 3; ++k) {
        double t = s + w[k], b = t - s;
        err += (s - (t - b)) + (w[k] - b);
        s = t;
    }
    return (s - 1.0) + err;
}

/* Validate p and bring it to its canonical form; *bad: the corner or
 * weight at fault. */
static int canonical(const gs_db *db, const gs_surface_point *p, spt *s, int *bad)
{
    for (int k = 0; k < 3; ++k) {
        *bad = k;
        if (p->corner[k] >= db->nv) return PT_RANGE;
        if (!isfinite(p->weight[k])) return PT_NONFINITE;
        if (p->weight[k] < GS_POINT_WEIGHT_MIN) return PT_NEGATIVE;
    }
    *bad = -1;
    if (!(fabs(sum_minus_one(p->weight)) <= GS_POINT_WEIGHT_SUM_TOL)) return PT_SUM;
    /* merge repeated corners, drop zero weights, sort by id (insertion) */
    s->n = 0;
    for (int k = 0; k < 3; ++k) {
        double w = p->weight[k] > 0.0 ? p->weight[k] : 0.0;
        if (w == 0.0) continue;
        uint32_t v = p->corner[k], i = 0;
        while (i < s->n && s->v[i] < v) ++i;
        if (i < s->n && s->v[i] == v) {
            s->w[i] += w;
            continue;
        }
        for (uint32_t j = s->n; j > i; --j) s->v[j] = s->v[j - 1], s->w[j] = s->w[j - 1];
        s->v[i] = v, s->w[i] = w, s->n++;
    }
    /* a vertex on its own may be unreferenced (it is then as gs_db_distance
     * answers it); corners of a face never are */
    for (uint32_t i = 0; s->n > 1 && i < s->n; ++i)
        if (db->leaf[s->v[i]] == GS_NONE) {
            for (int k = 0; k < 3; ++k)
                if (p->corner[k] == s->v[i]) *bad = k;
            return PT_UNUSED;
        }
    double total = 0.0; /* in id order: the corners' order does not matter */
    for (uint32_t i = 0; i < s->n; ++i) total += s->w[i];
    for (uint32_t i = 0; i < s->n; ++i) s->w[i] /= total;
    return PT_OK;
}

/* x with the fewest digits that read back as x: a value one ulp beyond a
 * bound does not print as the bound. buf: 32 bytes. */
static const char *shortest(double x, char *buf)
{
    for (int digits = 1; digits <= 17; ++digits) {
        snprintf(buf, 32, "%.*g", digits, x);
        if (strtod(buf, NULL) == x) break;
    }
    return buf;
}

static int explain(gs_error *err, const gs_db *db, const gs_surface_point *p, int why, int k, const char *where)
{
    char num[32];
    double off;
    switch (why) {
    case PT_RANGE:
        return gs__fail(err, GS_EARG, "%s: corner %d is vertex %u >= n_vertices %u", where, k, p->corner[k], db->nv);
    case PT_UNUSED:
        return gs__fail(err, GS_EARG, "%s: corner %d (vertex %u) is used by no face, so it is not a face's corner",
                        where, k, p->corner[k]);
    case PT_NONFINITE: return gs__fail(err, GS_EARG, "%s: weight %d is %g (must be finite)", where, k, p->weight[k]);
    case PT_NEGATIVE:
        return gs__fail(err, GS_EARG, "%s: weight %d is %s (must be >= %g)", where, k, shortest(p->weight[k], num),
                        GS_POINT_WEIGHT_MIN);
    case PT_SUM: /* near 1: how far off, else the sum */
        off = sum_minus_one(p->weight);
        if (fabs(off) < 1e-6)
            return gs__fail(err, GS_EARG, "%s: weights sum to 1 %c %s (must be 1 within %g)", where,
                            off < 0 ? '-' : '+', shortest(fabs(off), num), GS_POINT_WEIGHT_SUM_TOL);
        return gs__fail(err, GS_EARG, "%s: weights sum to %s (must be 1 within %g)", where,
                        shortest(p->weight[0] + p->weight[1] + p->weight[2], num), GS_POINT_WEIGHT_SUM_TOL);
    default: return GS_OK;
    }
}

int gs_db_point_check(const gs_db *db, const gs_surface_point *p, gs_error *err)
{
    if (!db || !p) return gs__fail(err, GS_EARG, "gs_db_point_check: NULL argument");
    spt s;
    int k, why = canonical(db, p, &s, &k);
    return explain(err, db, p, why, k, "surface point");
}

/* Vertex distances d(x, y) of m corner pairs (pairs[2k], pairs[2k + 1]) ->
 * out[k]: database queries, or lookups in precomputed fields. */
typedef void (*vdist_fn)(const void *ctx, const uint32_t *pairs, uint32_t m, double *out);

/* One batch (gs_db_distances answers as gs_db_distance, bit for bit, and
 * fetches the pairs' data from memory in parallel: the corners of a point
 * pair usually lie far from each other's, but close to their own). The
 * ids are valid (canonical() checked them). */
static void vdist_query(const void *ctx, const uint32_t *pairs, uint32_t m, double *out)
{
    gs_db_distances(ctx, pairs, m, out, NULL);
}

static int has(const spt *s, uint32_t v)
{
    for (uint32_t i = 0; i < s->n; ++i)
        if (s->v[i] == v) return 1;
    return 0;
}

/* Total order on canonical points: count, ids, weights. */
static int compare(const spt *a, const spt *b)
{
    if (a->n != b->n) return a->n < b->n ? -1 : 1;
    for (uint32_t i = 0; i < a->n; ++i)
        if (a->v[i] != b->v[i]) return a->v[i] < b->v[i] ? -1 : 1;
    for (uint32_t i = 0; i < a->n; ++i)
        if (a->w[i] != b->w[i]) return a->w[i] < b->w[i] ? -1 : 1;
    return 0;
}

/* |p - q|, from the corners' offsets to one of p's corners (not from
 * the points' positions: far from the origin, a position summed from its
 * corners loses the digits that tell nearby points apart). */
static double gap(const gs_db *db, const spt *a, const spt *b)
{
    const double *r = pos(db, a->v[0]);
    double d[3] = {0.0, 0.0, 0.0};
    for (uint32_t i = 0; i < a->n; ++i)
        for (int c = 0; c < 3; ++c) d[c] += a->w[i] * (pos(db, a->v[i])[c] - r[c]);
    for (uint32_t j = 0; j < b->n; ++j)
        for (int c = 0; c < 3; ++c) d[c] -= b->w[j] * (pos(db, b->v[j])[c] - r[c]);
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* A point's own geometry, computed once per query: the offsets to its
 * corners, its edge term, and (on first use, for targets near the face)
 * per edge of its face (n == 3) the point and the third corner in a frame
 * where the edge runs from (0,0) to (L,0). */
typedef struct frame {
    const gs_db *db;
    double gap[3]; /* |p - v_i| (straight: inside the face)              */
    double edge;   /* sum_{i<k} w_i w_k |v_i - v_k|^2                    */
    double near;   /* targets nearer than this to a corner are unfolded   */
    int unfold;    /* -1: not yet made; 0: none (an edge point, a degenerate face); 1: below */
    int chords;    /* the corners' distances are straight chords that fold:  */
                   /*   an unfolding is taken over the identity (estimate)   */
    double L[3], xm[3], ym[3], px[3], py[3]; /* edge (i, i+1), third corner i+2 */
} frame;

/* Beyond GS__UNFOLD_NEAR times the face's longest edge from its corners,
 * the unfolding across an edge and the planar identity agree to well
 * within the vertex queries' error (they differ where the geodesics from
 * the three corners part around a vertex next to the face). */
#define GS__UNFOLD_NEAR 4.0
/* The lower bound d_i - |p - v_i| is taken 0.5% short: next to a corner
 * (|p - v_i| small) it is as tight as d_i, so the vertex query's own error
 * would otherwise pass straight into the answer on flat meshes, where the
 * identity averages it out. */
#define GS__LOWER_SLACK 0.995

static void make_frame(const gs_db *db, const spt *s, frame *f)
{
    f->db = db, f->edge = 0.0, f->unfold = s->n == 3 ? -1 : 0, f->chords = 0;
    double e2max = 0.0;
    for (uint32_t k = 0; k < s->n; ++k) { /* from the other corners' offsets to v_k */
        const double *r = pos(db, s->v[k]);
        double d[3] = {0.0, 0.0, 0.0};
        for (uint32_t i = 0; i < s->n; ++i)
            if (i != k)
                for (int c = 0; c < 3; ++c) d[c] += s->w[i] * (pos(db, s->v[i])[c] - r[c]);
        f->gap[k] = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (uint32_t i = k + 1; i < s->n; ++i) {
            double e2 = dist2(r, pos(db, s->v[i]));
            f->edge += s->w[k] * s->w[i] * e2;
            if (e2 > e2max) e2max = e2;
        }
    }
    f->near = GS__UNFOLD_NEAR * sqrt(e2max);
}

static void make_unfold(const spt *s, frame *f)
{
    f->unfold = 0;
    for (uint32_t i = 0; i < 3; ++i) {
        uint32_t k = (i + 1) % 3, m = (i + 2) % 3;
        const double *vi = pos(f->db, s->v[i]), *vk = pos(f->db, s->v[k]), *vm = pos(f->db, s->v[m]);
        double ek[3], em[3];
        for (int c = 0; c < 3; ++c) ek[c] = vk[c] - vi[c], em[c] = vm[c] - vi[c];
        double L = sqrt(ek[0] * ek[0] + ek[1] * ek[1] + ek[2] * ek[2]);
        double xm = (em[0] * ek[0] + em[1] * ek[1] + em[2] * ek[2]) / L;
        double ym2 = em[0] * em[0] + em[1] * em[1] + em[2] * em[2] - xm * xm;
        if (!(L > 0.0) || !(ym2 > 0.0)) return; /* a degenerate face: no unfolding */
        f->L[i] = L, f->xm[i] = xm, f->ym[i] = sqrt(ym2);
        f->px[i] = s->w[k] * L + s->w[m] * xm, f->py[i] = s->w[m] * f->ym[i];
    }
    f->unfold = 1;
}

/* d(p, y) for the point p = s (frame f) from its corners' distances
 * dist[i] to y: the planar identity (sum_i w_i dist_i^2 - the edge term),
 * or the shorter unfolding across an edge (v_i, v_k) of the face (y placed
 * in the face's plane beyond the edge at distances dist_i, dist_k, where
 * the segment from it to p crosses the edge: the identity also uses the
 * third corner, whose own geodesic may bend around a vertex); then within
 * the triangle inequality through each corner:
 * dist_i - |p - v_i| <= d(p, y) <= dist_i + |p - v_i| (the lower bound
 * taken GS__LOWER_SLACK short; the identity
 * misses the upper bound where geodesics bend around a saddle vertex, the
 * lower where the face straddles y's cut locus). With f->chords (every
 * corner distance a straight chord, the corners not in one plane) the
 * identity is the chord |p - y| through the solid, and an unfolding, the
 * folded path, is taken wherever there is one (a point on a cube's or a
 * tetrahedron's face and a vertex of the next face: 45% short before). */
static double one_sided(const spt *s, frame *f, const double *dist)
{
    if (s->n == 1) return dist[0];
    double t = -f->edge, lo = 0.0, hi = INFINITY, dmin = INFINITY;
    for (uint32_t i = 0; i < s->n; ++i) {
        t += s->w[i] * dist[i] * dist[i];
        if (dist[i] + f->gap[i] < hi) hi = dist[i] + f->gap[i];
        if (GS__LOWER_SLACK * (dist[i] - f->gap[i]) > lo) lo = GS__LOWER_SLACK * (dist[i] - f->gap[i]);
        if (dist[i] < dmin) dmin = dist[i];
    }
    double r = t > 0.0 ? sqrt(t) : 0.0, u = INFINITY;
    if (f->unfold < 0 && dmin < f->near) make_unfold(s, f);
    for (uint32_t i = 0; f->unfold > 0 && dmin < f->near && i < 3; ++i) {
        uint32_t k = (i + 1) % 3;
        double L = f->L[i], px = f->px[i], py = f->py[i];
        double yx = (dist[i] * dist[i] - dist[k] * dist[k] + L * L) / (2.0 * L), h2 = dist[i] * dist[i] - yx * yx;
        if (!(h2 > 0.0)) continue;
        double h = sqrt(h2), xc = px + py / (py + h) * (yx - px);
        if (!(xc >= 0.0 && xc <= L)) continue;
        double c = sqrt((px - yx) * (px - yx) + (py + h) * (py + h));
        if (c < u) u = c;
    }
    if (u < r || (f->chords && u < INFINITY)) r = u;
    if (r > hi) r = hi;
    return r > lo ? r : lo;
}

/* Whether the corners of a and b (at most 6 points) lie in one plane, to
 * GS__PLANE_TOL of their largest spread: then corner distances that are
 * all straight make |p - q| the answer (p and q in one face, or in faces
 * of one flat region). Not so where they fold: on a tetrahedron every
 * corner pair is an edge, yet a point and the opposite vertex are a folded
 * path apart, not the chord through the solid (which the identity gives
 * for straight corner distances: it is exact in space). */
#define GS__PLANE_TOL 1e-9
static int coplanar(const gs_db *db, const spt *a, const spt *b)
{
    const double *P[6];
    uint32_t n = 0;
    for (uint32_t i = 0; i < a->n; ++i) P[n++] = pos(db, a->v[i]);
    for (uint32_t j = 0; j < b->n; ++j)
        if (!has(a, b->v[j])) P[n++] = pos(db, b->v[j]);
    if (n <= 3) return 1;
    /* the plane through P[0] and the pair of offsets with the largest normal */
    double best = 0.0, nrm[3] = {0.0, 0.0, 0.0}, span2 = 0.0;
    for (uint32_t i = 1; i < n; ++i) {
        double u[3];
        for (int c = 0; c < 3; ++c) u[c] = P[i][c] - P[0][c];
        double u2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        if (u2 > span2) span2 = u2;
        for (uint32_t k = i + 1; k < n; ++k) {
            double w[3], x[3];
            for (int c = 0; c < 3; ++c) w[c] = P[k][c] - P[0][c];
            x[0] = u[1] * w[2] - u[2] * w[1], x[1] = u[2] * w[0] - u[0] * w[2], x[2] = u[0] * w[1] - u[1] * w[0];
            double x2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
            if (x2 > best) best = x2, nrm[0] = x[0], nrm[1] = x[1], nrm[2] = x[2];
        }
    }
    if (!(best > 0.0)) return 1; /* collinear */
    double len = sqrt(best), tol = GS__PLANE_TOL * sqrt(span2);
    for (uint32_t i = 1; i < n; ++i) {
        double h = 0.0;
        for (int c = 0; c < 3; ++c) h += nrm[c] * (P[i][c] - P[0][c]);
        if (fabs(h) / len > tol) return 0;
    }
    return 1;
}

/* The estimate for a <= b (compare order), a != b. */
static double estimate(const gs_db *db, const spt *a, const spt *b, vdist_fn vd, const void *ctx)
{
    /* the corner pairs that are not an edge of either face go to the
     * database, in one batch; q[i][j]: pair (i, j)'s place in it, -1 for an
     * edge (its straight length) */
    uint32_t pairs[18], m = 0;
    int q[3][3];
    double d[9];
    for (uint32_t i = 0; i < a->n; ++i)
        for (uint32_t j = 0; j < b->n; ++j) {
            q[i][j] = has(a, b->v[j]) || has(b, a->v[i]) ? -1 : (int)m;
            if (q[i][j] >= 0) pairs[2 * m] = a->v[i], pairs[2 * m + 1] = b->v[j], m++;
        }
    if (m) vd(ctx, pairs, m, d);
    if (a->n == 1 && b->n == 1) return d[0]; /* two vertices: the vertex query itself */
    for (uint32_t k = 0; k < m; ++k)
        if (d[k] == INFINITY) return INFINITY;
    /* D[i][j]: corner pair (i, j)'s distance, an edge's straight length or
     * the database's */
    double D[3][3];
    int straight = 1;
    for (uint32_t i = 0; i < a->n; ++i)
        for (uint32_t j = 0; j < b->n; ++j) {
            D[i][j] = sqrt(dist2(pos(db, a->v[i]), pos(db, b->v[j])));
            if (q[i][j] >= 0) {
                straight &= d[q[i][j]] <= D[i][j];
                D[i][j] = d[q[i][j]];
            }
        }
    double e = gap(db, a, b);
    int chords = straight && !coplanar(db, a, b);
    if (straight && !chords) return e;
    frame fa, fb;
    make_frame(db, a, &fa);
    fa.chords = chords;
    double r;
    if (b->n == 1) { /* a point and a vertex */
        double col[3] = {D[0][0], a->n > 1 ? D[1][0] : 0.0, a->n > 2 ? D[2][0] : 0.0};
        r = one_sided(a, &fa, col);
    } else { /* both sides: d(p, q) from d(p, w_j), and from d(v_i, q) */
        make_frame(db, b, &fb);
        fb.chords = chords;
        double P[3], Q[3], col[3];
        for (uint32_t j = 0; j < b->n; ++j) {
            for (uint32_t i = 0; i < a->n; ++i) col[i] = D[i][j];
            P[j] = one_sided(a, &fa, col);
        }
        for (uint32_t i = 0; i < a->n; ++i) Q[i] = one_sided(b, &fb, D[i]);
        r = 0.5 * (one_sided(b, &fb, P) + one_sided(a, &fa, Q));
    }
    return r < e ? e : r;
}

static double ordered(const gs_db *db, const spt *p, const spt *q, vdist_fn vd, const void *ctx)
{
    int c = compare(p, q);
    if (c == 0) return 0.0;
    return c < 0 ? estimate(db, p, q, vd, ctx) : estimate(db, q, p, vd, ctx);
}

double gs_db_point_distance(const gs_db *db, const gs_surface_point *p, const gs_surface_point *q)
{
    if (!db || !p || !q) return NAN;
    spt a, b;
    int k;
    if (canonical(db, p, &a, &k) || canonical(db, q, &b, &k)) return NAN;
    return ordered(db, &a, &b, vdist_query, db);
}

int gs_db_point_distances(const gs_db *db, const gs_surface_point *pairs, size_t n, double *out, gs_error *err)
{
    if (!db || (n && (!pairs || !out))) return gs__fail(err, GS_EARG, "gs_db_point_distances: NULL argument");
    size_t bad = SIZE_MAX;
    int bad_why = PT_OK, bad_k = -1;
    for (size_t i = 0; i < n; ++i) {
        spt a, b;
        int ka, kb, wa = canonical(db, &pairs[2 * i], &a, &ka), wb = wa ? PT_OK : canonical(db, &pairs[2 * i + 1], &b, &kb);
        if (wa || wb) {
            out[i] = NAN;
            if (bad == SIZE_MAX) bad = 2 * i + (wa ? 0 : 1), bad_why = wa ? wa : wb, bad_k = wa ? ka : kb;
            continue;
        }
        out[i] = ordered(db, &a, &b, vdist_query, db);
    }
    if (bad == SIZE_MAX) return GS_OK;
    char where[96];
    snprintf(where, sizeof where, "gs_db_point_distances: pair %zu, point %d", bad / 2, (int)(bad % 2));
    return explain(err, db, &pairs[bad], bad_why, bad_k, where);
}

/* ---- fields ---- */

typedef struct field_ctx {
    const spt *p;
    const double *f[3]; /* the fields of p's corners */
} field_ctx;

/* In each pair one of x, y is a corner of p (the other is the field's
 * vertex). */
static void vdist_field(const void *ctx, const uint32_t *pairs, uint32_t m, double *out)
{
    const field_ctx *c = ctx;
    for (uint32_t k = 0; k < m; ++k) {
        uint32_t x = pairs[2 * k], y = pairs[2 * k + 1];
        out[k] = NAN; /* not reached */
        for (uint32_t i = 0; i < c->p->n; ++i) {
            if (c->p->v[i] == x) {
                out[k] = c->f[i][y];
                break;
            }
            if (c->p->v[i] == y) {
                out[k] = c->f[i][x];
                break;
            }
        }
    }
}

int gs_db_point_field(const gs_db *db, const gs_surface_point *p, double *out, gs_error *err)
{
    if (!db || !p || !out) return gs__fail(err, GS_EARG, "gs_db_point_field: NULL argument");
    spt a;
    int k, why = canonical(db, p, &a, &k);
    if (why) return explain(err, db, p, why, k, "gs_db_point_field");
    if (a.n == 1) return gs_db_field(db, a.v[0], out, err); /* a vertex */
    double *work = gs__malloc((size_t)(a.n - 1) * db->nv, sizeof *work);
    if (!work) return gs__fail(err, GS_ENOMEM, "gs_db_point_field: out of memory (%u fields)", a.n - 1);
    field_ctx c = {&a, {out, work, work + db->nv}};
    int rc = GS_OK;
    for (uint32_t i = 0; i < a.n && !rc; ++i) rc = gs_db_field(db, a.v[i], (double *)c.f[i], err);
    for (uint32_t y = 0; y < db->nv && !rc; ++y) { /* out[y] is read (f[0][y]) before it is written */
        spt b = {1, {y, 0, 0}, {1.0, 0, 0}}; /* as canonical() makes vertex y */
        out[y] = ordered(db, &a, &b, vdist_field, &c);
    }
    free(work);
    return rc;
}
