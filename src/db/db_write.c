/* db_write.c - the database writer: packs a gs__db_content (paper sec. 3.1)
 * into format version 6 (doc/database-format.md) and attaches the bytes;
 * the atomic save. Each function is stored compactly: integer coefficients
 * against the coarsest power-of-two step that keeps the stored function
 * within GS__DB_QREL of its minimum (int16 leading ones, int8 tail; else
 * float32), its minimum as a u16 code rounded down below the stored
 * function, and for a sharp dip (a vertex near the curve) the dip the
 * query's minimiser starts from. */
#include "db_internal.h"
#include "../io/atomic_file.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Integer coefficients when the stored function then differs from the
 * fitted one by at most this much relative to its minimum (a third of the
 * tightest fit tolerance, the default tol 0.003 at the root; measured over
 * all vertex pairs of bunny-5k and spot with the coarsest such step: ME,
 * RMSE, p99.9 and max unchanged to the digits of doc/accuracy.md), else
 * float32 coefficients. */
#define GS__DB_QREL 1e-3

/* ---- one function ---------------------------------------------------- */

/* A float at most v (v finite or +inf). */
static float float_below(double v)
{
    if (v > FLT_MAX) return v == INFINITY ? INFINITY : FLT_MAX;
    float f = (float)v;
    if (f > v) f = nextafterf(f, -INFINITY);
    return f;
}

/* The coarsest power-of-two step 2^*e at which c[0..m], rounded to
 * integers q_k (|q_k| <= 32767), have a sum of absolute errors <= tol, the
 * stored function then within tol of the fitted one everywhere; *w: 1 +
 * the last k with |q_k| > 127 (the int16 ones; the rest take a byte).
 * Returns 0 when no step in the exponent range meets tol. */
static int quantise(const double *c, uint32_t m, double tol, int16_t *q, int *e, uint32_t *w)
{
    double a = 0.0;
    for (uint32_t k = 0; k <= m; ++k) a = fabs(c[k]) > a ? fabs(c[k]) : a;
    int ex = GS__FB_EXP_MIN, found = 0;
    if (a > 0.0) {
        int t;
        frexp(a / 32767.0, &t); /* a / 32767 < 2^t */
        ex = t < GS__FB_EXP_MIN ? GS__FB_EXP_MIN : t;
    }
    int16_t r16[GS_FUN_MAX_DEGREE + 1];
    for (; ex <= GS__FB_EXP_MAX; ++ex) {
        double s = ldexp(1.0, ex), err = 0.0;
        int ok = 1;
        for (uint32_t k = 0; k <= m && ok; ++k) {
            double r = nearbyint(c[k] / s);
            if (fabs(r) > 32767.0) ok = 0;
            else r16[k] = (int16_t)r, err += fabs(r * s - c[k]);
        }
        if (!ok) continue;
        if (!(err <= tol)) break;
        found = 1, *e = ex;
        memcpy(q, r16, sizeof *q * (m + 1));
    }
    if (!found) return 0;
    *w = 0;
    for (uint32_t k = 0; k <= m; ++k)
        if (q[k] > 127 || q[k] < -127) *w = k + 1;
    return 1;
}

/* Encode f into out (NULL: only the size); *entry receives its minimum as
 * stored; *numbers adds the numbers it costs (coefficients and a loop's
 * shift, as Table 1 counts). g: its curve's grid (0: none). Returns the
 * block's size in bytes (0: unreachable, no block). */
static uint32_t encode(const gs__fun *f, uint32_t g, unsigned char *out, uint16_t *entry, uint64_t *numbers, int *bad)
{
    if (!f->coef || !(f->minval < INFINITY)) {
        *entry = GS__DB_MIN_INF;
        return 0;
    }
    uint32_t m = f->degree, sampled = f->kind == GS_FUN_SAMPLED, w = 0;
    unsigned char head[24];
    uint32_t n = 2;
    double dec[GS_FUN_MAX_DEGREE + 1];
    int16_t q[GS_FUN_MAX_DEGREE + 1];
    int e = GS__FB_F32;
    float shift = (float)(f->closed ? f->shift : 0.0);
    gs__fun fd = *f;
    fd.shift = shift;
    float dip[4] = {0};
    int has_dip = 0;
    if (sampled) {
        float lo = INFINITY;
        for (uint32_t k = 0; k <= m; ++k) {
            if (!(fabs(f->coef[k]) <= 1e30)) *bad = 1;
            float v = (float)f->coef[k];
            lo = v < lo ? v : lo;
        }
        *entry = gs__db_min_encode(float_below(lo < f->minval ? lo : f->minval));
    } else {
        double mv = f->minval;
        int ok16 = mv > 0.0 && quantise(f->coef, m, f->squared ? GS__DB_QREL * 2.0 * mv * mv : GS__DB_QREL * mv, q,
                                        &e, &w);
        if (!ok16) e = GS__FB_F32, w = 0;
        for (uint32_t k = 0; k <= m && !ok16; ++k)
            if (!(fabs(f->coef[k]) <= 1e30)) *bad = 1; /* beyond what float32 blocks may hold */
        for (uint32_t k = 0; k <= m; ++k) dec[k] = ok16 ? q[k] * ldexp(1.0, e) : (double)(float)f->coef[k];
        fd.coef = dec;
        /* the stored function's own minimum, a little lower, rounded down
         * to the stored 16-bit minimum: the quick reject's bound stays a
         * bound */
        double lo = gs__fun_min(&fd, NULL);
        lo = lo < f->minval ? lo : f->minval;
        lo = lo > 0.0 ? lo * (1.0 - 1e-7) : lo;
        *entry = gs__db_min_encode(lo);
        fd.minval = gs__db_min_value(*entry);
        if (g && gs__fun_is_sharp(&fd)) {
            gs__fun_dip d;
            gs__fun_dip_find(&fd, &d);
            if (d.u == d.u) {
                /* offsets from u as a float, pulled in a little (as the
                 * edges must not move by u's rounding) */
                float uf = (float)d.u;
                dip[0] = uf;
                dip[1] = (float)((d.lo - uf) * (1 - 1e-6));
                dip[2] = (float)((d.hi - uf) * (1 - 1e-6));
                dip[3] = (float)d.slope;
                has_dip = 1;
            }
        }
    }
    head[0] = (unsigned char)((sampled ? GS__FB_SAMPLED : m) | (f->squared && !sampled ? GS__FB_SQUARED : 0) |
                              (f->closed ? GS__FB_CLOSED : 0) | (has_dip ? GS__FB_DIP : 0));
    head[1] = (unsigned char)(signed char)e;
    if (sampled) {
        uint16_t mm = (uint16_t)m;
        memcpy(head + 2, &mm, 2);
        n = 4;
    } else if (e != GS__FB_F32) {
        head[2] = (unsigned char)w;
        n = 3;
    }
    if (f->closed) memcpy(head + n, &shift, 4), n += 4;
    if (has_dip) memcpy(head + n, dip, 16), n += 16;
    uint32_t cb = e == GS__FB_F32 ? 4 * (m + 1) : m + 1 + w;
    *numbers += m + 1 + (f->closed ? 1u : 0u);
    if (out) {
        memcpy(out, head, n);
        for (uint32_t k = 0; k <= m; ++k) {
            if (e == GS__FB_F32) {
                float v = (float)f->coef[k];
                memcpy(out + n + 4 * k, &v, 4);
            } else if (k < w) {
                memcpy(out + n + 2 * k, &q[k], 2);
            } else {
                out[n + w + k] = (unsigned char)(signed char)q[k];
            }
        }
    }
    return n + cb;
}

/* ---- records ------------------------------------------------------------ */

/* Vertex x's record into out (NULL: only its size, in bytes, a multiple of
 * GS__DB_RECORD_UNIT). */
static uint64_t encode_vertex(const gs__db_content *c, const uint32_t *grid, const uint32_t *fcurve, uint32_t x,
                              unsigned char *out, uint64_t *numbers, int *bad)
{
    uint64_t k0 = c->fun_start[x], nf = c->fun_start[x + 1] - k0, at = GS__DB_MIN_BYTES * nf;
    for (uint64_t k = 0; k < nf; ++k) {
        uint16_t entry;
        uint32_t g = grid[fcurve[k0 + k]] ? gs__fun_grid_points(grid[fcurve[k0 + k]] - 1) : 0;
        uint32_t b = encode(&c->funs[k0 + k], g, out ? out + at : NULL, &entry, numbers, bad);
        if (out) memcpy(out + GS__DB_MIN_BYTES * k, &entry, 2);
        at += b;
    }
    return (at + GS__DB_RECORD_UNIT - 1) / GS__DB_RECORD_UNIT * GS__DB_RECORD_UNIT;
}

/* The curve of every function (fcurve) and each curve's degree1: 1 + the
 * highest degree of its Chebyshev functions, 0 when one is sampled or none
 * is reachable. */
static int curve_grids(const gs__db_content *c, uint32_t *grid, uint32_t *fcurve, gs_error *err)
{
    uint32_t *path = gs__malloc((size_t)c->n_nodes + 1, sizeof *path);
    uint32_t *deg = gs__calloc((size_t)c->n_curves + 1, sizeof *deg);
    if (!path || !deg) {
        free(path), free(deg);
        return gs__fail(err, GS_ENOMEM, "database: out of memory");
    }
    for (uint32_t x = 0; x < c->nv; ++x) {
        uint32_t l = c->leaf[x], n = 0;
        if (l == GS_NONE) continue;
        for (uint32_t a = c->nodes[l].parent; a != GS_NONE && n < c->n_nodes; a = c->nodes[a].parent) path[n++] = a;
        uint64_t k = c->fun_start[x];
        while (n--) {
            const gs__db_node *a = &c->nodes[path[n]];
            for (uint32_t j = 0; j < a->n_curves && k < c->fun_start[x + 1]; ++j, ++k) {
                uint32_t cv = a->curve_start + j;
                const gs__fun *f = &c->funs[k];
                fcurve[k] = cv;
                if (!f->coef || !(f->minval < INFINITY)) continue;
                if (f->kind == GS_FUN_SAMPLED) deg[cv] = UINT32_MAX;
                else if (deg[cv] != UINT32_MAX && f->degree + 1 > deg[cv]) deg[cv] = f->degree + 1;
            }
        }
    }
    for (uint32_t j = 0; j < c->n_curves; ++j)
        grid[j] = deg[j] == UINT32_MAX ? 0 : deg[j];
    free(path), free(deg);
    return GS_OK;
}

static void write_header(unsigned char *b, const gs__db_content *c, uint32_t n_sec, uint64_t file_bytes,
                         const gs__db_counts *cn, uint64_t numbers)
{
    memcpy(b, GS__DB_MAGIC, 8);
    gs__put32(b + GS__H_VERSION, GS__DB_VERSION);
    gs__put32(b + GS__H_ENDIAN, GS__DB_ENDIAN_TAG);
    gs__put32(b + GS__H_FLAGS, cn->flags);
    gs__put32(b + GS__H_HEADER_BYTES, GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * n_sec);
    gs__put64(b + GS__H_FILE_BYTES, file_bytes);
    gs__put32(b + GS__H_NV, c->nv);
    gs__put32(b + GS__H_NODES, c->n_nodes);
    gs__put32(b + GS__H_CURVES, c->n_curves);
    gs__put32(b + GS__H_LEAVES, c->n_leaves);
    gs__put64(b + GS__H_FUNCTIONS, c->fun_start[c->nv]);
    gs__put64(b + GS__H_RECORDS_BYTES, cn->records_bytes);
    gs__put32(b + GS__H_SECTIONS, n_sec);
    gs__put32(b + GS__H_MAX_DEPTH, c->max_depth);
    gs__putf64(b + GS__H_AVG_DEPTH, c->avg_depth);
    gs__put32(b + GS__H_METHOD, c->method);
    gs__put32(b + GS__H_VMAX, c->vmax);
    gs__put32(b + GS__H_MMAX, c->mmax);
    gs__put32(b + GS__H_BUILD_FLAGS,
              (c->vertex_sources ? GS__DB_BUILD_VERTEX_SOURCES : 0) | (c->sampled ? GS__DB_BUILD_SAMPLED : 0) |
                  ((c->heat_refine << GS__DB_BUILD_HEAT_REFINE_SHIFT) & GS__DB_BUILD_HEAT_REFINE_MASK));
    gs__putf64(b + GS__H_TOL, c->tol);
    gs__put64(b + GS__H_LEAF_ENTRIES, cn->leaf_entries);
    /* Table 1 counts what describes the functions: coefficients and loop
     * shifts; minima and block heads are index overhead (bytes/vertex). */
    gs__putf64(b + GS__H_COST, c->nv ? (double)numbers / c->nv : 0.0);
    gs__putf64(b + GS__H_SPACING, c->sample_spacing);
    gs__put32(b + GS__H_SEED, c->seed);
    gs__put32(b + GS__H_MAX_SAMPLES, c->max_samples);
    gs__putf64(b + GS__H_HEAT_TIME, c->heat_time);
    gs__putf64(b + GS__H_FMM_START, c->fmm_exact_start);
    gs__putf64(b + GS__H_DGG_EPS, c->method == GS_METHOD_DGG ? c->dgg_eps : 0.0);
    if (cn->flags & GS__DB_FLAG_ALIASES) {
        gs__put32(b + GS__H_N_INPUT, c->n_input);
        gs__put32(b + GS__H_ALIAS_EXCEPTIONS, cn->alias_exceptions);
        gs__put64(b + GS__H_ALIAS_ENTRIES, cn->alias_entries);
    }
}

static void write_tree(unsigned char *const sec[], const gs__db_content *c, const uint32_t *grid)
{
    memcpy(sec[GS__SEC_POSITIONS], c->xyz, 24 * (size_t)c->nv);
    memcpy(sec[GS__SEC_LEAVES], c->leaf, 4 * (size_t)c->nv);
    for (uint32_t i = 0; i < c->n_nodes; ++i) memcpy(sec[GS__SEC_NODES] + 20 * (uint64_t)i, &c->nodes[i], 20);
    for (uint32_t j = 0; j < c->n_curves; ++j) {
        gs__db_disk_curve d = {c->curves[j].node, c->curves[j].closed, c->curves[j].n_samples, grid[j],
                              c->curves[j].length};
        memcpy(sec[GS__SEC_CURVES] + 24 * (uint64_t)j, &d, 24);
    }
}

/* ---- leaf tables: the upper triangle in 16 bits against a per-leaf scale */

/* A float at least v >= 0 (finite). */
static float float_above(double v)
{
    float f = (float)v;
    if (f < v) f = nextafterf(f, INFINITY);
    return f;
}

/* Check the builder's tables and size them: entries over all leaves, and
 * whether a leaf has more than 256 vertices (16-bit local numbers). */
static int leaf_plan(const gs__db_content *c, uint64_t *entries, int *local16, gs_error *err)
{
    uint64_t q = 0;
    uint32_t nmax = 0;
    for (uint32_t l = 0; l < c->n_nodes; ++l) {
        if (c->leaf_vstart[l + 1] < c->leaf_vstart[l] || c->leaf_vstart[l + 1] > c->nv)
            return gs__fail(err, GS_EINTERNAL, "database: leaf table ranges out of order at node %u", l);
        uint32_t n = c->leaf_vstart[l + 1] - c->leaf_vstart[l];
        if (c->leaf_dstart[l + 1] - c->leaf_dstart[l] != (uint64_t)n * n)
            return gs__fail(err, GS_EINTERNAL, "database: node %u's leaf table is not %u x %u", l, n, n);
        const double *t = c->leaf_dist + c->leaf_dstart[l];
        for (uint32_t k = c->leaf_vstart[l]; k < c->leaf_vstart[l + 1]; ++k)
            if (c->leaf_verts[k] >= c->nv)
                return gs__fail(err, GS_EINTERNAL, "database: leaf %u lists vertex %u (n_vertices %u)", l,
                                c->leaf_verts[k], c->nv);
        for (uint64_t i = 0; i < n; ++i)
            for (uint64_t j = i + 1; j < n; ++j)
                if (!(t[i * n + j] >= 0 && (t[i * n + j] <= GS__DB_LEAF_MAX_SCALE || t[i * n + j] == INFINITY)))
                    return gs__fail(err, GS_ELIMIT, "database: leaf %u: exact distance %g (must be in [0, 1e30] or inf)",
                                    l, t[i * n + j]);
        nmax = n > nmax ? n : nmax;
        q += gs__db_leaf_tri(n);
    }
    if (nmax > 65536)
        return gs__fail(err, GS_ELIMIT, "database: a leaf of %u vertices (leaf tables hold at most 65536; lower vmax)",
                        nmax);
    *entries = q;
    *local16 = nmax > 256;
    return GS_OK;
}

/* The excess of leaf distance t[i n + j] over the straight segment between
 * the two vertices (0 if rounding put it below; inf stays inf). */
static double leaf_excess(const gs__db_content *c, const uint32_t *verts, const double *t, uint64_t n, uint64_t i,
                          uint64_t j)
{
    double d = t[i * n + j];
    if (d == INFINITY) return d;
    double e = gs__db_segment(c->xyz + 3 * (size_t)verts[i], c->xyz + 3 * (size_t)verts[j]);
    return d > e ? d - e : 0.0;
}

/* Each leaf's scale s (its largest finite excess over the straight
 * segment, as a float rounded up) and its upper triangle as q = round(QMAX
 * excess / s) (QINF: +inf); each vertex's number in its leaf. Storing the
 * excess makes a flat or straight pair exact and shrinks the step to the
 * leaf's largest detour (bunny-5k: the largest distance is several times
 * it). */
static void write_leaf_tables(unsigned char *const sec[], const gs__db_content *c, int local16)
{
    uint64_t qstart = 0;
    uint16_t *qv = (uint16_t *)(void *)sec[GS__SEC_LEAF_Q];
    for (uint32_t l = 0; l < c->n_nodes; ++l) {
        uint32_t n = c->leaf_vstart[l + 1] - c->leaf_vstart[l];
        const uint32_t *verts = c->leaf_verts + c->leaf_vstart[l];
        const double *t = c->leaf_dist + c->leaf_dstart[l];
        double top = 0.0;
        for (uint64_t i = 0; i < n; ++i)
            for (uint64_t j = i + 1; j < n; ++j) {
                double x = leaf_excess(c, verts, t, n, i, j);
                if (x < INFINITY && x > top) top = x;
            }
        gs__db_leaf_node ln = {qstart, n, float_above(top)};
        memcpy(sec[GS__SEC_LEAF_NODES] + 16 * (uint64_t)l, &ln, 16);
        double s = ln.scale;
        for (uint64_t i = 0; i < n; ++i)
            for (uint64_t j = i + 1; j < n; ++j) {
                double x = leaf_excess(c, verts, t, n, i, j), r = s > 0 ? nearbyint(GS__DB_LEAF_QMAX * (x / s)) : 0.0;
                qv[qstart + gs__db_leaf_at(n, i, j)] =
                    x == INFINITY ? (uint16_t)GS__DB_LEAF_QINF : (uint16_t)(r > GS__DB_LEAF_QMAX ? GS__DB_LEAF_QMAX : r);
            }
        qstart += gs__db_leaf_tri(n);
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t x = verts[k];
            if (x >= c->nv) continue;
            if (local16) gs__put16(sec[GS__SEC_LEAF_LOCAL] + 2 * (uint64_t)x, (uint16_t)k);
            else sec[GS__SEC_LEAF_LOCAL][x] = (unsigned char)k;
        }
    }
}

/* ---- input-id aliases: the lists other than {v} ------------------------- */

static int alias_is_plain(const gs__db_content *c, uint32_t v)
{
    return c->alias_start[v + 1] - c->alias_start[v] == 1 && c->alias[c->alias_start[v]] == v;
}

static int alias_plan(const gs__db_content *c, uint32_t *exceptions, uint64_t *entries, gs_error *err)
{
    if (c->n_input > c->nv || !c->alias_start || !c->alias)
        return gs__fail(err, GS_EARG, "database: %u input vertices for %u vertices", c->n_input, c->nv);
    uint64_t e = 0;
    uint32_t k = 0;
    for (uint32_t v = 0; v < c->n_input; ++v) {
        if (c->alias_start[v + 1] <= c->alias_start[v])
            return gs__fail(err, GS_EARG, "database: input vertex %u has no alias", v);
        for (uint32_t i = c->alias_start[v]; i < c->alias_start[v + 1]; ++i)
            if (c->alias[i] >= c->nv)
                return gs__fail(err, GS_EARG, "database: input vertex %u's alias %u >= n_vertices %u", v, c->alias[i],
                                c->nv);
        if (alias_is_plain(c, v)) continue;
        ++k;
        e += c->alias_start[v + 1] - c->alias_start[v];
    }
    if (e > UINT32_MAX) return gs__fail(err, GS_ELIMIT, "database: %llu aliases", (unsigned long long)e);
    *exceptions = k;
    *entries = e;
    return GS_OK;
}

static void write_aliases(unsigned char *const sec[], const gs__db_content *c)
{
    unsigned char *h = sec[GS__SEC_ALIAS_INDEX];
    uint32_t *list = (uint32_t *)(void *)sec[GS__SEC_ALIAS_LIST];
    uint32_t at = 0;
    for (uint32_t v = 0; v < c->n_input; ++v) {
        if (alias_is_plain(c, v)) continue;
        gs__put32(h, v);
        gs__put32(h + 4, at);
        h += 8;
        for (uint32_t i = c->alias_start[v]; i < c->alias_start[v + 1]; ++i) list[at++] = c->alias[i];
    }
    gs__put32(h, c->n_input);
    gs__put32(h + 4, at);
}

static void write_table(unsigned char *buf, unsigned char *const sec[], const uint64_t size[], const uint32_t *ids,
                        uint32_t n_sec)
{
    unsigned char *t = buf + GS__DB_HEADER_BYTES;
    for (uint32_t e = 0; e < n_sec; ++e, t += GS__DB_ENTRY_BYTES) {
        uint32_t s = ids[e];
        gs__put32(t, s);
        gs__put32(t + 4, 0);
        gs__put64(t + 8, (uint64_t)(sec[s] - buf));
        gs__put64(t + 16, size[s]);
        gs__put64(t + 24, gs__db_checksum(sec[s], size[s], NULL, 0));
    }
    gs__put64(buf + GS__DB_CHECKSUM_AT,
              gs__db_checksum(buf, GS__DB_CHECKSUM_AT, buf + GS__DB_HEADER_BYTES, GS__DB_ENTRY_BYTES * n_sec));
}

int gs__db_pack(const gs__db_content *c, gs_db **out, gs_error *err)
{
    if (!c || !out || !c->fun_start || (c->nv && (!c->xyz || !c->leaf)) || !c->nodes)
        return gs__fail(err, GS_EARG, "gs__db_pack: missing content");
    *out = NULL;
    if (c->heat_refine > GS__DB_BUILD_HEAT_REFINE_MASK >> GS__DB_BUILD_HEAT_REFINE_SHIFT)
        return gs__fail(err, GS_EARG, "gs__db_pack: heat_refine %u does not fit the header", c->heat_refine);
    if (!gs__db_host_little_endian())
        return gs__fail(err, GS_EFORMAT, "database: big-endian hosts are not supported");
    int tables = c->leaf_dist && c->leaf_vstart && c->leaf_verts && c->leaf_dstart;
    uint64_t nfun = c->fun_start[c->nv];
    uint32_t *grid = gs__calloc((size_t)c->n_curves + 1, sizeof *grid);
    uint32_t *fcurve = gs__calloc(nfun + 1, sizeof *fcurve);
    uint32_t *index = gs__malloc((size_t)c->nv + 1, sizeof *index);
    uint64_t *rsize = gs__malloc((size_t)c->nv + 1, sizeof *rsize);
    int rc = grid && fcurve && index && rsize ? GS_OK : gs__fail(err, GS_ENOMEM, "database: out of memory");
    if (!rc) rc = curve_grids(c, grid, fcurve, err);
    uint64_t numbers = 0, records = 0;
    int bad = 0;
    if (!rc) {
#pragma omp parallel for schedule(dynamic, 512) reduction(+ : numbers) reduction(| : bad)
        for (uint32_t x = 0; x < c->nv; ++x) rsize[x] = encode_vertex(c, grid, fcurve, x, NULL, &numbers, &bad);
        if (bad) rc = gs__fail(err, GS_ELIMIT, "database: a function's coefficients exceed 1e30 or are not finite");
        for (uint32_t x = 0; x < c->nv && !rc; ++x) {
            index[x] = (uint32_t)(records / GS__DB_RECORD_UNIT);
            records += rsize[x];
            if (records > GS__DB_MAX_RECORDS_BYTES - 8)
                rc = gs__fail(err, GS_ELIMIT, "database: the records exceed %llu bytes (format limit)",
                              (unsigned long long)GS__DB_MAX_RECORDS_BYTES);
        }
        index[c->nv] = (uint32_t)(records / GS__DB_RECORD_UNIT);
        records = gs__pad8(records); /* the section: zero bytes to a multiple of 8 */
    }
    gs__db_counts cn = {0, c->nv, c->n_nodes, c->n_curves, records, 0, 0, 0};
    int local16 = 0;
    if (!rc && tables && !(rc = leaf_plan(c, &cn.leaf_entries, &local16, err)))
        cn.flags |= GS__DB_FLAG_LEAF_EXACT | (local16 ? GS__DB_FLAG_LEAF_LOCAL16 : 0);
    if (!rc && c->n_input && !(rc = alias_plan(c, &cn.alias_exceptions, &cn.alias_entries, err)))
        cn.flags |= GS__DB_FLAG_ALIASES;
    if (c->near_radius > 0) cn.flags |= GS__DB_FLAG_NEAR;
    uint64_t size[GS__SEC_MAX + 1];
    uint32_t ids[GS__SEC_MAX], n_sec = gs__db_section_ids(cn.flags, ids);
    if (!rc && !gs__db_layout(&cn, size))
        rc = gs__fail(err, GS_ELIMIT, "database: too many records or leaf entries");
    if (!rc && (cn.flags & GS__DB_FLAG_NEAR) && !(size[GS__SEC_NEAR] = gs__db_near_bytes(c->nv, c->n_near)))
        rc = gs__fail(err, GS_ELIMIT, "database: %llu near pairs", (unsigned long long)c->n_near);
    uint64_t total = GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * n_sec;
    for (uint32_t e = 0; e < n_sec && !rc; ++e) total += size[ids[e]];
    if (!rc && total > SIZE_MAX) rc = gs__fail(err, GS_ELIMIT, "database: %llu bytes", (unsigned long long)total);
    unsigned char *buf = rc ? NULL : gs__calloc((size_t)total, 1);
    if (!rc && !buf) rc = gs__fail(err, GS_ENOMEM, "database: out of memory (%llu bytes)", (unsigned long long)total);
    if (!rc) {
        unsigned char *sec[GS__SEC_MAX + 1] = {0};
        uint64_t off = GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * n_sec;
        for (uint32_t e = 0; e < n_sec; ++e) sec[ids[e]] = buf + off, off += size[ids[e]];
        write_header(buf, c, n_sec, total, &cn, numbers);
        write_tree(sec, c, grid);
        memcpy(sec[GS__SEC_INDEX], index, 4 * ((size_t)c->nv + 1));
        uint64_t unused = 0;
        int unused_bad = 0;
#pragma omp parallel for schedule(dynamic, 512) reduction(+ : unused) reduction(| : unused_bad)
        for (uint32_t x = 0; x < c->nv; ++x)
            encode_vertex(c, grid, fcurve, x, sec[GS__SEC_RECORDS] + GS__DB_RECORD_UNIT * (uint64_t)index[x], &unused, &unused_bad);
        if (tables) write_leaf_tables(sec, c, local16);
        if (cn.flags & GS__DB_FLAG_ALIASES) write_aliases(sec, c);
        if (cn.flags & GS__DB_FLAG_NEAR)
            gs__db_near_write(sec[GS__SEC_NEAR], c->nv, c->near_radius, c->near_pairs, c->n_near);
        write_table(buf, sec, size, ids, n_sec);
        rc = gs__db_attach(buf, (size_t)total, 0, "built database", 0, out, err);
        if (rc) free(buf);
    }
    free(grid), free(fcurve), free(index), free(rsize);
    return rc;
}

const void *gs_db_file_bytes(const gs_db *db, size_t *size)
{
    if (size) *size = db ? (size_t)db->size : 0;
    return db ? db->bytes : NULL;
}

int gs_db_save(const gs_db *db, const char *path, gs_error *err)
{
    if (!db || !path) return gs__fail(err, GS_EARG, "gs_db_save: NULL argument");
    gs__atomic_file af;
    int rc = gs__atomic_open(&af, path, err);
    if (rc) return rc;
    if (fwrite(db->bytes, 1, (size_t)db->size, af.fp) != (size_t)db->size) {
        gs__atomic_abort(&af);
        return gs__fail(err, GS_EIO, "%s: cannot write the database", path);
    }
    return gs__atomic_commit(&af, err);
}
