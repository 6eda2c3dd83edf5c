/* topology.c - validation of a triangle soup and its corner/half-edge
 * connectivity: twins, edge lengths, corner angles, vertex fans. Every check
 * runs in O(F log F) whatever the input, so hostile files cannot make it hang. */
#include "mesh_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *unit_name(const gs__origin *o)
{
    return (o && o->unit) ? o->unit : "face";
}

/* "file: line 12" or "file: face 7" (1-based for lines, 0-based faces). */
static void where(char *buf, size_t n, const gs__origin *o, uint32_t f)
{
    const char *file = (o && o->file) ? o->file : "mesh";
    if (o && o->face_line)
        snprintf(buf, n, "%s: %s %u", file, unit_name(o), o->face_line[f]);
    else
        snprintf(buf, n, "%s: face %u", file, f);
}

void gs__topo_free(gs__topo *t)
{
    if (!t) return;
    free(t->opp);
    free(t->len);
    free(t->angle);
    free(t->vc_start);
    free(t->vc);
    free(t->vangle);
    free(t->vflag);
    memset(t, 0, sizeof *t);
}

typedef struct {
    uint32_t other; /* max vertex of the edge */
    uint32_t h;     /* half-edge */
} edge_entry;

static int cmp_edge(const void *a, const void *b)
{
    const edge_entry *x = a, *y = b;
    if (x->other != y->other) return x->other < y->other ? -1 : 1;
    return x->h < y->h ? -1 : (x->h > y->h);
}

static double corner_angle(const double *p, const double *q, const double *r)
{
    /* angle at p between pq and pr, robust for tiny and near-pi angles */
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                   u[0] * v[1] - u[1] * v[0]};
    double s = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    return atan2(s, d);
}

int gs__tri_zero_area(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                   u[0] * v[1] - u[1] * v[0]};
    double a2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    double l2 = fmax(u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
                     v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    /* |u x v| = |u||v| sin(angle): degenerate to rounding when the
     * triangle's height is ~1e-12 of its longest edge. */
    if (a2 > 1e-24 * l2 * l2) return 0;
    return l2 == 0 ? 2 : 1;
}

static int check_faces(const gs__topo *t, const gs__origin *o, gs_error *err)
{
    char w[600];
    for (uint32_t f = 0; f < t->nf; ++f) {
        const uint32_t *c = t->tri + 3 * (size_t)f;
        for (int i = 0; i < 3; ++i)
            if (c[i] >= t->nv) {
                where(w, sizeof w, o, f);
                return gs__fail(err, GS_EMESH,
                                "%s: vertex index %u out of range (the mesh has %u vertices)",
                                w, c[i], t->nv);
            }
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
            where(w, sizeof w, o, f);
            return gs__fail(err, GS_EMESH, "%s: face repeats a vertex (%u %u %u)", w,
                            c[0], c[1], c[2]);
        }
        const double *p = t->xyz + 3 * (size_t)c[0], *q = t->xyz + 3 * (size_t)c[1],
                     *r = t->xyz + 3 * (size_t)c[2];
        double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        double e[3][3] = {{u[0], u[1], u[2]}, {r[0] - q[0], r[1] - q[1], r[2] - q[2]},
                          {v[0], v[1], v[2]}};
        /* Edge lengths in [GS_MESH_MIN_EDGE, GS_MESH_MAX_EDGE] keep every
         * product below (the 4th powers here, squares elsewhere) finite and
         * normal; 0 is left to the zero-area test. */
        for (int k = 0; k < 3; ++k) {
            double l2 = e[k][0] * e[k][0] + e[k][1] * e[k][1] + e[k][2] * e[k][2];
            if (l2 >= GS_MESH_MIN_EDGE * GS_MESH_MIN_EDGE && l2 <= GS_MESH_MAX_EDGE * GS_MESH_MAX_EDGE)
                continue; /* the common case, without hypot's cost */
            double l = hypot(hypot(e[k][0], e[k][1]), e[k][2]); /* no overflow */
            if (!(l <= GS_MESH_MAX_EDGE) || (l > 0 && l < GS_MESH_MIN_EDGE)) {
                where(w, sizeof w, o, f);
                return gs__fail(err, GS_EMESH, "%s: edge %u-%u has length %.3g, outside geosep's "
                                "range [%g, %g] (rescale the mesh)", w, c[k], c[(k + 1) % 3], l,
                                GS_MESH_MIN_EDGE, GS_MESH_MAX_EDGE);
            }
        }
        int z = gs__tri_zero_area(p, q, r);
        if (z) {
            where(w, sizeof w, o, f);
            return gs__fail(err, GS_EMESH, "%s: zero-area face (vertices %u %u %u are %s)",
                            w, c[0], c[1], c[2], z == 2 ? "at one point" : "collinear");
        }
    }
    return GS_OK;
}

/* Find twins by bucketing half-edges under their smaller endpoint. */
static int link_twins(gs__topo *t, const gs__origin *o, gs_error *err)
{
    char w[600];
    size_t nh = 3 * (size_t)t->nf;
    uint32_t *start = gs__calloc((size_t)t->nv + 1, sizeof *start);
    edge_entry *e = gs__malloc(nh, sizeof *e);
    if (!start || !e) {
        free(start);
        free(e);
        return gs__fail(err, GS_ENOMEM, "out of memory building edges");
    }
    for (size_t h = 0; h < nh; ++h) {
        uint32_t a = t->tri[h], b = t->tri[gs__next((uint32_t)h)];
        start[(a < b ? a : b) + 1]++;
    }
    for (uint32_t v = 0; v < t->nv; ++v) start[v + 1] += start[v];
    {
        uint32_t *fill = gs__malloc((size_t)t->nv + 1, sizeof *fill);
        if (!fill) {
            free(start);
            free(e);
            return gs__fail(err, GS_ENOMEM, "out of memory building edges");
        }
        memcpy(fill, start, ((size_t)t->nv + 1) * sizeof *fill);
        for (size_t h = 0; h < nh; ++h) {
            uint32_t a = t->tri[h], b = t->tri[gs__next((uint32_t)h)];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            e[fill[lo]++] = (edge_entry){hi, (uint32_t)h};
        }
        free(fill);
    }
    int rc = GS_OK;
    uint32_t n_edges = 0;
    for (uint32_t v = 0; v < t->nv && rc == GS_OK; ++v) {
        uint32_t s = start[v], end = start[v + 1];
        if (end - s > 1) qsort(e + s, end - s, sizeof *e, cmp_edge);
        for (uint32_t i = s; i < end;) {
            uint32_t j = i + 1;
            while (j < end && e[j].other == e[i].other) ++j;
            n_edges++;
            if (j - i > 2) {
                where(w, sizeof w, o, e[i + 2].h / 3);
                rc = gs__fail(err, GS_EMESH,
                              "%s: non-manifold edge between vertices %u and %u (0-based ids; shared by %u faces)", w, v,
                              e[i].other, j - i);
                break;
            }
            if (j - i == 2) {
                uint32_t h0 = e[i].h, h1 = e[i + 1].h;
                if (t->tri[h0] == t->tri[h1]) {
                    where(w, sizeof w, o, h1 / 3);
                    rc = gs__fail(err, GS_EMESH,
                                  "%s: inconsistent orientation: edge %u-%u is used in the "
                                  "same direction by faces %u and %u%s",
                                  w, t->tri[h0], t->tri[gs__next(h0)], h0 / 3, h1 / 3,
                                  " (duplicate or flipped face)");
                    break;
                }
                t->opp[h0] = h1;
                t->opp[h1] = h0;
            }
            i = j;
        }
    }
    t->n_edges = n_edges;
    free(start);
    free(e);
    return rc;
}

/* Corners around each vertex (CSR), fans, flags, angles. */
static int build_vertex_data(gs__topo *t, unsigned flags, const gs__origin *o,
                             gs_error *err)
{
    char w[600];
    size_t nh = 3 * (size_t)t->nf;
    for (size_t h = 0; h < nh; ++h) t->vc_start[t->tri[h] + 1]++;
    for (uint32_t v = 0; v < t->nv; ++v) t->vc_start[v + 1] += t->vc_start[v];
    uint32_t *fill = gs__malloc((size_t)t->nv, sizeof *fill);
    uint8_t *seen = gs__calloc(nh, 1);
    if (!fill || !seen) {
        free(fill);
        free(seen);
        return gs__fail(err, GS_ENOMEM, "out of memory building vertex fans");
    }
    memcpy(fill, t->vc_start, (size_t)t->nv * sizeof *fill);
    for (size_t h = 0; h < nh; ++h) t->vc[fill[t->tri[h]]++] = (uint32_t)h;
    free(fill);

    int rc = GS_OK;
    for (uint32_t v = 0; v < t->nv && rc == GS_OK; ++v) {
        uint32_t s = t->vc_start[v], end = t->vc_start[v + 1];
        double total = 0;
        uint8_t fl = 0;
        if (s == end) fl |= GS_V_UNUSED;
        uint32_t fans = 0;
        for (uint32_t k = s; k < end; ++k) {
            uint32_t c = t->vc[k];
            total += t->angle[c];
            if (t->opp[c] == GS_NONE || t->opp[gs__prev(c)] == GS_NONE) fl |= GS_V_BOUNDARY;
            if (seen[c]) continue;
            /* walk the fan of c both ways, marking its corners */
            fans++;
            seen[c] = 1;
            uint32_t x = c;
            for (;;) { /* clockwise: across the outgoing edge */
                uint32_t tw = t->opp[x];
                if (tw == GS_NONE) break;
                x = gs__next(tw);
                if (seen[x]) break;
                seen[x] = 1;
            }
            x = c;
            for (;;) { /* counter-clockwise: across the incoming edge */
                uint32_t tw = t->opp[gs__prev(x)];
                if (tw == GS_NONE) break;
                x = tw;
                if (seen[x]) break;
                seen[x] = 1;
            }
        }
        if (fans > 1) {
            if (!(flags & GS_TOPO_ALLOW_NONMANIFOLD_VERTICES)) {
                where(w, sizeof w, o, t->vc[s] / 3);
                rc = gs__fail(err, GS_EMESH,
                              "%s: non-manifold vertex %u (its faces form %u separate fans)",
                              w, v, fans);
                break;
            }
            fl |= GS_V_NONMANIFOLD | GS_V_BOUNDARY;
        }
        if (!(fl & (GS_V_BOUNDARY | GS_V_UNUSED)) && total > 2 * M_PI) fl |= GS_V_SADDLE;
        t->vangle[v] = total;
        t->vflag[v] = fl;
    }
    free(seen);
    return rc;
}

int gs__topo_build(gs__topo *t, uint32_t nv, const double *xyz, uint32_t nf,
                  const uint32_t *tri, unsigned flags, const gs__origin *origin,
                  gs_error *err)
{
    memset(t, 0, sizeof *t);
    t->nv = nv;
    t->nf = nf;
    t->xyz = xyz;
    t->tri = tri;
    if ((uint64_t)nf * 3 >= UINT32_MAX)
        return gs__fail(err, GS_ELIMIT, "%s: %u faces is more than geosep supports",
                        origin && origin->file ? origin->file : "mesh", nf);
    for (uint32_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(xyz[3 * (size_t)v + k]))
                return gs__fail(err, GS_EMESH,
                                "%s: vertex %u has a non-finite coordinate (%c = %g)",
                                origin && origin->file ? origin->file : "mesh", v,
                                "xyz"[k], xyz[3 * (size_t)v + k]);
    int rc = check_faces(t, origin, err);
    if (rc) return rc;
    size_t nh = 3 * (size_t)nf;
    t->opp = gs__malloc(nh, sizeof *t->opp);
    t->len = gs__malloc(nh, sizeof *t->len);
    t->angle = gs__malloc(nh, sizeof *t->angle);
    t->vc_start = gs__calloc((size_t)nv + 1, sizeof *t->vc_start);
    t->vc = gs__malloc(nh, sizeof *t->vc);
    t->vangle = gs__malloc(nv, sizeof *t->vangle);
    t->vflag = gs__calloc(nv, 1);
    if (!t->opp || !t->len || !t->angle || !t->vc_start || !t->vc || !t->vangle ||
        !t->vflag) {
        gs__topo_free(t);
        return gs__fail(err, GS_ENOMEM, "out of memory building connectivity");
    }
    for (size_t h = 0; h < nh; ++h) {
        t->opp[h] = GS_NONE;
        const double *p = xyz + 3 * (size_t)tri[h];
        const double *q = xyz + 3 * (size_t)tri[gs__next((uint32_t)h)];
        const double *r = xyz + 3 * (size_t)tri[gs__prev((uint32_t)h)];
        double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
        t->len[h] = sqrt(dx * dx + dy * dy + dz * dz);
        t->angle[h] = corner_angle(p, q, r);
    }
    rc = link_twins(t, origin, err);
    if (rc == GS_OK) rc = build_vertex_data(t, flags, origin, err);
    if (rc) {
        gs__topo_free(t);
        t->nv = nv;
        t->nf = nf;
    }
    return rc;
}

int gs__topo_build_sub(gs__topo *t, const gs__topo *whole, const uint32_t *fmap, uint32_t *opp, uint32_t nv,
                       const double *xyz, uint32_t nf, const uint32_t *tri, gs_error *err)
{
    memset(t, 0, sizeof *t);
    t->nv = nv;
    t->nf = nf;
    t->xyz = xyz;
    t->tri = tri;
    t->opp = opp;
    size_t nh = 3 * (size_t)nf;
    t->len = gs__malloc(nh ? nh : 1, sizeof *t->len);
    t->angle = gs__malloc(nh ? nh : 1, sizeof *t->angle);
    t->vc_start = gs__calloc((size_t)nv + 1, sizeof *t->vc_start);
    t->vc = gs__malloc(nh ? nh : 1, sizeof *t->vc);
    t->vangle = gs__malloc(nv ? nv : 1, sizeof *t->vangle);
    t->vflag = gs__calloc(nv ? nv : 1, 1);
    if (!t->len || !t->angle || !t->vc_start || !t->vc || !t->vangle || !t->vflag) {
        gs__topo_free(t);
        return gs__fail(err, GS_ENOMEM, "out of memory building connectivity");
    }
    uint32_t half = 0, border = 0;
    for (uint32_t f = 0; f < nf; ++f) {
        size_t H = 3 * (size_t)fmap[f], h = 3 * (size_t)f;
        memcpy(t->len + h, whole->len + H, 3 * sizeof *t->len);
        memcpy(t->angle + h, whole->angle + H, 3 * sizeof *t->angle);
        for (int k = 0; k < 3; ++k) {
            if (opp[h + k] == GS_NONE) ++border;
            else ++half;
        }
    }
    t->n_edges = border + half / 2;
    int rc = build_vertex_data(t, GS_TOPO_ALLOW_NONMANIFOLD_VERTICES, NULL, err);
    if (rc) {
        gs__topo_free(t);
        t->nv = nv;
        t->nf = nf;
    }
    return rc;
}
