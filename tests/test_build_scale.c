/* test_build_scale.c - building at scale (issue 4): the cap on samples per
 * curve (max_samples) keeps the database accurate; fields computed in small
 * blocks (field_memory_mib) give the same database as in one block; the
 * large-node path (threads inside a node) and the small-node path (nodes in
 * parallel) give the same file for 1 and 2 threads. */
#include "check.h"
#include "db/db_internal.h"
#include "geodesic/geodesic_internal.h"
#include "geosep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Mean / max of the section-5 mean relative error over k exact fields. */
static double db_me(const gs_db *db, const gs_mesh *m, uint32_t k, double *max_me)
{
    uint32_t n = gs_mesh_num_vertices(m);
    uint32_t *src = malloc(k * sizeof *src);
    double *exact = malloc((size_t)n * sizeof *exact), *d = malloc((size_t)n * sizeof *d);
    gs_error err;
    CHECK(gs_mesh_random_vertices(m, k, 3, src, &err) == GS_OK);
    gs_patch *p = NULL;
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    double me = 0;
    *max_me = 0;
    for (uint32_t j = 0; j < k; ++j) {
        gs_source s = gs_source_vertex(src[j]);
        CHECK(gs_distance_field(p, GS_METHOD_EXACT, &s, 1, 0, exact, &err) == GS_OK);
        CHECK(gs_db_field(db, src[j], d, &err) == GS_OK);
        gs_field_errors fe;
        CHECK(gs_field_errors_compute(exact, d, n, src[j], &fe, &err) == GS_OK);
        CHECK(fe.n_invalid == 0);
        me += fe.me / k;
        *max_me = fmax(*max_me, fe.me);
    }
    gs_patch_free(p);
    free(src);
    free(exact);
    free(d);
    return me;
}

static gs_db *build(const gs_mesh *m, const gs_build_options *o)
{
    gs_db *db = NULL;
    gs_error err;
    int rc = gs_db_build(m, o, &db, NULL, &err);
    CHECK_MSG(rc == GS_OK, "%s", rc ? err.message : "");
    return db;
}

/* The file bytes of a database (malloc'ed; *n receives the size). */
static unsigned char *db_bytes(const gs_db *db, long *n)
{
    char path[] = "/tmp/geosep-scale-XXXXXX";
    int fd = mkstemp(path);
    *n = -1;
    if (fd < 0) return NULL;
    close(fd);
    gs_error err;
    unsigned char *data = NULL;
    if (gs_db_save(db, path, &err) == GS_OK) {
        FILE *f = fopen(path, "rb");
        if (f) {
            fseek(f, 0, SEEK_END);
            *n = ftell(f);
            fseek(f, 0, SEEK_SET);
            data = malloc(*n > 0 ? (size_t)*n : 1);
            if (fread(data, 1, (size_t)*n, f) != (size_t)*n) *n = -1;
            fclose(f);
        }
    }
    unlink(path);
    return data;
}

static int same_file(const gs_db *a, const gs_db *b)
{
    long na, nb;
    unsigned char *x = db_bytes(a, &na), *y = db_bytes(b, &nb);
    int same = x && y && na > 0 && na == nb && memcmp(x, y, (size_t)na) == 0;
    free(x);
    free(y);
    return same;
}

/* Thinning: every curve keeps at most max_samples samples, some were longer,
 * and the database stays about as accurate as the uncapped one. Curves are
 * thinned before long ones are split into pieces of <= 48 intervals (each
 * piece a curve), so the two databases' curves differ in number but cover
 * the same separators: the same total length. */
static void capped_samples(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("sphere:4", &m, &err) == GS_OK); /* 2562 vertices */
    gs_build_options o;
    gs_build_options_default(&o);
    o.max_samples = 0;
    gs_db *full = build(m, &o);
    o.max_samples = 24;
    gs_db *capped = build(m, &o);
    uint32_t longest = 0, at_cap = 0;
    double len_full = 0, len_capped = 0;
    for (uint32_t c = 0; c < full->n_curves; ++c) {
        if (full->curves[c].n_samples > longest) longest = full->curves[c].n_samples;
        len_full += full->curves[c].length;
    }
    for (uint32_t c = 0; c < capped->n_curves; ++c) {
        CHECK_MSG(capped->curves[c].n_samples <= 24, "curve %u: %u samples, cap 24", c, capped->curves[c].n_samples);
        at_cap += capped->curves[c].n_samples == 24;
        len_capped += capped->curves[c].length;
    }
    CHECK_MSG(longest > 24 && at_cap >= 3, "uncapped: longest %u samples; capped: %u curves thinned", longest, at_cap);
    CHECK_MSG(capped->n_curves < full->n_curves, "%u curves capped, %u uncapped (pieces)", capped->n_curves,
              full->n_curves);
    CHECK_MSG(fabs(len_capped - len_full) <= 1e-9 * len_full, "curve length %.17g capped, %.17g uncapped", len_capped,
              len_full);
    double mx_full, mx_capped;
    double me_full = db_me(full, m, 8, &mx_full), me_capped = db_me(capped, m, 8, &mx_capped);
    printf("sphere:4 exact: ME %.4f%% uncapped (longest curve %u samples), %.4f%% with 24 samples at most\n",
           100 * me_full, longest, 100 * me_capped);
    /* within 0.1% (absolute) of the uncapped ME: the separators and the
     * per-level tolerance make the uncapped database so accurate (0.06%)
     * that a ratio would test noise */
    CHECK_MSG(me_full < 0.004 && me_capped < 0.004 && me_capped < me_full + 0.001,
              "ME %.5f uncapped, %.5f capped", me_full, me_capped);
    gs_db_free(full);
    gs_db_free(capped);
    gs_mesh_free(m);
}

/* Fields in blocks of 16 sources (1 MiB) give the same database as in one
 * block, for methods solving one source at a time (bit-identical) and for
 * heat (batched solves: equal up to rounding). */
static void blocks(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("torus:90,40", &m, &err) == GS_OK); /* 3600 vertices */
    const gs_method methods[] = {GS_METHOD_FMM, GS_METHOD_GRAPH, GS_METHOD_HEAT};
    for (int q = 0; q < 3; ++q)
        for (int vs = 0; vs < 2; ++vs) {
            gs_build_options o;
            gs_build_options_default(&o);
            o.method = methods[q];
            o.solver.heat_refine = 0; /* as it is: refined builds below */
            o.vertex_sources = vs;
            o.threads = 2;
            gs_db *one = build(m, &o);
            o.field_memory_mib = 1;
            gs_db *many = build(m, &o);
            if (methods[q] != GS_METHOD_HEAT) {
                CHECK_MSG(same_file(one, many), "%s, %s sources: blocks change the database",
                          gs_method_name(methods[q]), vs ? "vertex" : "sample");
            } else {
                double worst = 0;
                for (uint32_t x = 0; x < gs_mesh_num_vertices(m); x += 7)
                    for (uint32_t y = 1; y < gs_mesh_num_vertices(m); y += 131) {
                        double a = gs_db_distance(one, x, y), b = gs_db_distance(many, x, y);
                        worst = fmax(worst, fabs(a - b) / fmax(a, 1e-3));
                    }
                CHECK_MSG(worst < 1e-5, "heat, %s sources: blocks change distances by %g (relative)",
                          vs ? "vertex" : "sample", worst);
            }
            gs_db_free(one);
            gs_db_free(many);
        }
    gs_mesh_free(m);
}

/* 1 and 2 threads: the same file, on a mesh whose top nodes are large
 * (threads inside a node) and whose lower nodes are small (in parallel). */
static void threads(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("sphere:5", &m, &err) == GS_OK); /* 10242 vertices */
    const gs_method methods[] = {GS_METHOD_HEAT, GS_METHOD_FMM};
    for (int q = 0; q < 2; ++q) {
        gs_build_options o;
        gs_build_options_default(&o);
        o.method = methods[q];
        o.solver.heat_refine = 0; /* as it is: refined builds below */
        o.max_samples = 64;
        o.threads = 1;
        gs_db *a = build(m, &o);
        o.threads = 2;
        gs_db *b = build(m, &o);
        CHECK_MSG(same_file(a, b), "%s: 1 and 2 threads give different files", gs_method_name(methods[q]));
        gs_db_free(a);
        gs_db_free(b);
    }
    gs_mesh_free(m);
}

/* One field per source in one call (heat: batched linear solves) equals
 * one solve per source: to the bit for the methods without a batched solve,
 * up to rounding for heat (a patch with a boundary: three systems). */
static void solve_each(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("plate:1500", &m, &err) == GS_OK);
    gs_patch *p = NULL;
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    uint32_t nv = gs_patch_num_vertices(p), n = 37; /* 16 + 16 + 5 */
    gs_source *src = malloc(n * sizeof *src);
    for (uint32_t i = 0; i < n; ++i)
        src[i] = i % 3 ? gs_source_vertex((i * 7919u) % nv)
                       : gs_source_point((i * 104729u) % gs_patch_num_faces(p), 0.2, 0.3, 0.5);
    double *all = malloc((size_t)n * nv * sizeof *all), *one = malloc(nv * sizeof *one);
    const gs_method methods[] = {GS_METHOD_HEAT, GS_METHOD_FMM, GS_METHOD_EXACT, GS_METHOD_HEAT};
    for (int q = 0; q < 4; ++q) {
        gs_solver *s = NULL;
        gs_solver_options so;
        gs_solver_options_default(&so);
        so.heat_refine = q == 3; /* heat on the patch subdivided once */
        CHECK(gs_solver_create_ex(p, methods[q], &so, &s, &err) == GS_OK);
        CHECK(gs__solver_solve_each(s, src, n, all, &err) == GS_OK);
        double worst = 0;
        for (uint32_t i = 0; i < n; ++i) {
            CHECK(gs_solver_solve(s, &src[i], 1, 0, one, &err) == GS_OK);
            for (uint32_t v = 0; v < nv; ++v) {
                double a = all[(size_t)i * nv + v], b = one[v];
                worst = fmax(worst, a == b ? 0 : fabs(a - b) / fmax(fabs(b), 1e-3));
            }
        }
        if (methods[q] == GS_METHOD_HEAT)
            CHECK_MSG(worst < 1e-9, "heat: batched and single solves differ by %g", worst);
        else
            CHECK_MSG(worst == 0, "%s: batched and single solves differ by %g", gs_method_name(methods[q]), worst);
        /* clones (the heat method's share the factorisations): the same
         * fields bit for bit, solved by two threads at once with the
         * original, and from a clone of a clone */
        gs_solver *c1 = NULL, *c2 = NULL;
        CHECK(gs__solver_clone(s, &c1, &err) == GS_OK && c1);
        CHECK(c1 && gs__solver_clone(c1, &c2, &err) == GS_OK && c2);
        double *par = malloc(3 * (size_t)n * nv * sizeof *par);
        int prc[3] = {-1, -1, -1};
        gs_solver *use[3] = {s, c1, c2};
#pragma omp parallel for num_threads(3)
        for (int t = 0; t < 3; ++t)
            if (use[t] && par) prc[t] = gs__solver_solve_each(use[t], src, n, par + (size_t)t * n * nv, NULL);
        for (int t = 0; t < 3 && par; ++t)
            CHECK_MSG(prc[t] == GS_OK && memcmp(par + (size_t)t * n * nv, all, (size_t)n * nv * sizeof *all) == 0,
                      "%s%s: solver %d of 3 (0: the original) gives other fields", gs_method_name(methods[q]),
                      q == 3 ? " refined" : "", t);
        free(par);
        gs_solver_free(c2);
        gs_solver_free(c1);
        gs_solver_free(s);
    }
    CHECK(gs__solver_solve_each(NULL, src, n, all, &err) == GS_EARG);
    gs_solver *none = NULL;
    CHECK(gs__solver_clone(NULL, &none, &err) == GS_EARG && none == NULL);
    free(src);
    free(all);
    free(one);
    gs_patch_free(p);
    gs_mesh_free(m);
}

static void bad_options(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("grid:5,5", &m, &err) == GS_OK);
    gs_build_options o;
    gs_build_options_default(&o);
    o.max_samples = 3;
    gs_db *db = NULL;
    CHECK(gs_db_build(m, &o, &db, NULL, &err) == GS_EARG && db == NULL);
    CHECK(strstr(err.message, "max_samples") != NULL);
    gs_build_options_default(&o);
    o.field_memory_mib = 1u << 30;
    CHECK(gs_db_build(m, &o, &db, NULL, &err) == GS_EARG && db == NULL);
    CHECK(strstr(err.message, "field_memory_mib") != NULL);
    gs_build_options_default(&o);
    o.method = GS_METHOD_HEAT;
    o.solver.heat_refine = GS_HEAT_REFINE_MAX + 1;
    CHECK(gs_db_build(m, &o, &db, NULL, &err) == GS_EARG && db == NULL);
    CHECK(strstr(err.message, "heat_refine 4 must be at most 3") != NULL);
    /* a count that is neither 0..3 nor GS_HEAT_REFINE_AUTO, for any method */
    o.method = GS_METHOD_FMM;
    o.solver.heat_refine = GS_HEAT_REFINE_AUTO - 1;
    CHECK(gs_db_build(m, &o, &db, NULL, &err) == GS_EARG && db == NULL);
    CHECK(strstr(err.message, "must be at most 3") != NULL);
    gs_mesh_free(m);
}

/* gs_heat_refine_auto: the fewest subdivisions (at most 2) to reach
 * GS_HEAT_REFINE_AUTO_VERTICES vertices; a solver created with
 * GS_HEAT_REFINE_AUTO gives the fields of the count it chooses for its
 * patch, bit for bit. */
static void heat_refine_auto(void)
{
    static const uint32_t nv[] = {0, 1, 1999, 2000, 5051, 7999, 8000, 10000, 20000, 31999, 32000, 35947, UINT32_MAX};
    static const uint32_t want[] = {2, 2, 2, 2, 2, 2, 1, 1, 1, 1, 0, 0, 0};
    for (size_t k = 0; k < sizeof nv / sizeof *nv; ++k)
        CHECK_MSG(gs_heat_refine_auto(nv[k]) == want[k], "gs_heat_refine_auto(%u) = %u, expected %u", nv[k],
                  gs_heat_refine_auto(nv[k]), want[k]);
    CHECK(GS_HEAT_REFINE_AUTO > GS_HEAT_REFINE_MAX);
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("peaks:15", &m, &err) == GS_OK);
    gs_patch *p = NULL;
    CHECK(gs_patch_create(m, NULL, 0, &p, &err) == GS_OK);
    uint32_t n = gs_patch_num_vertices(p), r = gs_heat_refine_auto(n);
    CHECK_MSG(r == 2, "peaks:15 (%u vertices): refined %u times", n, r);
    double *a = malloc(2 * (size_t)n * sizeof *a);
    gs_source src = gs_source_vertex(n / 3);
    for (int k = 0; k < 2; ++k) {
        gs_solver_options so;
        gs_solver_options_default(&so);
        CHECK(so.heat_refine == 0); /* a solver's default: the patch as it is */
        so.heat_refine = k ? r : GS_HEAT_REFINE_AUTO;
        gs_solver *s = NULL;
        CHECK(gs_solver_create_ex(p, GS_METHOD_HEAT, &so, &s, &err) == GS_OK);
        CHECK(s && gs_solver_solve(s, &src, 1, 0, a + (size_t)k * n, &err) == GS_OK);
        gs_solver_free(s);
    }
    CHECK_MSG(memcmp(a, a + n, n * sizeof *a) == 0, "GS_HEAT_REFINE_AUTO and heat_refine %u differ", r);
    free(a);
    gs_patch_free(p);
    gs_mesh_free(m);
}

/* heat_refine is recorded in the database (build_flags bits 2-3) and read
 * back, also from the saved file; the fields come from the refined solve
 * (a database differs from the unrefined one). */
static void heat_refine_recorded(void)
{
    gs_mesh *m = NULL;
    gs_error err;
    CHECK(gs_mesh_generate("sphere:2", &m, &err) == GS_OK); /* 162 vertices */
    gs_build_options o;
    gs_build_options_default(&o);
    o.method = GS_METHOD_HEAT;
    o.solver.heat_refine = 0;
    gs_db *plain = build(m, &o);
    o.solver.heat_refine = 2;
    gs_db *db = build(m, &o);
    gs_db_info i;
    CHECK(gs_db_get_info(plain, &i, &err) == GS_OK && i.solver.heat_refine == 0);
    CHECK(gs_db_get_info(db, &i, &err) == GS_OK && i.solver.heat_refine == 2 && i.method == GS_METHOD_HEAT);
    CHECK(!same_file(plain, db));
    /* the default (GS_HEAT_REFINE_AUTO) resolves from the mesh's 162
     * vertices to 2, the number recorded; the same file with 1 thread or 2 */
    gs_build_options_default(&o);
    CHECK(o.solver.heat_refine == GS_HEAT_REFINE_AUTO);
    o.method = GS_METHOD_HEAT;
    o.threads = 2;
    gs_db *a2 = build(m, &o);
    o.threads = 1;
    gs_db *a1 = build(m, &o);
    CHECK(gs_db_get_info(a2, &i, &err) == GS_OK && i.solver.heat_refine == 2);
    CHECK_MSG(same_file(a2, db) && same_file(a1, db), "the default build is not the one refined twice");
    gs_db_free(a1);
    gs_db_free(a2);
    /* other methods ignore it and record 0 */
    o.method = GS_METHOD_FMM;
    gs_db *f = build(m, &o);
    CHECK(gs_db_get_info(f, &i, &err) == GS_OK && i.solver.heat_refine == 0);
    gs_db_free(f);
    char path[256];
    snprintf(path, sizeof path, "/tmp/geosep_test_refine_%d.gsdb", (int)getpid());
    CHECK(gs_db_save(db, path, &err) == GS_OK);
    gs_db *back = NULL;
    CHECK(gs_db_open(path, &back, &err) == GS_OK);
    CHECK(back && gs_db_get_info(back, &i, &err) == GS_OK && i.solver.heat_refine == 2);
    CHECK(back && same_file(db, back));
    unlink(path);
    gs_db_free(back);
    gs_db_free(db);
    gs_db_free(plain);
    gs_mesh_free(m);
}

int main(void)
{
    bad_options();
    heat_refine_recorded();
    heat_refine_auto();
    solve_each();
    capped_samples();
    blocks();
    threads();
    return gs_test_finish("test_build_scale");
}
