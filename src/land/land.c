/* land.c - the LAND baseline of the paper's section 5 (Burghard & Klein
 * 2015): farthest-point landmarks, exact landmark fields, and the
 * triangle-inequality lower/upper bounds; the lower bound is the estimate. */
#include "../mesh/mesh_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct gs_land {
    uint32_t nv, m;
    uint32_t *landmarks; /* m vertex ids, in the order chosen                */
    double *dist;        /* nv * m, vertex-major: dist[x*m + k] = d(l_k, x)  */
};

void gs_land_free(gs_land *l)
{
    if (!l) return;
    free(l->landmarks);
    free(l->dist);
    free(l);
}

uint32_t gs_land_num_vertices(const gs_land *l) { return l ? l->nv : 0; }
uint32_t gs_land_num_landmarks(const gs_land *l) { return l ? l->m : 0; }
const uint32_t *gs_land_landmarks(const gs_land *l) { return l ? l->landmarks : NULL; }

/* The next landmark: the unchosen used vertex farthest from the chosen ones
 * (ties: lowest id). mind holds +inf for vertices no landmark reaches. */
static uint32_t farthest(const gs_mesh *mesh, const double *mind, const unsigned char *chosen)
{
    uint32_t best = GS_NONE;
    double bd = -1;
    for (uint32_t v = 0; v < mesh->nv; ++v) {
        if (chosen[v] || (mesh->topo.vflag[v] & GS_V_UNUSED)) continue;
        if (mind[v] > bd) bd = mind[v], best = v;
    }
    return best;
}

static int select_and_solve(gs_land *l, const gs_mesh *mesh, gs_solver *solver, gs_error *err)
{
    uint32_t nv = mesh->nv;
    double *field = gs__malloc(nv, sizeof *field), *mind = gs__malloc(nv, sizeof *mind);
    unsigned char *chosen = gs__calloc(nv, 1);
    int rc = (!field || !mind || !chosen) ? gs__fail(err, GS_ENOMEM, "gs_land_build: out of memory") : GS_OK;
    for (uint32_t v = 0; v < nv && !rc; ++v) mind[v] = INFINITY;
    for (uint32_t k = 0; k < l->m && !rc; ++k) {
        uint32_t s = farthest(mesh, mind, chosen); /* k == 0: the lowest used id */
        gs_source src = gs_source_vertex(s);
        rc = gs_solver_solve(solver, &src, 1, 0, field, err);
        if (rc) break;
        chosen[s] = 1;
        l->landmarks[k] = s;
        for (uint32_t v = 0; v < nv; ++v) {
            l->dist[(size_t)v * l->m + k] = field[v];
            if (field[v] < mind[v]) mind[v] = field[v];
        }
    }
    free(field);
    free(mind);
    free(chosen);
    return rc;
}

int gs_land_build(const gs_mesh *mesh, uint32_t m, gs_method method, gs_land **out, gs_error *err)
{
    if (!mesh || !out) return gs__fail(err, GS_EARG, "gs_land_build: NULL argument");
    *out = NULL;
    uint32_t used = mesh->nv - mesh->report.n_unreferenced;
    if (m == 0 || m > used)
        return gs__fail(err, GS_EARG, "gs_land_build: %u landmarks requested, the mesh has %u used vertices", m, used);
    gs_land *l = gs__calloc(1, sizeof *l);
    if (!l) return gs__fail(err, GS_ENOMEM, "gs_land_build: out of memory");
    l->nv = mesh->nv;
    l->m = m;
    l->landmarks = gs__malloc(m, sizeof *l->landmarks);
    l->dist = gs__malloc((size_t)mesh->nv * m, sizeof *l->dist);
    if (!l->landmarks || !l->dist) {
        gs_land_free(l);
        return gs__fail(err, GS_ENOMEM, "gs_land_build: out of memory (%u x %u distances)", mesh->nv, m);
    }
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    int rc = gs_patch_create(mesh, NULL, 0, &patch, err);
    if (!rc) rc = gs_solver_create(patch, method, &solver, err);
    if (!rc) rc = select_and_solve(l, mesh, solver, err);
    gs_solver_free(solver);
    gs_patch_free(patch);
    if (rc) {
        gs_land_free(l);
        return rc;
    }
    *out = l;
    return GS_OK;
}

/* Both bounds over the landmarks that reach x or y. Returns the number of
 * landmarks reaching both; if one reaches exactly one of them, x and y are
 * not connected and both bounds are +inf. */
static uint32_t land_bounds(const gs_land *l, uint32_t x, uint32_t y, double *lo, double *up)
{
    const double *a = l->dist + (size_t)x * l->m, *b = l->dist + (size_t)y * l->m;
    double lower = 0, upper = INFINITY;
    uint32_t n = 0;
    for (uint32_t k = 0; k < l->m; ++k) {
        int fa = isfinite(a[k]), fb = isfinite(b[k]);
        if (fa != fb) {
            *lo = *up = INFINITY;
            return 0;
        }
        if (!fa) continue;
        double d = fabs(a[k] - b[k]), s = a[k] + b[k];
        if (d > lower) lower = d;
        if (s < upper) upper = s;
        n++;
    }
    *lo = lower;
    *up = upper;
    return n;
}

double gs_land_distance(const gs_land *l, uint32_t x, uint32_t y)
{
    if (!l || x >= l->nv || y >= l->nv) return NAN;
    if (x == y) return 0.0;
    double lo, up;
    return land_bounds(l, x, y, &lo, &up) ? lo : INFINITY;
}

int gs_land_bounds(const gs_land *l, uint32_t x, uint32_t y, double *lower, double *upper, gs_error *err)
{
    if (!l) return gs__fail(err, GS_EARG, "gs_land_bounds: NULL argument");
    if (x >= l->nv || y >= l->nv)
        return gs__fail(err, GS_EARG, "gs_land_bounds: vertex %u or %u >= n_vertices %u", x, y, l->nv);
    double lo = 0, up = 0;
    if (x != y) land_bounds(l, x, y, &lo, &up);
    if (lower) *lower = lo;
    if (upper) *upper = up;
    return GS_OK;
}

int gs_land_field(const gs_land *l, uint32_t x, double *out, gs_error *err)
{
    if (!l || !out) return gs__fail(err, GS_EARG, "gs_land_field: NULL argument");
    if (x >= l->nv) return gs__fail(err, GS_EARG, "gs_land_field: vertex %u >= n_vertices %u", x, l->nv);
    for (uint32_t y = 0; y < l->nv; ++y) out[y] = gs_land_distance(l, x, y);
    return GS_OK;
}
