/* grid.c - the query cache (paper sec. 4.3, made fast): at open, every
 * separator distance function is tabulated on a uniform grid in its curve's
 * parameter u (a loop's shift already applied), as floats, so that a query
 * finds the cell of the minimum of f_x + f_y with one vectorised pass and
 * only refines it (src/fit/fun.c gs_fun_pair_min_grid). Memory only; the
 * file stays as compact as the paper's. */
#include "../db/db_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Visit the functions of vertex x root first: calls fn(db, x, k, curve). */
typedef void (*visit_fn)(gs_db *db, uint32_t x, uint64_t k, uint32_t curve, void *user);

static void visit(gs_db *db, uint32_t x, visit_fn fn, void *user)
{
    uint32_t l = db->leaf[x], path[1024], n = 0;
    if (l == GS_NONE) return;
    for (uint32_t a = db->nodes[l].parent; a != GS_NONE && n < 1024; a = db->nodes[a].parent) path[n++] = a;
    while (n--) {
        const gs_db_node *a = &db->nodes[path[n]];
        for (uint32_t j = 0; j < a->n_curves; ++j) fn(db, x, a->curve_prefix + j, a->curve_start + j, user);
    }
}

static void max_degree(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    uint32_t *deg = user;
    if (f.kind == GS_FUN_SAMPLED) deg[c] = UINT32_MAX;
    else if (deg[c] != UINT32_MAX && f.degree + 1 > deg[c]) deg[c] = f.degree + 1;
}

typedef struct fill_ctx {
    uint64_t next;
} fill_ctx;

static void assign(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    fill_ctx *fc = user;
    db->grid_start[db->vdir[x].first_function + k] = fc->next;
    fc->next += db->curve_grid[c];
}

static void tabulate(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    (void)user;
    uint32_t g = db->curve_grid[c];
    if (!g) return;
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    uint64_t fid = db->vdir[x].first_function + k;
    float *v = db->grid + db->grid_start[fid];
    double um = NAN; /* only a sharp function's own minimiser is ever used */
    if (gs_fun_is_sharp(&f)) gs_fun_min(&f, &um);
    db->umin[fid] = (float)um;
    int closed = db->curves[c].closed != 0;
    for (uint32_t j = 0; j < g; ++j) {
        double u = closed ? -1.0 + 2.0 * j / g : -1.0 + 2.0 * j / (g - 1);
        v[j] = (float)gs_fun_value(&f, u);
    }
}

void gs__db_grid_free(gs_db *db)
{
    free(db->grid);
    free(db->grid_start);
    free(db->curve_grid);
    free(db->umin);
    db->umin = NULL;
    db->grid = NULL;
    db->grid_start = NULL;
    db->curve_grid = NULL;
}

int gs__db_grid_build(gs_db *db, gs_error *err)
{
    for (uint32_t x = 0; x < db->nv; ++x) /* absurdly deep trees: no cache */
        if (db->leaf[x] != GS_NONE && db->nodes[db->leaf[x]].depth >= 1024) return GS_OK;
    db->curve_grid = gs__calloc(db->n_curves ? db->n_curves : 1, sizeof *db->curve_grid);
    db->grid_start = gs__malloc(db->n_functions ? db->n_functions : 1, sizeof *db->grid_start);
    db->umin = gs__malloc(db->n_functions ? db->n_functions : 1, sizeof *db->umin);
    if (!db->curve_grid || !db->grid_start || !db->umin) {
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "out of memory for the query cache");
    }
    for (uint32_t x = 0; x < db->nv; ++x) visit(db, x, max_degree, db->curve_grid);
    for (uint32_t c = 0; c < db->n_curves; ++c) {
        uint32_t d = db->curve_grid[c];
        db->curve_grid[c] = (d == 0 || d == UINT32_MAX) ? 0 : gs_fun_grid_points(d - 1);
    }
    fill_ctx fc = {0};
    for (uint32_t x = 0; x < db->nv; ++x) visit(db, x, assign, &fc);
    db->grid = gs__malloc(fc.next ? fc.next : 1, sizeof *db->grid);
    if (!db->grid) {
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "out of memory for the query cache (%llu values)",
                        (unsigned long long)fc.next);
    }
#pragma omp parallel for schedule(dynamic, 256)
    for (uint32_t x = 0; x < db->nv; ++x) visit(db, x, tabulate, NULL);
    return GS_OK;
}
