/* grid.c - the query cache (paper sec. 4.3, made fast): at open, every
 * vertex's separator distance functions are copied into one contiguous
 * block (quick-reject entries, then per function its shift, coefficients and
 * values tabulated on a uniform grid in the curve parameter u, a loop's
 * shift already applied, quantised to 16 bits), so that a query touches few cache lines
 * and finds the cell of the minimum of f_x + f_y with one vectorised pass
 * (src/fit/fun.c gs_fun_pair_min_grid). Memory only; the file stays as
 * compact as the paper's. Layout: src/db/db_internal.h (struct gs_db). */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#endif
#include "../db/db_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef __linux__
#include <sys/mman.h>
#endif

#define MAX_PATH 1024 /* deeper trees (absurd) get no cache */

uint64_t gs__qslot_min_bytes = GS_QSLOT_MIN_BYTES;

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

/* Doubles of a record with up to m1 coefficients and g grid points. */
static uint64_t record_doubles(uint32_t m1, uint32_t g)
{
    return GS_QREC_HEAD + gs__qrec_grid_doubles(g) + m1;
}

/* Per curve: the most coefficients (or samples) of its functions. */
static void max_coefs(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    uint32_t *m1 = user;
    if (f.coef && f.degree + 1 > m1[c]) m1[c] = f.degree + 1;
}

typedef struct fill_ctx {
    double *block, *slot;
    uint64_t nf, ns;
    uint64_t bad_k;     /* a function whose minval lies above its values */
    double bad_min, bad_u;
    int bad;
} fill_ctx;

static void fill(gs_db *db, uint32_t x, uint64_t k, uint32_t c, void *user)
{
    fill_ctx *fc = user;
    gs_fun f;
    gs__db_fun(db, x, k, &f);
    const gs_db_fentry *fe = &db->funs[db->vdir[x].first_function + k];
    int root = k < fc->ns; /* the shallow curves: records in the slot */
    /* the entry: minval rounded down to a float (a lower bound stays one) */
    float mv = fe->minval > FLT_MAX && fe->minval < INFINITY ? FLT_MAX : (float)fe->minval;
    if (mv > fe->minval) mv = nextafterf(mv, -INFINITY);
    ((float *)fc->block)[k] = mv;
    if (root) ((float *)(fc->slot + GS_QSLOT_HEAD))[k] = mv;
    if (!f.coef) return; /* unreachable: never minimised */
    uint32_t g = db->qgrid[c];
    double *rec = root ? fc->slot + gs__qrec_in_slot(db, c) : fc->block + gs__qrec_in_block(db, fc->nf, c);
    gs_fun_dip dip = {NAN, NAN, NAN, 0.0, NAN, GS_FUN_NO_CELL};
    if (g) gs_fun_dip_find(&f, &dip);
    /* the meta word with a loop's seam cell in bits the file leaves 0 */
    _Static_assert(GS_FUN_GRID_MAX < GS_QREC_NO_CELL, "a seam cell must fit below the none value");
    uint32_t cell = g && f.closed && f.kind == GS_FUN_CHEBYSHEV ? gs_fun_seam_cell(&f, g) : GS_QREC_NO_CELL;
    uint32_t meta = fe->meta | cell << GS_QREC_SEAM_SHIFT;
    /* offsets as floats from u as a float (so that the edges do not move
     * by u's rounding), pulled in by a little more than their own */
    float uf = (float)dip.u;
    float head[3] = {uf, (float)((dip.lo - uf) * (1 - 1e-6)), (float)((dip.hi - uf) * (1 - 1e-6))};
    if (dip.u != dip.u) head[1] = head[2] = 0.0f;
    rec[0] = f.shift;
    memcpy(rec + 1, head, 4);
    memcpy((char *)(rec + 1) + 4, &meta, 4);
    memcpy(rec + 2, head + 1, 8);
    /* the seam value rounded down: seam_low then searches every seam it
     * would with the exact value, and rarely one more */
    float tail[2] = {(float)dip.slope, (float)dip.seam};
    if (tail[1] > dip.seam) tail[1] = nextafterf(tail[1], -INFINITY);
    memcpy(rec + 3, tail, 8);
    double vmin = INFINITY, umin = 0.0;
    float bs[2] = {0.0f, NAN};
    if (g) gs_fun_grid_fill(&f, g, (uint16_t *)(rec + GS_QREC_HEAD), bs, bs + 1, &vmin, &umin);
    memcpy(rec + 4, bs, 8);
    rec[5] = fe->minval;
    /* the quick reject skips a curve whose minval is not below the best
     * sum found: a minval above the function's own values would silently
     * lengthen answers (the fitter's is its minimum, to ~1e-11) */
    if (!fc->bad && !(fe->minval <= vmin * (1.0 + 1e-9) + 1e-300))
        fc->bad = 1, fc->bad_k = k, fc->bad_min = vmin, fc->bad_u = umin;
    memcpy((double *)gs__qrec_coef(rec, g), f.coef, ((size_t)f.degree + 1) * sizeof *rec);
}

void gs__db_grid_free(gs_db *db)
{
    free(db->qbuf);
    free(db->qroot);
    free(db->qcoff);
    free(db->qclen);
    free(db->qgrid);
    db->qgrid = NULL;
    db->qbuf = NULL;
    db->qroot = NULL;
    db->qcoff = NULL;
    db->qclen = NULL;
    db->qsize = 0;
    db->qslot = db->qslot0 = db->qnroot = db->qlev = db->qhead = 0;
}

/* The cache's memory. Queries jump between vertex blocks at random: on
 * Linux, a cache of some megabytes is asked to live on 2 MiB pages (a TLB
 * miss per block otherwise; bunny-5k: 23 MB). The advice may be ignored.
 * Rounded up to whole 64-byte lines (aligned_alloc wants a multiple). */
#define HUGE_PAGE ((size_t)2 << 20)
static void *cache_alloc(size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes >= HUGE_PAGE) {
        size_t n = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
        void *p = aligned_alloc(HUGE_PAGE, n);
        if (p) madvise(p, n, MADV_HUGEPAGE); /* before the first touch */
        return p;
    }
#endif
    return aligned_alloc(64, (bytes + 63) / 64 * 64);
}

/* Vertex blocks start on a 64-byte line. */
#define LINE_DOUBLES 8u

/* The offsets qcoff: the records of the curves of nodes shallower than
 * db->qlev in the slot, those of deeper nodes in the block (both in
 * the order of a vertex's functions: the ancestors' first, then the node's
 * own); rsize: each curve's record size. nend[a]: where the records of
 * node a's own curves end, in the slot or in the block. Returns 0 when some
 * vertex's block or slot would exceed 32-bit offsets (no cache then). */
static int curve_offsets(gs_db *db, const uint32_t *rsize, uint64_t *nend)
{
    int ok = 1;
    for (uint32_t a = 0; a < db->n_nodes; ++a) { /* parents come first (validated) */
        const gs_db_node *n = &db->nodes[a];
        uint64_t co = n->parent != GS_NONE && n->depth != db->qlev ? nend[n->parent] : 0;
        for (uint32_t j = 0; j < n->n_curves; ++j) {
            db->qcoff[n->curve_start + j] = (uint32_t)co;
            co += rsize[n->curve_start + j];
        }
        nend[a] = co;
        if (co + gs__qent_doubles((uint64_t)n->curve_prefix + n->n_curves) + GS_QSLOT_HEAD > UINT32_MAX) ok = 0;
    }
    return ok;
}

/* x's ancestor at depth d (x's leaf when it is shallower). */
static uint32_t ancestor_at(const gs_db *db, uint32_t l, uint32_t d)
{
    while (db->nodes[l].depth > d) l = db->nodes[l].parent;
    return l;
}

int gs__db_grid_build(gs_db *db, const char *name, gs_error *err)
{
    for (uint32_t x = 0; x < db->nv; ++x) /* absurdly deep trees: no cache */
        if (db->leaf[x] != GS_NONE && db->nodes[db->leaf[x]].depth >= MAX_PATH) return GS_OK;
    size_t nc = db->n_curves ? db->n_curves : 1;
    uint32_t *m1 = gs__calloc(nc, sizeof *m1);
    uint32_t *curve_grid = db->qgrid = gs__calloc(nc, sizeof *db->qgrid); /* the database's from here */
    uint64_t *nend = gs__malloc(db->n_nodes, sizeof *nend);
    db->qcoff = gs__calloc(nc, sizeof *db->qcoff);
    db->qclen = gs__calloc(nc, sizeof *db->qclen);
    int ok = curve_grid && m1 && nend && db->qcoff && db->qclen;
    if (ok) {
        for (uint32_t x = 0; x < db->nv; ++x) visit(db, x, max_degree, curve_grid), visit(db, x, max_coefs, m1);
        for (uint32_t c = 0; c < db->n_curves; ++c) {
            uint32_t d = curve_grid[c];
            curve_grid[c] = (d == 0 || d == UINT32_MAX) ? 0 : gs_fun_grid_points(d - 1);
            m1[c] = (uint32_t)record_doubles(m1[c], curve_grid[c]); /* now: record size */
            db->qclen[c] = m1[c];
        }
        db->qlev = 0;
        int r = curve_offsets(db, m1, nend);
        if (r > 0) { /* a large cache gets slots with the curves of depths 0 and 1 */
            uint64_t t = 0;
            for (uint32_t x = 0; x < db->nv; ++x) {
                uint32_t l = db->leaf[x];
                if (l != GS_NONE && db->nodes[l].curve_prefix)
                    t += gs__qent_doubles(db->nodes[l].curve_prefix) + nend[db->nodes[l].parent] + LINE_DOUBLES;
            }
            if (t * sizeof(double) > gs__qslot_min_bytes) db->qlev = GS_QSLOT_LEVELS, r = curve_offsets(db, m1, nend);
        }
        if (r <= 0) {
            free(m1), free(nend);
            gs__db_grid_free(db);
            return r < 0 ? gs__fail(err, GS_ENOMEM, "%s: out of memory for the query cache", name) : GS_OK;
        }
    }
    if (!ok) {
        free(m1), free(nend);
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "%s: out of memory for the query cache", name);
    }
    /* the slot: header, room for the most shallow entries, then the most
     * shallow records */
    uint64_t nsmax = 0, recmax = 0;
    for (uint32_t a = 0; a < db->n_nodes; ++a)
        if (db->nodes[a].depth < db->qlev) {
            uint64_t ns = db->nodes[a].curve_prefix + (uint64_t)db->nodes[a].n_curves;
            nsmax = ns > nsmax ? ns : nsmax;
            recmax = nend[a] > recmax ? nend[a] : recmax;
        }
    uint64_t slot = GS_QSLOT_HEAD + gs__qent_doubles(nsmax) + recmax;
    slot = (slot + LINE_DOUBLES - 1) / LINE_DOUBLES * LINE_DOUBLES;
    if (!db->qlev) slot = 2; /* a small cache: start, leaf and nf only (16 bytes: they stay in cache) */
    else if (slot / LINE_DOUBLES % 2 == 0) slot += LINE_DOUBLES; /* an odd number of lines: slots do not all */
                                                            /* fall in the same cache sets (2 KB apart) */
    db->qnroot = (uint32_t)nsmax;
    uint64_t total = 0;
    int big = slot > UINT32_MAX || (db->nv + 1ull) * slot > SIZE_MAX / 16;
    if (!big) db->qroot = cache_alloc((db->nv + 1ull) * slot * sizeof(double));
    if (db->qroot) {
        db->qslot = (uint32_t)slot;
        db->qslot0 = db->qlev ? (uint32_t)(GS_QSLOT_HEAD + gs__qent_doubles(nsmax) + (db->n_nodes ? nend[0] : 0)) : (uint32_t)slot;
        for (uint32_t x = 0; x <= db->nv; ++x) {
            uint32_t l = x < db->nv ? db->leaf[x] : GS_NONE;
            uint64_t n = 0;
            gs_qvert *h = (gs_qvert *)(db->qroot + x * slot);
            h->start = total;
            h->leaf = l;
            h->nf = l == GS_NONE ? 0 : db->nodes[l].curve_prefix;
            if (h->nf) { /* entries, then the deep records up to the last one's end */
                uint32_t p = db->nodes[l].parent;
                n = gs__qent_doubles(h->nf) + (db->nodes[p].depth >= db->qlev ? nend[p] : 0);
            }
            if (db->qlev) { /* a large cache: ns and the ancestors too */
                h->ns = l == GS_NONE ? 0 : db->nodes[ancestor_at(db, l, db->qlev)].curve_prefix;
                for (uint32_t d = 0; d < GS_QANC; ++d) h->anc[d] = GS_NONE;
                for (uint32_t a = l; a != GS_NONE; a = db->nodes[a].parent)
                    if (db->nodes[a].depth < GS_QANC) h->anc[db->nodes[a].depth] = a;
            }
            total += (n + LINE_DOUBLES - 1) / LINE_DOUBLES * LINE_DOUBLES;
        }
    }
    free(m1), free(nend);
    size_t bytes = (total ? total : LINE_DOUBLES) * sizeof(double);
    if (!db->qroot || total > SIZE_MAX / 16 || !(db->qbuf = cache_alloc(bytes))) {
        gs__db_grid_free(db);
        return gs__fail(err, GS_ENOMEM, "%s: out of memory for the query cache (%llu + %llu bytes)", name,
                        (unsigned long long)total * 8, (unsigned long long)((db->nv + 1ull) * slot * 8));
    }
    db->qsize = total;
    db->qhead = !db->qlev && db->nodes[0].n_curves ? db->qclen[db->nodes[0].curve_start] : 0;
    uint32_t bad_x = UINT32_MAX;
    uint64_t bad_k = 0;
    double bad_min = 0.0, bad_u = 0.0;
#pragma omp parallel for schedule(dynamic, 256)
    for (uint32_t x = 0; x < db->nv; ++x) {
        double *sl = db->qroot + (size_t)x * slot;
        double *block = db->qbuf + ((gs_qvert *)sl)->start;
        uint64_t n = ((gs_qvert *)(sl + slot))->start - ((gs_qvert *)sl)->start;
        memset(block, 0, n * sizeof *block); /* padding and unused room */
        if (db->qlev) {
            memset(sl + GS_QSLOT_XYZ, 0, (slot - GS_QSLOT_XYZ) * sizeof *sl);
            memcpy(sl + GS_QSLOT_XYZ, db->xyz + 3 * (size_t)x, 3 * sizeof *sl);
        }
        const gs_qvert *h = (const gs_qvert *)sl;
        fill_ctx fc = {block, sl, h->nf, db->qlev ? h->ns : 0, 0, 0.0, 0.0, 0};
        visit(db, x, fill, &fc);
        if (fc.bad) {
#pragma omp critical(gs_grid_bad)
            if (x < bad_x) bad_x = x, bad_k = fc.bad_k, bad_min = fc.bad_min, bad_u = fc.bad_u;
        }
    }
    if (bad_x != UINT32_MAX) { /* the lowest such vertex: the same message for any thread count */
        double mv = db->funs[db->vdir[bad_x].first_function + bad_k].minval;
        gs__db_grid_free(db);
        return gs__fail(err, GS_EPARSE,
                        "%s: section 'functions': vertex %u, function %llu: minval %.17g is above the function's "
                        "value %.17g at u = %.6f (the quick reject would skip it)",
                        name, bad_x, (unsigned long long)bad_k, mv, bad_min, bad_u);
    }
    return GS_OK;
}
