/* db_fixture.c - the hand-made database of db_fixture.h. */
#include "db_fixture.h"
#include "check.h"

#include <math.h>
#include <string.h>

static void fx_quadratic(fixture *f, uint64_t i, uint32_t x, uint32_t k, uint32_t closed)
{
    double a = 0.1 + 0.05 * x + 0.02 * k, b = 0.5 + 0.1 * ((x + k) % 3), t0 = -0.6 + 0.2 * ((x * 3 + k) % 7);
    int sq = (x == 3 && k == 1);
    double A = sq ? a * a : a; /* squared: the series holds d^2 = a^2 + b (t-t0)^2 */
    f->qa[i] = a, f->qb[i] = b, f->qt[i] = t0;
    f->coef[i][0] = A + b * (0.5 + t0 * t0);
    f->coef[i][1] = -2 * b * t0;
    f->coef[i][2] = b / 2;
    gs__fun *g = &f->funs[i];
    g->kind = GS_FUN_CHEBYSHEV;
    g->degree = 2;
    g->squared = (uint32_t)sq;
    g->closed = closed;
    g->shift = closed ? 0.25 * (x % 3) - 0.25 : 0.0;
    g->minval = a;
    g->coef = f->coef[i];
    if (x == 5 && (k == 0 || k == 2)) { /* unreachable */
        g->minval = INFINITY;
        g->degree = 0;
        g->coef = NULL;
    }
}

static void fx_tree(fixture *f)
{
    gs__db_node nodes[5] = {{GS_NONE, 0, 0, 1, 0}, {0, 1, 1, 0, 1}, {0, 1, 1, 2, 1}, {2, 2, 3, 0, 3}, {2, 2, 3, 0, 3}};
    gs__db_curve curves[3] = {{0, 0, 50, 2.0}, {2, 1, 40, 1.5}, {2, 0, 30, 1.0}};
    uint32_t leaf[FX_NV] = {1, 1, 3, 3, 4, 4, GS_NONE};
    memcpy(f->nodes, nodes, sizeof nodes);
    memcpy(f->curves, curves, sizeof curves);
    memcpy(f->leaf, leaf, sizeof leaf);
    for (uint32_t x = 0; x < FX_NV; ++x) {
        f->xyz[3 * x] = 0.3 * x;
        f->xyz[3 * x + 1] = 0.1 * (x % 2);
        f->xyz[3 * x + 2] = 0.05 * x * x;
    }
}

static void fx_leaf_tables(fixture *f)
{
    uint32_t vs[6] = {0, 0, 2, 2, 4, 6};
    uint64_t ds[6] = {0, 0, 4, 4, 8, 12};
    memcpy(f->leaf_vstart, vs, sizeof vs);
    memcpy(f->leaf_dstart, ds, sizeof ds);
    for (uint32_t i = 0; i < 6; ++i) f->leaf_verts[i] = i;
    for (uint32_t l = 0; l < 3; ++l) { /* 1.25 x Euclidean, distinguishable */
        uint32_t x = 2 * l, y = x + 1;
        double dx = f->xyz[3 * x] - f->xyz[3 * y], dy = f->xyz[3 * x + 1] - f->xyz[3 * y + 1],
               dz = f->xyz[3 * x + 2] - f->xyz[3 * y + 2];
        double e = 1.25 * sqrt(dx * dx + dy * dy + dz * dz);
        double t[4] = {0, e, e, 0};
        memcpy(f->leaf_dist + 4 * l, t, sizeof t);
    }
}

void make_fixture(fixture *f, int leaf_exact)
{
    memset(f, 0, sizeof *f);
    fx_tree(f);
    uint64_t i = 0;
    for (uint32_t x = 0; x < FX_NV; ++x) {
        f->fun_start[x] = i;
        uint32_t nf = f->leaf[x] == GS_NONE ? 0 : f->nodes[f->leaf[x]].curve_prefix;
        for (uint32_t k = 0; k < nf; ++k, ++i) fx_quadratic(f, i, x, k, k == 1);
    }
    f->fun_start[FX_NV] = i;
    gs__db_content *c = &f->c;
    c->nv = FX_NV;
    c->xyz = f->xyz;
    c->n_nodes = 5;
    c->nodes = f->nodes;
    c->n_curves = 3;
    c->curves = f->curves;
    c->leaf = f->leaf;
    c->fun_start = f->fun_start;
    c->funs = f->funs;
    if (leaf_exact) {
        fx_leaf_tables(f);
        c->leaf_vstart = f->leaf_vstart;
        c->leaf_verts = f->leaf_verts;
        c->leaf_dstart = f->leaf_dstart;
        c->leaf_dist = f->leaf_dist;
    }
    c->method = GS_METHOD_EXACT;
    c->vmax = 2;
    c->mmax = 12;
    c->tol = 0.005;
    c->vertex_sources = 1;
    c->sample_spacing = 0.25;
    c->seed = 7;
    c->max_samples = 64;
    c->heat_time = 0.5;
    c->fmm_exact_start = 3;
    c->heat_refine = 2;
    c->avg_depth = 10.0 / 6.0;
    c->max_depth = 2;
    c->n_leaves = 3;
}

gs_db *fixture_db(fixture *f, int leaf_exact)
{
    make_fixture(f, leaf_exact);
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs__db_pack(&f->c, &db, &err);
    CHECK_MSG(rc == GS_OK, "pack: %s", err.message);
    return db;
}


void fixture_add_aliases(fixture *f)
{
    static const uint32_t start[6] = {0, 1, 3, 5, 6, 7}, alias[7] = {0, 1, 5, 2, 6, 3, 2};
    memcpy(f->alias_start, start, sizeof start);
    memcpy(f->alias, alias, sizeof alias);
    f->c.n_input = 5;
    f->c.alias_start = f->alias_start;
    f->c.alias = f->alias;
}

gs_db *fixture_db_full(fixture *f)
{
    make_fixture(f, 1);
    fixture_add_aliases(f);
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs__db_pack(&f->c, &db, &err);
    CHECK_MSG(rc == GS_OK, "pack: %s", err.message);
    return db;
}
