/* grid.c - the query cache (paper sec. 4.3, made fast): at open, every
 * vertex's separator distance functions are copied into one contiguous
 * block (quick-reject entries, then per function its shift, coefficients and
 * values tabulated on a uniform grid in the curve parameter u, a loop's
 * shift already applied, as floats), so that a query touches few cache lines
 * and finds the cell of the minimum of f_x + f_y with one vectorised pass
 * (src/fit/fun.c gs_fun_pair_min_grid). Memory only; the file stays as
 * compact as the paper's. Layout: src/db/db_internal.h (gs_qentry). */
#include "../db/db_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_PATH 1024 /* deeper trees (absurd) get no cache */

/* Visit the functions of vertex x root first: calls fn(db, x, k, curve). */
typedef void (*visit_fn)(gs_db *db, uint32_t x, uint64_t k, uint32_t curve, void *user);

static void visit(gs_db *db, uint32_t x, visit_fn fn, void *user)
{
    uint32_t l = db->leaf[x], path[MAX_PATH], n = 0;
    if (l == GS_NONE) return;
    for (uint32_t a = db->nodes[l].parent; a != GS_NONE && n < MAX_PATH; a = db->nodes[a].parent) path[n++] = a;
    while (n--) {
        const gs_db_node *a = &db->nodes[path[n]];
        for (uint32_t j = 0; j < a->n_curves; ++j) fn(db, x, a->curve_prefix + j, a->curve_start + j, user);
    }
}

/* Per curve: 1 + the largest degree of its Chebyshev functions, UINT32_MAX
 * when one is sampled, 0 when none is reachable. */
static void max_degree(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    uint32_t *deg = user;
    if (!f.coef) return;
    if (f.kind == GS_FUN_SAMPLED) deg[c] = UINT32_MAX;
    else if (deg[c] != UINT32_MAX && f.degree + 1 > deg[c]) deg[c] = f.degree + 1;
}

/* Doubles of a record: head, coefficients, grid values padded to 4 floats. */
static uint64_t record_doubles(const gs_fun *f, uint32_t g)
{
    return GS_QREC_HEAD + (uint64_t)f->degree + 1 + ((g + 3u) / 4u) * 2u;
}

typedef struct size_ctx {
    const uint32_t *curve_grid;
    uint64_t n; /* doubles of the block so far */
} size_ctx;

static void add_size(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    size_ctx *s = user;
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    if (f.coef) s->n += record_doubles(&f, s->curve_grid[c]);
}

typedef struct fill_ctx {
    const uint32_t *curve_grid;
    double *block;
    uint64_t next; /* next record, doubles from the block start */
} fill_ctx;

static void fill(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    fill_ctx *fc = user;
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    gs_qentry *e = (gs_qentry *)fc->block + k;
    const gs_db_fentry *fe = &db->funs[db->vdir[x].first_function + k];
    e->minval = fe->minval;
    e->meta = fe->meta;
    e->rec = 0;
    if (!f.coef) return; /* unreachable: never minimised */
    uint32_t g = f.kind == GS_FUN_SAMPLED ? 0 : fc->curve_grid[c];
    double *rec = fc->block + fc->next;
    e->rec = (uint32_t)fc->next;
    fc->next += record_doubles(&f, g);
    gs_fun_dip dip = {NAN, NAN, NAN};
    if (g) gs_fun_dip_find(&f, &dip);
    /* offsets as floats: pulled in by a little more than their rounding */
    float head[3] = {(float)dip.u, (float)((dip.lo - dip.u) * (1 - 1e-6)), (float)((dip.hi - dip.u) * (1 - 1e-6))};
    if (dip.u != dip.u) head[1] = head[2] = 0.0f;
    rec[0] = f.shift;
    memcpy(rec + 1, head, 4);
    memcpy((char *)(rec + 1) + 4, &g, 4);
    memcpy(rec + 2, head + 1, 8);
    memcpy(rec + GS_QREC_HEAD, f.coef, ((size_t)f.degree + 1) * sizeof *rec);
    float *v = (float *)(rec + GS_QREC_HEAD + f.degree + 1);
    for (uint32_t j = 0; j < g; ++j) {
        double u = f.closed ? -1.0 + 2.0 * j / g : -1.0 + 2.0 * j / (g - 1);
        v[j] = (float)gs_fun_value(&f, u);
    }
    for (uint32_t j = g; j < (g + 3u) / 4u * 4u; ++j) v[j] = INFINITY;
}

void gs__db_grid_free(gs_db *db)
{
    free(db->qbuf);
    free(db->qstart);
    db->qbuf = NULL;
    db->qstart = NULL;
    db->qsize = 0;
}

/* Vertex blocks start on a 64-byte line. */
#define LINE_DOUBLES 8u

int gs__db_grid_build(gs_db *db, gs_error *err)
{
    for (uint32_t x = 0; x < db->nv; ++x) /* absurdly deep trees: no cache */
        if (db->leaf[x] != GS_NONE && db->nodes[db->leaf[x]].depth >= MAX_PATH) return GS_OK;
    uint32_t *curve_grid = gs__calloc(db->n_curves ? db->n_curves : 1, sizeof *curve_grid);
    db->qstart = gs__malloc((size_t)db->nv + 1, sizeof *db->qstart);
    if (!curve_grid || !db->qstart) {
        free(curve_grid);
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "out of memory for the query cache");
    }
    for (uint32_t x = 0; x < db->nv; ++x) visit(db, x, max_degree, curve_grid);
    for (uint32_t c = 0; c < db->n_curves; ++c) {
        uint32_t d = curve_grid[c];
        curve_grid[c] = (d == 0 || d == UINT32_MAX) ? 0 : gs_fun_grid_points(d - 1);
    }
    uint64_t total = 0;
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x];
        uint64_t nf = l == GS_NONE ? 0 : db->nodes[l].curve_prefix;
        size_ctx s = {curve_grid, 2 * nf};
        visit(db, x, add_size, &s);
        if (s.n > UINT32_MAX) { /* record offsets are 32-bit: no cache */
            free(curve_grid);
            gs__db_grid_free(db);
            return GS_OK;
        }
        db->qstart[x] = total;
        total += (s.n + LINE_DOUBLES - 1) / LINE_DOUBLES * LINE_DOUBLES;
    }
    db->qstart[db->nv] = total;
    size_t bytes = (total ? total : LINE_DOUBLES) * sizeof(double);
    if (total > SIZE_MAX / 16 || !(db->qbuf = aligned_alloc(64, bytes))) {
        free(curve_grid);
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "out of memory for the query cache (%llu bytes)",
                        (unsigned long long)total * 8);
    }
    db->qsize = total;
#pragma omp parallel for schedule(dynamic, 256)
    for (uint32_t x = 0; x < db->nv; ++x) {
        uint32_t l = db->leaf[x];
        uint64_t nf = l == GS_NONE ? 0 : db->nodes[l].curve_prefix;
        fill_ctx fc = {curve_grid, db->qbuf + db->qstart[x], 2 * nf};
        visit(db, x, fill, &fc);
        uint64_t end = db->qstart[x + 1] - db->qstart[x];
        for (uint64_t i = fc.next; i < end; ++i) fc.block[i] = 0.0; /* padding */
    }
    free(curve_grid);
    return GS_OK;
}
