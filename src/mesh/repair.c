/* repair.c - gs_mesh_repair: a flawed triangle soup made into a valid mesh,
 * knowingly (doc/repair.md). One file (about 1,100 lines) on purpose: the
 * stages share one working state (union-find of welded vertices, the face
 * list, the report being filled) and read as one pipeline; split, each part
 * would export that state. The stages, in order:
 *   1. faces naming a vertex twice are dropped; duplicate faces too;
 *   2. zero-area faces (rounds): corners at one position are welded (the
 *      face and its neighbours across the collapsed edge vanish); collinear
 *      faces vanish by splitting the face across their longest edge at
 *      their middle corner; what cannot be fixed so is dropped;
 *   3. edges are glued by (welded) vertex pairs: two faces glue, more keep
 *      their best-aligned pair and the others are detached;
 *   4. boundary edges at the same positions as exactly one other boundary
 *      edge are glued, their vertices welded (unwelded seams);
 *   5. each component is oriented by a breadth-first search (majority
 *      kept); an edge that cannot agree is cut (non-orientable);
 *   6. vertex ids from the fans of corners around each vertex: the first fan
 *      keeps the smallest free input id, further fans get appended copies;
 *      edges whose ids would still clash are cut until none does.
 * Positions never move; every weld is of bit-identical positions. Internal
 * state lives in one struct per call: reentrant. */
#include "io_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ROUNDS 64  /* zero-area rounds; what is left after is dropped */
#define MAX_PASSES 64  /* id-clash passes (one suffices in practice)     */
#define BIG_GROUP 64   /* edges with more faces: first opposite pair kept */

typedef struct rp {
    const double *xyz;
    uint32_t nv;
    const uint32_t *face_line; /* per input face, or NULL */
    uint32_t nf, cap;          /* working faces (dead ones included) */
    uint32_t *tri;             /* 3 * cap input vertex ids */
    uint32_t *orig;            /* input face of each working face */
    uint8_t *alive;            /* 0 dropped; else 1, | 2 if made by a split */
    uint32_t *vuf;             /* union-find of welded vertices (root: min id) */
    uint32_t *stamp;           /* per vertex root: round it was touched in */
    gs_repair *r;
    gs_error *err;
    /* after compaction: F faces, half-edges 3F */
    uint32_t F;
    uint32_t *opp;
} rp;

static const char *const kind_names[GS_REPAIR_NUM_KINDS] = {
    "faces naming a vertex twice (dropped)",
    "duplicate faces, same three vertices as an earlier one (dropped)",
    "zero-area faces with corners at one position (corners welded together, face gone)",
    "zero-area faces removed by splitting the face across their longest edge",
    "zero-area needles whose tiny edge was collapsed (its ends welded)",
    "zero-area faces on the boundary (dropped, same surface)",
    "zero-area faces dropped (a zero-width gap where each was)",
    "seam edges glued to the boundary edge at the same positions",
    "boundary edges left open (more than two at the same positions)",
    "vertices welded into a vertex at the same position or across a collapsed needle edge "
    "(now unreferenced)",
    "non-manifold edges (best-aligned pair kept, other faces detached)",
    "faces flipped to agree with their component's orientation",
    "edges cut open (non-orientable component)",
    "edges cut open to give touching sheets their own vertices",
    "vertices split into one vertex per fan (non-manifold, or where a cut or a detached face "
    "ends; copies appended)",
};

const char *gs_repair_kind_name(int kind)
{
    return (kind >= 0 && kind < GS_REPAIR_NUM_KINDS) ? kind_names[kind] : NULL;
}

/* ---- small helpers -------------------------------------------------------- */

static uint32_t find(uint32_t *p, uint32_t x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* Union by smaller root; returns the new root. */
static uint32_t unite(uint32_t *p, uint32_t a, uint32_t b)
{
    a = find(p, a);
    b = find(p, b);
    if (a == b) return a;
    if (a < b) return p[b] = a;
    return p[a] = b;
}

static void note(rp *s, int kind, uint32_t input_face, uint32_t a, uint32_t b, uint32_t c)
{
    gs_repair *r = s->r;
    r->count[kind]++;
    if (r->n_examples[kind] >= GS_REPAIR_EXAMPLES) return;
    gs_repair_example *e = &r->example[kind][r->n_examples[kind]++];
    e->face = input_face;
    e->line = (s->face_line && input_face != GS_NONE) ? s->face_line[input_face] : GS_NONE;
    e->vertex[0] = a;
    e->vertex[1] = b;
    e->vertex[2] = c;
}

static const double *pos(const rp *s, uint32_t v) { return s->xyz + 3 * (size_t)v; }

static int same_pos(const double *p, const double *q)
{
    return p[0] == q[0] && p[1] == q[1] && p[2] == q[2]; /* -0 == 0 */
}

static uint32_t cls(rp *s, uint32_t v) { return find(s->vuf, v); }

/* Position of v's welded class (its smallest id): where v's corners end up
 * (differs from v's own only after a needle's collapse). */
static const double *cpos(rp *s, uint32_t v) { return pos(s, cls(s, v)); }

static int zero_area(rp *s, const uint32_t *c)
{
    return gs__tri_zero_area(cpos(s, c[0]), cpos(s, c[1]), cpos(s, c[2]));
}

static int add_face(rp *s, uint32_t a, uint32_t b, uint32_t c, uint32_t orig)
{
    if (s->nf == s->cap) {
        if ((uint64_t)(s->cap + 1) * 3 >= UINT32_MAX)
            return gs__fail(s->err, GS_ELIMIT, "repair: more faces than geosep supports");
        uint64_t want = (uint64_t)s->cap + s->cap / 2 + 16;
        uint32_t cap = want * 3 >= UINT32_MAX ? (UINT32_MAX - 1) / 3 : (uint32_t)want;
        uint32_t *t = gs__realloc(s->tri, 3 * (size_t)cap, sizeof *t);
        if (t) s->tri = t;
        uint32_t *o = t ? gs__realloc(s->orig, cap, sizeof *o) : NULL;
        if (o) s->orig = o;
        uint8_t *al = o ? gs__realloc(s->alive, cap, 1) : NULL;
        if (!al) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
        s->alive = al;
        s->cap = cap;
    }
    uint32_t *t = s->tri + 3 * (size_t)s->nf;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    s->orig[s->nf] = orig;
    s->alive[s->nf] = 1;
    s->nf++;
    return GS_OK;
}

/* ---- edges keyed by their (welded) end vertices --------------------------- */

typedef struct ekey {
    uint32_t lo, hi, id; /* id: a face (stage 2) or a half-edge (stages 3-6) */
} ekey;

static int cmp_ekey(const void *a, const void *b)
{
    const ekey *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->id < y->id ? -1 : (x->id > y->id);
}

static ekey make_key(uint32_t a, uint32_t b, uint32_t id)
{
    return a < b ? (ekey){a, b, id} : (ekey){b, a, id};
}

/* First entry with (lo, hi) >= (a, b) sorted; index in [0, n]. */
static size_t lower(const ekey *e, size_t n, uint32_t lo, uint32_t hi)
{
    size_t a = 0, b = n;
    while (a < b) {
        size_t m = a + (b - a) / 2;
        if (e[m].lo < lo || (e[m].lo == lo && e[m].hi < hi)) a = m + 1;
        else b = m;
    }
    return a;
}

/* ---- stage 1: repeated corners, duplicates -------------------------------- */

static void drop_repeated(rp *s)
{
    for (uint32_t f = 0; f < s->nf; ++f) {
        const uint32_t *c = s->tri + 3 * (size_t)f;
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
            s->alive[f] = 0;
            note(s, GS_REPAIR_REPEATED_CORNER, s->orig[f], c[0], c[1], c[2]);
        }
    }
}

typedef struct fkey {
    uint32_t v[3], f;
} fkey;

static int cmp_fkey(const void *a, const void *b)
{
    const fkey *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x->v[k] != y->v[k]) return x->v[k] < y->v[k] ? -1 : 1;
    return x->f < y->f ? -1 : (x->f > y->f);
}

static int drop_duplicates(rp *s)
{
    fkey *k = gs__malloc(s->nf ? s->nf : 1, sizeof *k);
    if (!k) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    uint32_t n = 0;
    for (uint32_t f = 0; f < s->nf; ++f) {
        if (!s->alive[f]) continue;
        uint32_t a = cls(s, s->tri[3 * (size_t)f]), b = cls(s, s->tri[3 * (size_t)f + 1]),
                 c = cls(s, s->tri[3 * (size_t)f + 2]), t;
        if (a > b) t = a, a = b, b = t;
        if (b > c) t = b, b = c, c = t;
        if (a > b) t = a, a = b, b = t;
        k[n++] = (fkey){{a, b, c}, f};
    }
    qsort(k, n, sizeof *k, cmp_fkey);
    for (uint32_t i = 1; i < n; ++i)
        if (!memcmp(k[i].v, k[i - 1].v, sizeof k[i].v) && k[i].v[0] != k[i].v[1] &&
            k[i].v[1] != k[i].v[2]) {
            uint32_t f = k[i].f;
            const uint32_t *c = s->tri + 3 * (size_t)f;
            s->alive[f] = 0;
            note(s, GS_REPAIR_DUPLICATE_FACE, s->orig[f], c[0], c[1], c[2]);
        }
    free(k);
    return GS_OK;
}

/* ---- stage 2: zero-area faces --------------------------------------------- */

static int touched(rp *s, uint32_t v, uint32_t round) { return s->stamp[cls(s, v)] == round; }
static void touch(rp *s, uint32_t v, uint32_t round) { s->stamp[cls(s, v)] = round; }

/* Weld the corners of f at one position; 1 if there were such corners. */
static int collapse(rp *s, uint32_t f, uint32_t round)
{
    const uint32_t *c = s->tri + 3 * (size_t)f;
    int any = 0;
    for (int i = 0; i < 3; ++i) {
        uint32_t a = c[i], b = c[(i + 1) % 3];
        if (!same_pos(cpos(s, a), cpos(s, b))) continue;
        touch(s, a, round);
        touch(s, b, round);
        unite(s->vuf, a, b);
        touch(s, a, round);
        any = 1;
    }
    return any;
}

/* The split of a collinear face f: 1 done, 0 deferred (something nearby
 * changed this round), -1 impossible (f is left for the final drop). */
static int split_across(rp *s, uint32_t f, const ekey *e, size_t ne, uint32_t round, int *rc)
{
    const uint32_t *c = s->tri + 3 * (size_t)f;
    int li = 0;
    double best = -1;
    for (int i = 0; i < 3; ++i) {
        const double *p = cpos(s, c[i]), *q = cpos(s, c[(i + 1) % 3]);
        double l = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                   (p[2] - q[2]) * (p[2] - q[2]);
        if (l > best) best = l, li = i;
    }
    uint32_t x = c[li], y = c[(li + 1) % 3], m = c[(li + 2) % 3];
    if (touched(s, x, round) || touched(s, y, round) || touched(s, m, round)) return 0;
    uint32_t cx = cls(s, x), cy = cls(s, y);
    uint32_t lo = cx < cy ? cx : cy, hi = cx < cy ? cy : cx;
    uint32_t other = GS_NONE, n_other = 0;
    for (size_t i = lower(e, ne, lo, hi); i < ne && e[i].lo == lo && e[i].hi == hi && n_other < 2; ++i)
        if (e[i].id != f && s->alive[e[i].id]) other = e[i].id, n_other++;
    if (n_other == 0) { /* the longest edge is on the boundary */
        s->alive[f] = 0;
        note(s, GS_REPAIR_ZERO_AREA_BOUNDARY, s->orig[f], c[0], c[1], c[2]);
        touch(s, x, round), touch(s, y, round), touch(s, m, round);
        return 1;
    }
    if (n_other > 1) return -1;
    uint32_t *n = s->tri + 3 * (size_t)other;
    if (zero_area(s, n)) return -1;
    int j = 0; /* n's edge (n[j], n[j+1]) is the edge {x, y} */
    while (j < 3 && !((cls(s, n[j]) == cx && cls(s, n[(j + 1) % 3]) == cy) ||
                      (cls(s, n[j]) == cy && cls(s, n[(j + 1) % 3]) == cx)))
        ++j;
    if (j == 3) return -1;
    uint32_t a = n[j], b = n[(j + 1) % 3], d = n[(j + 2) % 3];
    if (touched(s, d, round)) return 0;
    uint32_t cm = cls(s, m), cd = cls(s, d);
    if (cm == cd) return -1;
    /* the new edge m-d must not exist yet */
    uint32_t l2 = cm < cd ? cm : cd, h2 = cm < cd ? cd : cm;
    size_t i = lower(e, ne, l2, h2);
    if (i < ne && e[i].lo == l2 && e[i].hi == h2) return -1;
    uint32_t t1[3] = {a, m, d}, t2[3] = {m, b, d};
    if (zero_area(s, t1) || zero_area(s, t2)) return -1;
    touch(s, x, round), touch(s, y, round), touch(s, m, round), touch(s, d, round);
    uint32_t forig = s->orig[other];
    note(s, GS_REPAIR_ZERO_AREA_SPLIT, s->orig[f], c[0], c[1], c[2]);
    s->alive[f] = 0;
    n[0] = a, n[1] = m, n[2] = d; /* before add_face, which may move s->tri */
    s->alive[other] = 3;
    *rc = add_face(s, m, b, d, forig);
    if (*rc == GS_OK) s->alive[s->nf - 1] = 3;
    return 1;
}

/* A needle no split removes: weld the ends of its shortest edge if that
 * edge is below 1e-6 of the longest. 1 if done. */
static int collapse_needle(rp *s, uint32_t f, uint32_t round)
{
    const uint32_t *c = s->tri + 3 * (size_t)f;
    double l[3];
    int lo = 0, hi = 0;
    for (int i = 0; i < 3; ++i) {
        const double *p = cpos(s, c[i]), *q = cpos(s, c[(i + 1) % 3]);
        l[i] = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (l[i] < l[lo]) lo = i;
        if (l[i] > l[hi]) hi = i;
    }
    if (!(l[lo] <= 1e-12 * l[hi])) return 0;
    for (int i = 0; i < 3; ++i)
        if (touched(s, c[i], round)) return 0;
    uint32_t a = c[lo], b = c[(lo + 1) % 3];
    touch(s, a, round), touch(s, b, round);
    unite(s->vuf, a, b);
    touch(s, a, round);
    s->alive[f] = 0;
    note(s, GS_REPAIR_ZERO_AREA_NEEDLE, s->orig[f], c[0], c[1], c[2]);
    return 1;
}

static int zero_area_faces(rp *s)
{
    ekey *e = NULL;
    int rc = GS_OK;
    for (uint32_t round = 1;; ++round) {
        int changed = 0;
        /* faces whose corners were welded together are gone */
        for (uint32_t f = 0; f < s->nf; ++f) {
            if (!s->alive[f]) continue;
            const uint32_t *c = s->tri + 3 * (size_t)f;
            uint32_t a = cls(s, c[0]), b = cls(s, c[1]), d = cls(s, c[2]);
            if (a == b || b == d || a == d) {
                s->alive[f] = 0;
                note(s, GS_REPAIR_ZERO_AREA_COLLAPSED, s->orig[f], c[0], c[1], c[2]);
            }
        }
        size_t ne = 0;
        free(e);
        e = gs__malloc(3 * (size_t)s->nf + 1, sizeof *e);
        if (!e) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
        uint32_t nf0 = s->nf, n_zero = 0;
        for (uint32_t f = 0; f < nf0; ++f) {
            if (!s->alive[f]) continue;
            const uint32_t *c = s->tri + 3 * (size_t)f;
            for (int i = 0; i < 3; ++i)
                e[ne++] = make_key(cls(s, c[i]), cls(s, c[(i + 1) % 3]), f);
            n_zero += zero_area(s, c) != 0;
        }
        if (n_zero == 0) break;
        qsort(e, ne, sizeof *e, cmp_ekey);
        int last = round >= MAX_ROUNDS;
        for (uint32_t f = 0; f < nf0 && rc == GS_OK; ++f) {
            if (!s->alive[f] || !zero_area(s, s->tri + 3 * (size_t)f)) continue;
            if (collapse(s, f, round)) {
                const uint32_t *c = s->tri + 3 * (size_t)f;
                s->alive[f] = 0;
                note(s, GS_REPAIR_ZERO_AREA_COLLAPSED, s->orig[f], c[0], c[1], c[2]);
                changed = 1;
                continue;
            }
            if (last) continue;
            int k = split_across(s, f, e, ne, round, &rc);
            if (k > 0) changed = 1;
            if (k < 0 && collapse_needle(s, f, round)) changed = 1;
        }
        if (rc) break;
        if (!changed || last) { /* what is left cannot be removed otherwise */
            for (uint32_t f = 0; f < s->nf; ++f) {
                const uint32_t *c = s->tri + 3 * (size_t)f;
                if (!s->alive[f] || !zero_area(s, c)) continue;
                s->alive[f] = 0;
                note(s, GS_REPAIR_ZERO_AREA_DROPPED, s->orig[f], c[0], c[1], c[2]);
            }
            break;
        }
    }
    free(e);
    return rc;
}

/* ---- stage 3: gluing edges ------------------------------------------------ */

static void face_normal(const rp *s, const uint32_t *c, double *n)
{
    const double *p = pos(s, c[0]), *q = pos(s, c[1]), *r = pos(s, c[2]);
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0) n[0] /= l, n[1] /= l, n[2] /= l;
}

/* Keep only the live faces, in order (faces made by splits last). */
static int compact(rp *s)
{
    uint32_t F = 0;
    for (uint32_t f = 0; f < s->nf; ++f) {
        if (!s->alive[f]) continue;
        memmove(s->tri + 3 * (size_t)F, s->tri + 3 * (size_t)f, 3 * sizeof *s->tri);
        s->alive[F] = s->alive[f];
        s->orig[F++] = s->orig[f];
    }
    s->F = s->nf = F;
    if (F == 0) return GS_OK;
    if ((uint64_t)F * 3 >= UINT32_MAX)
        return gs__fail(s->err, GS_ELIMIT, "repair: %u faces is more than geosep supports", F);
    s->opp = gs__malloc(3 * (size_t)F, sizeof *s->opp);
    if (!s->opp) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    for (size_t h = 0; h < 3 * (size_t)F; ++h) s->opp[h] = GS_NONE;
    return GS_OK;
}

static uint32_t hv(const rp *s, uint32_t h) { return s->tri[h]; }
static uint32_t hnext(uint32_t h) { return gs__next(h); }

/* Score of gluing half-edges a and b: opposite directions first, then the
 * alignment of the faces' normals (made comparable). */
static double pair_score(rp *s, uint32_t a, uint32_t b)
{
    double na[3], nb[3];
    face_normal(s, s->tri + 3 * (size_t)(a / 3), na);
    face_normal(s, s->tri + 3 * (size_t)(b / 3), nb);
    double dot = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
    int opposite = cls(s, hv(s, a)) != cls(s, hv(s, b));
    return opposite ? 4 + dot : -dot;
}

static int glue_edges(rp *s)
{
    size_t nh = 3 * (size_t)s->F;
    ekey *e = gs__malloc(nh ? nh : 1, sizeof *e);
    if (!e) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    for (size_t h = 0; h < nh; ++h)
        e[h] = make_key(cls(s, hv(s, (uint32_t)h)), cls(s, hv(s, hnext((uint32_t)h))), (uint32_t)h);
    qsort(e, nh, sizeof *e, cmp_ekey);
    for (size_t i = 0; i < nh;) {
        size_t j = i + 1;
        while (j < nh && e[j].lo == e[i].lo && e[j].hi == e[i].hi) ++j;
        size_t k = j - i;
        if (k == 2) {
            s->opp[e[i].id] = e[i + 1].id;
            s->opp[e[i + 1].id] = e[i].id;
        } else if (k > 2) {
            size_t ba = i, bb = i + 1;
            double best = -1e300;
            for (size_t a = i; a < j; ++a)
                for (size_t b = a + 1; b < j; ++b) {
                    if (k > BIG_GROUP && (a > i + BIG_GROUP || b > i + BIG_GROUP)) break;
                    double sc = pair_score(s, e[a].id, e[b].id);
                    if (sc > best) best = sc, ba = a, bb = b;
                }
            s->opp[e[ba].id] = e[bb].id;
            s->opp[e[bb].id] = e[ba].id;
            uint32_t extra = GS_NONE;
            for (size_t a = i; a < j && extra == GS_NONE; ++a)
                if (a != ba && a != bb) extra = e[a].id;
            note(s, GS_REPAIR_NONMANIFOLD_EDGE, s->orig[extra / 3], hv(s, extra),
                 hv(s, hnext(extra)), GS_NONE);
        }
        i = j;
    }
    free(e);
    return GS_OK;
}

/* ---- stage 4: seams -------------------------------------------------------- */

typedef struct pkey {
    double a[3], b[3]; /* end positions, a <= b lexicographically */
    uint32_t h;
    uint32_t ca, cb;   /* the ends' classes when the edges were glued */
} pkey;

static int cmp_pos(const double *p, const double *q)
{
    for (int k = 0; k < 3; ++k)
        if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
    return 0;
}

static int cmp_pkey(const void *x, const void *y)
{
    const pkey *a = x, *b = y;
    int c = cmp_pos(a->a, b->a);
    if (!c) c = cmp_pos(a->b, b->b);
    if (!c) c = a->h < b->h ? -1 : (a->h > b->h);
    return c;
}

static int weld_seams(rp *s)
{
    size_t nh = 3 * (size_t)s->F, n = 0;
    for (size_t h = 0; h < nh; ++h) n += s->opp[h] == GS_NONE;
    if (n < 2) return GS_OK;
    pkey *k = gs__malloc(n, sizeof *k);
    if (!k) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    n = 0;
    for (size_t h = 0; h < nh; ++h) {
        if (s->opp[h] != GS_NONE) continue;
        const double *p = pos(s, hv(s, (uint32_t)h)), *q = pos(s, hv(s, hnext((uint32_t)h)));
        if (cmp_pos(p, q) > 0) {
            const double *t = p;
            p = q, q = t;
        }
        pkey *x = &k[n++];
        for (int c = 0; c < 3; ++c) x->a[c] = p[c] + 0.0, x->b[c] = q[c] + 0.0;
        x->h = (uint32_t)h;
        x->ca = cls(s, hv(s, (uint32_t)h));
        x->cb = cls(s, hv(s, hnext((uint32_t)h)));
    }
    qsort(k, n, sizeof *k, cmp_pkey);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && !cmp_pos(k[j].a, k[i].a) && !cmp_pos(k[j].b, k[i].b)) ++j;
        if (j - i == 2) {
            uint32_t h1 = k[i].h, h2 = k[i + 1].h;
            uint32_t a = hv(s, h1), b = hv(s, hnext(h1)), c = hv(s, h2), d = hv(s, hnext(h2));
            /* two edges of the same vertices are boundary edges only when
             * they were detached from a non-manifold edge: they stay so
             * (the classes of the time: welds made here along a loop of
             * seam edges must not stop the loop's last edge) */
            const pkey *x = &k[i], *y = &k[i + 1];
            int same_classes = (x->ca == y->ca && x->cb == y->cb) || (x->ca == y->cb && x->cb == y->ca);
            if (h1 / 3 != h2 / 3 && !same_classes) {
                s->opp[h1] = h2;
                s->opp[h2] = h1;
                if (same_pos(pos(s, a), pos(s, d))) unite(s->vuf, a, d), unite(s->vuf, b, c);
                else unite(s->vuf, a, c), unite(s->vuf, b, d);
                note(s, GS_REPAIR_SEAM_EDGE, s->orig[h2 / 3], c, d, GS_NONE);
            }
        } else if (j - i > 2) {
            note(s, GS_REPAIR_SEAM_AMBIGUOUS, s->orig[k[i].h / 3], hv(s, k[i].h),
                 hv(s, hnext(k[i].h)), GS_NONE);
        }
        i = j;
    }
    free(k);
    return GS_OK;
}

/* ---- stage 5: orientation -------------------------------------------------- */

static void unglue(rp *s, uint32_t h)
{
    uint32_t o = s->opp[h];
    if (o == GS_NONE) return;
    s->opp[h] = s->opp[o] = GS_NONE;
}

static int orient(rp *s)
{
    uint32_t F = s->F;
    uint8_t *flip = gs__calloc(F ? F : 1, 1), *seen = gs__calloc(F ? F : 1, 1);
    uint32_t *queue = gs__malloc(F ? F : 1, sizeof *queue);
    if (!flip || !seen || !queue) {
        free(flip), free(seen), free(queue);
        return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    }
    for (uint32_t f0 = 0; f0 < F; ++f0) {
        if (seen[f0]) continue;
        uint32_t head = 0, tail = 0, n_flip = 0;
        seen[f0] = 1;
        queue[tail++] = f0;
        while (head < tail) {
            uint32_t f = queue[head++];
            for (uint32_t i = 0; i < 3; ++i) {
                uint32_t h = 3 * f + i, o = s->opp[h];
                if (o == GS_NONE) continue;
                uint32_t g = o / 3;
                /* glued half-edges agree when they run in opposite directions */
                uint8_t same = cls(s, hv(s, h)) == cls(s, hv(s, o));
                uint8_t want = flip[f] ^ same;
                if (!seen[g]) {
                    seen[g] = 1;
                    flip[g] = want;
                    n_flip += want;
                    queue[tail++] = g;
                } else if (flip[g] != want) {
                    note(s, GS_REPAIR_ORIENTATION_CUT, s->orig[f], hv(s, h), hv(s, hnext(h)), GS_NONE);
                    unglue(s, h);
                }
            }
        }
        if (2 * (uint64_t)n_flip > tail) /* the majority keeps its orientation */
            for (uint32_t q = 0; q < tail; ++q) flip[queue[q]] ^= 1;
    }
    /* reverse the flipped faces: (a, b, c) -> (a, c, b); half-edge i -> 2 - i */
    uint32_t *nopp = gs__malloc(3 * (size_t)F + 1, sizeof *nopp);
    if (!nopp) {
        free(flip), free(seen), free(queue);
        return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    }
    for (uint32_t h = 0; h < 3 * F; ++h) {
        uint32_t nh = flip[h / 3] ? 3 * (h / 3) + 2 - h % 3 : h, o = s->opp[h];
        nopp[nh] = o == GS_NONE ? GS_NONE : (flip[o / 3] ? 3 * (o / 3) + 2 - o % 3 : o);
    }
    for (uint32_t f = 0; f < F; ++f) {
        if (!flip[f]) continue;
        uint32_t *c = s->tri + 3 * (size_t)f, t = c[1];
        s->alive[f] |= 4;
        note(s, GS_REPAIR_FLIPPED_FACE, s->orig[f], c[0], c[1], c[2]);
        c[1] = c[2];
        c[2] = t;
    }
    free(s->opp);
    s->opp = nopp;
    free(flip), free(seen), free(queue);
    return GS_OK;
}

/* ---- stage 6: vertex ids from fans ----------------------------------------- */

typedef struct cfan {
    uint32_t root, v, h; /* fan (its smallest corner), input vertex, corner */
} cfan;

static int cmp_cfan(const void *a, const void *b)
{
    const cfan *x = a, *y = b;
    if (x->root != y->root) return x->root < y->root ? -1 : 1;
    if (x->v != y->v) return x->v < y->v ? -1 : 1;
    return x->h < y->h ? -1 : (x->h > y->h);
}

typedef struct ids {
    uint32_t *out_tri;   /* 3F repaired ids */
    uint32_t nv_out;
    uint32_t *copy_of;   /* nv_out - nv: input vertex of each copy */
    uint32_t n_copy_cap;
} ids;

/* One assignment of ids from the current gluing. */
static int assign(rp *s, ids *d, cfan *c, uint32_t *cuf, uint32_t *owner, uint32_t *fan_id)
{
    size_t nh = 3 * (size_t)s->F;
    for (size_t h = 0; h < nh; ++h) cuf[h] = (uint32_t)h;
    for (size_t h = 0; h < nh; ++h)
        if (s->opp[h] != GS_NONE) unite(cuf, (uint32_t)h, hnext(s->opp[h]));
    for (size_t h = 0; h < nh; ++h) c[h] = (cfan){find(cuf, (uint32_t)h), s->tri[h], (uint32_t)h};
    qsort(c, nh, sizeof *c, cmp_cfan);
    for (uint32_t v = 0; v < s->nv; ++v) owner[v] = GS_NONE;
    d->nv_out = s->nv;
    for (size_t i = 0; i < nh;) {
        size_t j = i + 1;
        while (j < nh && c[j].root == c[i].root) ++j;
        uint32_t id = GS_NONE;
        for (size_t k = i; k < j && id == GS_NONE; ++k)
            if (owner[c[k].v] == GS_NONE) id = c[k].v;
        if (id != GS_NONE) {
            owner[id] = c[i].root;
        } else {
            if (d->nv_out == UINT32_MAX - 1)
                return gs__fail(s->err, GS_ELIMIT, "repair: more vertices than geosep supports");
            uint32_t n = d->nv_out - s->nv;
            if (n == d->n_copy_cap) {
                uint32_t cap = d->n_copy_cap ? 2 * d->n_copy_cap : 64;
                uint32_t *p = gs__realloc(d->copy_of, cap, sizeof *p);
                if (!p) return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
                d->copy_of = p;
                d->n_copy_cap = cap;
            }
            d->copy_of[n] = c[i].v; /* the smallest input id of the fan */
            id = d->nv_out++;
        }
        fan_id[c[i].root] = id;
        i = j;
    }
    for (size_t h = 0; h < nh; ++h) d->out_tri[h] = fan_id[find(cuf, (uint32_t)h)];
    return GS_OK;
}

/* Half-edges whose repaired ids clash (more than two on an edge, or two not
 * glued to each other) get their start corner cut loose from its fan.
 * Returns the number of edges cut (0: the ids are final). */
static uint32_t separate(rp *s, const ids *d, ekey *e)
{
    size_t nh = 3 * (size_t)s->F;
    for (size_t h = 0; h < nh; ++h)
        e[h] = make_key(d->out_tri[h], d->out_tri[hnext((uint32_t)h)], (uint32_t)h);
    qsort(e, nh, sizeof *e, cmp_ekey);
    uint32_t cuts = 0;
    for (size_t i = 0; i < nh;) {
        size_t j = i + 1;
        while (j < nh && e[j].lo == e[i].lo && e[j].hi == e[i].hi) ++j;
        int ok = j - i == 1 || (j - i == 2 && s->opp[e[i].id] == e[i + 1].id);
        if (!ok) {
            /* keep the first glued pair of the group, if any */
            uint32_t keep = GS_NONE;
            for (size_t k = i; k < j && keep == GS_NONE; ++k) {
                uint32_t o = s->opp[e[k].id];
                for (size_t m = i; m < j; ++m)
                    if (o != GS_NONE && e[m].id == o) keep = e[k].id;
            }
            int skip_one = keep == GS_NONE; /* one loose edge may stay as it is */
            for (size_t k = i; k < j; ++k) {
                uint32_t h = e[k].id;
                if (keep != GS_NONE && (h == keep || h == s->opp[keep])) continue;
                if (skip_one) {
                    skip_one = 0;
                    continue;
                }
                uint32_t p = gs__prev(h);
                if (s->opp[h] != GS_NONE || s->opp[p] != GS_NONE) {
                    note(s, GS_REPAIR_SHEET_CUT, s->orig[h / 3], s->tri[h], s->tri[hnext(h)], GS_NONE);
                    cuts++;
                }
                unglue(s, h);
                unglue(s, p);
            }
        }
        i = j;
    }
    return cuts;
}

static int make_ids(rp *s, ids *d)
{
    size_t nh = 3 * (size_t)s->F;
    cfan *c = gs__malloc(nh, sizeof *c);
    uint32_t *cuf = gs__malloc(nh, sizeof *cuf), *fan_id = gs__malloc(nh, sizeof *fan_id);
    uint32_t *owner = gs__malloc(s->nv ? s->nv : 1, sizeof *owner);
    ekey *e = gs__malloc(nh, sizeof *e);
    d->out_tri = gs__malloc(nh, sizeof *d->out_tri);
    int rc = (!c || !cuf || !fan_id || !owner || !e || !d->out_tri)
                 ? gs__fail(s->err, GS_ENOMEM, "repair: out of memory")
                 : GS_OK;
    for (int pass = 0; rc == GS_OK; ++pass) {
        rc = assign(s, d, c, cuf, owner, fan_id);
        if (rc || separate(s, d, e) == 0) break;
        if (pass == MAX_PASSES)
            rc = gs__fail(s->err, GS_EINTERNAL, "repair: could not separate the sheets of the mesh");
    }
    free(c), free(cuf), free(fan_id), free(owner), free(e);
    return rc;
}

/* ---- the result --------------------------------------------------------------- */

typedef struct vpair {
    uint32_t v, id, h;
} vpair;

static int cmp_vpair(const void *a, const void *b)
{
    const vpair *x = a, *y = b;
    if (x->v != y->v) return x->v < y->v ? -1 : 1;
    if (x->id != y->id) return x->id < y->id ? -1 : 1;
    return x->h < y->h ? -1 : (x->h > y->h);
}

/* vertex_map, aliases, origins, and the welded / split counts. */
static int fill_maps(rp *s, const ids *d)
{
    gs_repair *r = s->r;
    size_t nh = 3 * (size_t)s->F;
    vpair *p = gs__malloc(nh ? nh : 1, sizeof *p);
    r->vertex_map = gs__malloc(s->nv ? s->nv : 1, sizeof *r->vertex_map);
    r->alias_start = gs__malloc((size_t)s->nv + 1, sizeof *r->alias_start);
    r->alias = gs__malloc(nh + s->nv + 1, sizeof *r->alias);
    r->vertex_origin = gs__malloc(d->nv_out ? d->nv_out : 1, sizeof *r->vertex_origin);
    r->face_origin = gs__malloc(s->F ? s->F : 1, sizeof *r->face_origin);
    r->face_change = gs__malloc(s->F ? s->F : 1, 1);
    if (!p || !r->vertex_map || !r->alias_start || !r->alias || !r->vertex_origin || !r->face_origin ||
        !r->face_change) {
        free(p);
        return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    }
    for (size_t h = 0; h < nh; ++h) p[h] = (vpair){s->tri[h], d->out_tri[h], (uint32_t)h};
    qsort(p, nh, sizeof *p, cmp_vpair); /* by input vertex, then repaired id */
    /* a vertex that no face uses any more but was welded (its faces all
     * collapsed) goes where its class's first corner went */
    uint32_t *target = gs__malloc(s->nv ? s->nv : 1, sizeof *target);
    if (!target) {
        free(p);
        return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    }
    for (uint32_t v = 0; v < s->nv; ++v) target[v] = GS_NONE;
    for (size_t h = 0; h < nh; ++h) {
        uint32_t c = cls(s, s->tri[h]);
        if (target[c] == GS_NONE) target[c] = d->out_tri[h];
    }
    uint32_t na = 0;
    size_t i = 0;
    for (uint32_t v = 0; v < s->nv; ++v) {
        r->alias_start[v] = na;
        size_t j = i;
        while (j < nh && p[j].v == v) ++j;
        if (i == j) { /* no face uses v */
            uint32_t t = target[cls(s, v)];
            r->vertex_map[v] = t == GS_NONE ? v : t;
            r->alias[na++] = r->vertex_map[v];
            if (t != GS_NONE && t != v) note(s, GS_REPAIR_WELDED_VERTEX, GS_NONE, v, t, GS_NONE);
            continue;
        }
        /* primary: v itself if one of its fans kept it, else the fan of its
         * first corner (v was welded into it) */
        uint32_t primary = GS_NONE, first_h = GS_NONE, first_id = GS_NONE;
        for (size_t k = i; k < j; ++k) {
            if (p[k].id == v) primary = v;
            if (p[k].h < first_h) first_h = p[k].h, first_id = p[k].id;
        }
        if (primary == GS_NONE) primary = first_id;
        r->vertex_map[v] = primary;
        r->alias[na++] = primary;
        for (size_t k = i; k < j; ++k) /* the others, increasing, once each */
            if (p[k].id != primary && (k == i || p[k].id != p[k - 1].id)) r->alias[na++] = p[k].id;
        if (primary != v) note(s, GS_REPAIR_WELDED_VERTEX, s->orig[first_h / 3], v, primary, GS_NONE);
        i = j;
    }
    r->alias_start[s->nv] = na;
    free(p);
    free(target);
    for (uint32_t v = 0; v < d->nv_out; ++v)
        r->vertex_origin[v] = v < s->nv ? v : d->copy_of[v - s->nv];
    /* split vertices: input vertices that got copies (each counted once);
     * the example names a face of the copy */
    uint32_t n_copy = d->nv_out - s->nv;
    uint8_t *mark = gs__calloc(s->nv ? s->nv : 1, 1);
    uint32_t *copy_face = gs__malloc(n_copy ? n_copy : 1, sizeof *copy_face);
    if (!mark || !copy_face) {
        free(mark), free(copy_face);
        return gs__fail(s->err, GS_ENOMEM, "repair: out of memory");
    }
    for (uint32_t k = 0; k < n_copy; ++k) copy_face[k] = GS_NONE;
    for (size_t h = 0; h < nh; ++h)
        if (d->out_tri[h] >= s->nv && copy_face[d->out_tri[h] - s->nv] == GS_NONE)
            copy_face[d->out_tri[h] - s->nv] = s->orig[h / 3];
    for (uint32_t k = 0; k < n_copy; ++k) {
        uint32_t v = d->copy_of[k];
        if (mark[v]) continue;
        mark[v] = 1;
        note(s, GS_REPAIR_SPLIT_VERTEX, copy_face[k], v, s->nv + k, GS_NONE);
    }
    free(mark), free(copy_face);
    for (uint32_t f = 0; f < s->F; ++f) {
        r->face_origin[f] = s->orig[f];
        r->face_change[f] = (s->alive[f] & 2) ? GS_REPAIR_FACE_SPLIT
                            : (s->alive[f] & 4) ? GS_REPAIR_FACE_FLIPPED
                                                : GS_REPAIR_FACE_SAME;
    }
    r->n_vertices = d->nv_out;
    r->n_faces = s->F;
    return GS_OK;
}

/* ---- entry points ------------------------------------------------------------- */

void gs_repair_free(gs_repair *info)
{
    if (!info) return;
    free(info->vertex_map);
    free(info->alias_start);
    free(info->alias);
    free(info->vertex_origin);
    free(info->face_origin);
    free(info->face_change);
    free(info);
}

static int check_input(const double *xyz, uint32_t nv, const uint32_t *tri, uint32_t nf,
                       const char *file, const uint32_t *face_line, const char *unit, gs_error *err)
{
    for (uint32_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(xyz[3 * (size_t)v + k]))
                return gs__fail(err, GS_EMESH, "%s: vertex %u has a non-finite coordinate (%c = %g)",
                                file, v, "xyz"[k], xyz[3 * (size_t)v + k]);
    for (uint32_t f = 0; f < nf; ++f) {
        const uint32_t *c = tri + 3 * (size_t)f;
        char w[64];
        if (face_line) snprintf(w, sizeof w, "%s %u", unit, face_line[f]);
        else snprintf(w, sizeof w, "face %u", f);
        for (int i = 0; i < 3; ++i) {
            if (c[i] >= nv)
                return gs__fail(err, GS_EMESH, "%s: %s: vertex index %u out of range (the mesh has %u vertices)",
                                file, w, c[i], nv);
        }
        for (int i = 0; i < 3; ++i) {
            const double *p = xyz + 3 * (size_t)c[i], *q = xyz + 3 * (size_t)c[(i + 1) % 3];
            double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            if (dx * dx + dy * dy + dz * dz <= GS_MESH_MAX_EDGE * GS_MESH_MAX_EDGE) continue;
            double l = hypot(hypot(dx, dy), dz); /* no overflow */
            if (!(l <= GS_MESH_MAX_EDGE))
                return gs__fail(err, GS_EMESH, "%s: %s: edge %u-%u has length %.3g, longer than geosep's "
                                "%g (rescale the mesh; repair does not move vertices)",
                                file, w, c[i], c[(i + 1) % 3], l, GS_MESH_MAX_EDGE);
        }
    }
    return GS_OK;
}

static int run(const double *xyz, uint32_t nv, const uint32_t *tri, uint32_t nf, const char *file,
               int is_file, const uint32_t *face_line, const char *unit, gs_mesh **out,
               gs_repair **info, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_mesh_repair: out is NULL");
    *out = NULL;
    if (info) *info = NULL;
    if ((nv && !xyz) || (nf && !tri))
        return gs__fail(err, GS_EARG, "gs_mesh_repair: NULL array with a non-zero count");
    if (nf == 0)
        return gs__fail(err, GS_EMESH, "%s: no faces (%u vertices given); a mesh needs at least one "
                        "triangle", file, nv);
    if ((uint64_t)nf * 3 >= UINT32_MAX)
        return gs__fail(err, GS_ELIMIT, "%s: %u faces is more than geosep supports", file, nf);
    int rc = check_input(xyz, nv, tri, nf, file, face_line, unit ? unit : "face", err);
    if (rc) return rc;

    rp s;
    memset(&s, 0, sizeof s);
    s.xyz = xyz;
    s.nv = nv;
    s.face_line = face_line;
    s.err = err;
    s.r = gs__calloc(1, sizeof *s.r);
    s.cap = nf;
    s.tri = gs__malloc(3 * (size_t)nf, sizeof *s.tri);
    s.orig = gs__malloc(nf, sizeof *s.orig);
    s.alive = gs__malloc(nf, 1);
    s.vuf = gs__malloc(nv ? nv : 1, sizeof *s.vuf);
    s.stamp = gs__calloc(nv ? nv : 1, sizeof *s.stamp);
    ids d = {0};
    if (!s.r || !s.tri || !s.orig || !s.alive || !s.vuf || !s.stamp) {
        rc = gs__fail(err, GS_ENOMEM, "repair: out of memory for %u faces", nf);
        goto done;
    }
    gs_repair *r = s.r;
    r->n_input_vertices = nv;
    r->n_input_faces = nf;
    snprintf(r->file, sizeof r->file, "%s", is_file ? file : "");
    snprintf(r->unit, sizeof r->unit, "%s", face_line ? (unit ? unit : "face") : "face");
    s.nf = nf;
    memcpy(s.tri, tri, 3 * (size_t)nf * sizeof *tri);
    for (uint32_t f = 0; f < nf; ++f) s.orig[f] = f, s.alive[f] = 1;
    for (uint32_t v = 0; v < nv; ++v) s.vuf[v] = v;

    drop_repeated(&s);
    rc = drop_duplicates(&s);
    if (!rc) rc = zero_area_faces(&s);
    /* welds can make faces duplicates; splits make faces of new edges only */
    if (!rc && (r->count[GS_REPAIR_ZERO_AREA_COLLAPSED] || r->count[GS_REPAIR_ZERO_AREA_NEEDLE]))
        rc = drop_duplicates(&s);
    if (!rc) rc = compact(&s);
    if (!rc && s.F == 0)
        rc = gs__fail(err, GS_EMESH, "%s: nothing is left after repair: every face was degenerate "
                      "or a duplicate", file);
    if (!rc) rc = glue_edges(&s);
    if (!rc) rc = weld_seams(&s);
    if (!rc) rc = orient(&s);
    if (!rc) rc = make_ids(&s, &d);
    if (!rc) rc = fill_maps(&s, &d);
    if (rc) goto done;
    {
        double *x = gs__malloc(3 * (size_t)d.nv_out, sizeof *x);
        uint32_t *lines = face_line ? gs__malloc(s.F, sizeof *lines) : NULL;
        if (!x || (face_line && !lines)) {
            free(x), free(lines);
            rc = gs__fail(err, GS_ENOMEM, "repair: out of memory");
            goto done;
        }
        for (uint32_t v = 0; v < d.nv_out; ++v)
            memcpy(x + 3 * (size_t)v, xyz + 3 * (size_t)r->vertex_origin[v], 3 * sizeof *x);
        for (uint32_t f = 0; lines && f < s.F; ++f) lines[f] = face_line[s.orig[f]];
        gs__origin origin = {file, lines, unit};
        gs_error e2 = {0};
        rc = gs__mesh_adopt(x, d.nv_out, d.out_tri, s.F, &origin, out, &e2);
        d.out_tri = NULL; /* adopted (or freed) */
        free(lines);
        if (rc)
            rc = gs__fail(err, rc, "%s: the repaired mesh is still invalid (%s)", file, e2.message);
    }
done:
    free(s.tri), free(s.orig), free(s.alive), free(s.vuf), free(s.stamp), free(s.opp);
    free(d.out_tri), free(d.copy_of);
    if (rc == GS_OK && info) *info = s.r;
    else gs_repair_free(s.r);
    return rc;
}

int gs_mesh_repair(const double *xyz, uint32_t n_vertices, const uint32_t *tri, uint32_t n_faces,
                   gs_mesh **out, gs_repair **info, gs_error *err)
{
    return run(xyz, n_vertices, tri, n_faces, "mesh", 0, NULL, NULL, out, info, err);
}

int gs_mesh_repair_file(const char *path, gs_mesh_format format, gs_mesh **out, gs_repair **info,
                        gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_mesh_repair_file: out is NULL");
    *out = NULL;
    if (info) *info = NULL;
    if (!path) return gs__fail(err, GS_EARG, "gs_mesh_repair_file: path is NULL");
    gs__soup s;
    int rc = gs__load_soup(path, format, &s, err);
    if (rc) return rc;
    rc = run(s.xyz, s.nv, s.tri, s.nf, path, 1, s.face_line, s.unit ? s.unit : "line", out, info, err);
    gs__soup_free(&s);
    return rc;
}

int gs__mesh_repair_memory(const char *name, const void *data, size_t size, gs_mesh_format format,
                           gs_mesh **out, gs_repair **info, gs_error *err)
{
    *out = NULL;
    if (info) *info = NULL;
    gs__soup s;
    int rc = gs__load_soup_memory(name, data, size, format, &s, err);
    if (rc) return rc;
    rc = run(s.xyz, s.nv, s.tri, s.nf, name, 1, s.face_line, s.unit ? s.unit : "line", out, info, err);
    gs__soup_free(&s);
    return rc;
}

/* ---- the text report ---------------------------------------------------------- */

typedef struct sbuf {
    char *p;
    size_t n, len;
} sbuf;

static void put(sbuf *b, const char *fmt, ...) GS_PRINTF(2, 3);
static void put(sbuf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    size_t room = b->len < b->n ? b->n - b->len : 0;
    int k = vsnprintf(room ? b->p + b->len : NULL, room, fmt, ap);
    va_end(ap);
    if (k > 0) b->len += (size_t)k;
}

size_t gs_repair_format(const gs_repair *r, char *buf, size_t size)
{
    sbuf b = {buf, size, 0};
    if (buf && size) buf[0] = 0;
    if (!r) return 0;
    const char *file = r->file[0] ? r->file : "mesh";
    put(&b, "repair %s: %u vertices, %u faces -> %u vertices (%u new), %u faces\n", file,
        r->n_input_vertices, r->n_input_faces, r->n_vertices, r->n_vertices - r->n_input_vertices,
        r->n_faces);
    int any = 0;
    for (int k = 0; k < GS_REPAIR_NUM_KINDS; ++k) {
        if (!r->count[k]) continue;
        any = 1;
        put(&b, "  %llu %s", (unsigned long long)r->count[k], kind_names[k]);
        for (uint32_t i = 0; i < r->n_examples[k]; ++i) {
            const gs_repair_example *e = &r->example[k][i];
            put(&b, "%s", i ? "; " : ": e.g. ");
            if (e->line != GS_NONE) put(&b, "%s %u", r->unit, e->line);
            else if (e->face != GS_NONE) put(&b, "face %u", e->face);
            const char *what = k == GS_REPAIR_WELDED_VERTEX ? "vertex %u into %u"
                               : k == GS_REPAIR_SPLIT_VERTEX ? "vertex %u, copy %u"
                                                              : NULL;
            int located = e->line != GS_NONE || e->face != GS_NONE;
            if (what && e->vertex[0] != GS_NONE) {
                put(&b, located ? " (" : "");
                put(&b, what, e->vertex[0], e->vertex[1]);
                put(&b, located ? ")" : "");
                continue;
            }
            int nvx = 0;
            for (int j = 0; j < 3; ++j) {
                if (e->vertex[j] == GS_NONE) continue;
                put(&b, "%s%u", nvx ? " " : located ? " (vertices " : "vertices ", e->vertex[j]);
                nvx++;
            }
            if (nvx && located) put(&b, ")");
        }
        if (r->count[k] > r->n_examples[k]) put(&b, "; ...");
        put(&b, "\n");
    }
    if (!any) put(&b, "  nothing to repair\n");
    if (r->file[0])
        put(&b, "  (vertex ids and faces 0-based, faces being the file's triangles in order; %ss as "
            "in the file)\n", r->unit);
    else
        put(&b, "  (vertex ids and faces 0-based, as in the input arrays)\n");
    return b.len;
}
