/* db_cmds.c - the database subcommands: build, query, field, eval (section 5
 * error measures against a GEOGT1 file) and the LAND baseline. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char usage_build[] =
    "usage: geosep build MESH -o DB [--method exact|graph|fmm|heat|dgg] [--vmax N] [--mmax N] [--tol F]\n"
    "                    [--threads N] [--vertex-sources|--sample-sources] [--sampled] [--seed N]\n"
    "                    [--spacing F] [--max-samples N] [--field-memory MIB] [--heat-time M] [--heat-refine N|auto]\n"
    "                    [--fmm-start R] [--dgg-eps E] [--no-leaf-exact] [--near-radius F] [--quiet] [--repair]\n"
    "  Build a query database (-o or --output DB): nested bisection tree\n"
    "  (leaves of at most --vmax vertices, default 30), distance fields from\n"
    "  every separator sample inside its patch (--method, default exact), and\n"
    "  per-vertex polynomial separator distance functions of degree <= --mmax\n"
    "  (20) fitted to mean relative error\n"
    "  --tol (0.003) at the root, 1.5x looser per tree level (at most 2%).\n"
    "  --vertex-sources: fields from the corners of the sample\n"
    "  triangles + barycentric interpolation (the paper's way; the default for\n"
    "  fmm and heat); --sample-sources: from the samples (the default for\n"
    "  exact fields). --sampled: store\n"
    "  the sampled values (SEPsam) instead of polynomials. --spacing: separator\n"
    "  sample spacing in mean edge lengths (0.5). --max-samples: longer curves\n"
    "  are thinned to this many samples (192; 0 = no cap), then split into\n"
    "  pieces of at most 48 sample intervals (each its own function). --field-memory: MiB\n"
    "  for one block of distance fields (384, also for 0; two live at a time).\n"
    "  Exact distances between the vertices of each leaf are stored (paper sec.\n"
    "  3.1, matrix D; at most vmax numbers per vertex); --no-leaf-exact answers\n"
    "  same-leaf queries with the Euclidean distance instead (smaller, but off\n"
    "  by up to 56% on curved leaves; --leaf-exact: the default). Pairs of\n"
    "  vertices in different leaves nearer than --near-radius mean edge lengths\n"
    "  (5; 2-10 times that from a vertex with an uncertified fit; 0 = none) whose\n"
    "  answer through the separators is off by more than 2% get their exact\n"
    "  distance stored (doc/accuracy.md). --threads:\n"
    "  build threads (0 = all cores, the default). --seed: the partitioning\n"
    "  seed (1). --heat-time,\n"
    "  --heat-refine, --fmm-start and --dgg-eps: the field method's parameters (see geosep\n"
    "  solve --help; --heat-refine subdivides each patch while its fields are\n"
    "  solved; default auto: meshes under 32,000 vertices are subdivided to\n"
    "  reach that, at most twice).\n"
    "  Shows progress on a terminal; prints the stage times and the size\n"
    "  (--quiet: neither).\n"
    "  --repair: repair the mesh in memory first (geosep repair --help; what was\n"
    "  done goes to stderr): the database is of the repaired mesh, whose vertex\n"
    "  ids are the input's plus appended copies, and it stores where every input\n"
    "  vertex went (doc/repair.md): query --input-ids and field --input-ids\n"
    "  answer by the input's ids.\n";
const char usage_query[] =
    "usage: geosep query DB X Y [--input-ids]\n"
    "       geosep query DB --pairs FILE [--input-ids]  (FILE: lines 'X Y')\n"
    "       geosep query DB --points FILE               (lines 'v0 v1 v2 l0 l1 l2  w0 w1 w2 m0 m1 m2')\n"
    "       geosep query DB --points FILE --mesh MESH   (lines 'f b0 b1 b2  g c0 c1 c2')\n"
    "  Approximate geodesic distance between vertices X and Y, one per line\n"
    "  (\"inf\" if they are not connected; FILE '-' = stdin, blank lines skipped;\n"
    "  fields separated by spaces or tabs, lines of at most 4095 bytes).\n"
    "  --points: between two surface points per line, each a face's three corner\n"
    "  vertex ids and barycentric weights (l0 v0 + l1 v1 + l2 v2), or with\n"
    "  --mesh (the mesh the database was built from) a face id of MESH and\n"
    "  three barycentric weights. Weights: finite, >= -1e-12, summing to 1\n"
    "  within 1e-9. A vertex v is 'v v v 1 0 0' (or any face of it with\n"
    "  weight 1 at v).\n"
    "  --input-ids: X and Y are the ids of the mesh given to geosep build\n"
    "  --repair: each answers the least distance over the vertices it became\n"
    "  (a split vertex: its copies; a welded one: the vertex it joined). On a\n"
    "  database built without --repair, input ids are the vertex ids.\n"
    "  The database is opened without reading it whole (its structure is\n"
    "  checked, not its checksums: geosep verify DB checks those).\n";
const char usage_verify[] =
    "usage: geosep verify DB\n"
    "  Check a database whole: its structure, every section's checksum, every\n"
    "  function record (well formed, coefficients in range, its stored minimum\n"
    "  not above its values), positions and leaf tables. Prints 'DB: ok' and\n"
    "  a summary, or names the section, vertex and field that is wrong (exit 1).\n";
const char usage_field[] =
    "usage: geosep field DB --source X [--input-ids] [-o OUT]\n"
    "       geosep field DB --point V0,V1,V2:L0,L1,L2 [-o OUT]\n"
    "       geosep field DB --mesh MESH --source-point F:b0,b1,b2 [-o OUT]\n"
    "       geosep field DB --format gt --sources-from FILE.gt -o OUT.gt\n"
    "  Database distances from X to every vertex, one per line (or, with\n"
    "  --format gt, for every source of FILE.gt, written as GEOGT1).\n"
    "  --point: from the surface point L0 V0 + L1 V1 + L2 V2 (a face's corners\n"
    "  and barycentric weights); --source-point: from the point of face F of\n"
    "  MESH (the database's mesh) with barycentric weights b0,b1,b2.\n"
    "  --input-ids (with --source): X and the lines are the ids of the mesh\n"
    "  given to geosep build --repair (one line per input vertex; geosep query\n"
    "  --help says how they are answered).\n";
const char usage_eval[] =
    "usage: geosep eval DB --groundtruth FILE.gt\n"
    "  Compare the database with exact distances (GEOGT1): ME and RMSE of the\n"
    "  relative error e = |d^ - d| / d as the paper's section 5 defines them\n"
    "  (per source, averaged over the sources); over all (source, vertex) pairs:\n"
    "  p99 and p99.9 (nearest rank), max, near-pair ME (the mean e over pairs\n"
    "  whose exact d is below 10% of the median exact d), the largest under- and\n"
    "  overestimate and the pairs off by more than 5%; cost (numbers stored per\n"
    "  vertex, as Table 1 counts them), bytes per vertex, tree depth, query\n"
    "  speed. For the maximum over all vertex pairs, give a FILE.gt with every\n"
    "  vertex as a source (geosep solve MESH --format gt --all -o FILE.gt).\n";
const char usage_land[] =
    "usage: geosep land MESH --landmarks M --groundtruth FILE.gt [--method exact|graph|fmm|heat|dgg]\n"
    "  The LAND baseline (Burghard & Klein 2015) with M landmarks, evaluated\n"
    "  against FILE.gt like geosep eval.\n";

/* ---- build --------------------------------------------------------------- */

typedef struct bar {
    int tty;
    double t0, stage_t0; /* build start, current stage's start */
    const char *stage;
    int last_pct;
} bar;

static void on_progress(void *user, const char *stage, double f)
{
    bar *b = user;
    if (!b->tty) return;
    int pct = (int)(f * 100);
    int same = b->stage && !strcmp(b->stage, stage);
    if (same && pct == b->last_pct) return;
    if (!same) b->stage_t0 = now();
    b->stage = stage;
    b->last_pct = pct;
    double el = now() - b->t0, st = now() - b->stage_t0;
    char eta[32] = "";
    /* the time left in this stage, from its own rate so far */
    if (f > 0.02 && f < 1) snprintf(eta, sizeof eta, " ~%.0f s left", st * (1 - f) / f);
    int w = 30, k = (int)(f * w);
    fprintf(stderr, "\r%-7s [%.*s%*s] %3d%% %6.1f s%-16s", stage, k, "##############################",
            w - k, "", pct, el, eta);
    fflush(stderr);
}

static int build_option(gs_build_options *o, const char **out, int *quiet, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--vertex-sources")) return o->vertex_sources = 1, 0;
    if (!strcmp(a, "--sample-sources")) return o->vertex_sources = 0, 0;
    if (!strcmp(a, "--sampled")) return o->sampled = 1, 0;
    if (!strcmp(a, "--leaf-exact")) return o->leaf_exact = 1, 0;
    if (!strcmp(a, "--no-leaf-exact")) return o->leaf_exact = 0, 0;
    if ((v = opt_value(argc, argv, i, "--near-radius")))
        return parse_double(v, &o->near_radius) ? fail(EXIT_USAGE, "build: --near-radius '%s' is not a number", v) : 0;
    if (!strcmp(a, "--quiet")) return *quiet = 1, 0;
    if ((v = opt_value(argc, argv, i, "-o")) || (v = opt_value(argc, argv, i, "--output"))) return *out = v, 0;
    if ((v = opt_value(argc, argv, i, "--method"))) {
        gs_error e = {0};
        return gs_method_from_name(v, &o->method, &e) ? fail(EXIT_USAGE, "build: %s", e.message) : 0;
    }
    if ((v = opt_value(argc, argv, i, "--vmax")))
        return parse_u32(v, &o->vmax) ? fail(EXIT_USAGE, "build: --vmax '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--mmax")))
        return parse_u32(v, &o->mmax) ? fail(EXIT_USAGE, "build: --mmax '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--threads")))
        return parse_u32(v, &o->threads) ? fail(EXIT_USAGE, "build: --threads '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--max-samples")))
        return parse_u32(v, &o->max_samples) ? fail(EXIT_USAGE, "build: --max-samples '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--field-memory")))
        return parse_u32(v, &o->field_memory_mib) ? fail(EXIT_USAGE, "build: --field-memory '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--seed")))
        return parse_u32(v, &o->seed) ? fail(EXIT_USAGE, "build: --seed '%s' is not a count", v) : 0;
    if ((v = opt_value(argc, argv, i, "--spacing")))
        return parse_double(v, &o->sample_spacing) ? fail(EXIT_USAGE, "build: --spacing '%s' is not a number", v) : 0;
    if ((v = opt_value(argc, argv, i, "--heat-time")))
        return parse_double(v, &o->solver.heat_time) ? fail(EXIT_USAGE, "build: --heat-time '%s' is not a number", v) : 0;
    if ((v = opt_value(argc, argv, i, "--dgg-eps")))
        return parse_double(v, &o->solver.dgg_eps) ? fail(EXIT_USAGE, "build: --dgg-eps '%s' is not a number", v) : 0;
    if ((v = opt_value(argc, argv, i, "--fmm-start")))
        return parse_double(v, &o->solver.fmm_exact_start) ? fail(EXIT_USAGE, "build: --fmm-start '%s' is not a number", v) : 0;
    if ((v = opt_value(argc, argv, i, "--heat-refine")))
        return parse_heat_refine(v, &o->solver.heat_refine)
                   ? fail(EXIT_USAGE, "build: --heat-refine '%s': expected 0 to %d or auto", v, GS_HEAT_REFINE_MAX)
                   : 0;
    if ((v = opt_value(argc, argv, i, "--tol")))
        return parse_double(v, &o->tol) ? fail(EXIT_USAGE, "build: --tol '%s' is not a number", v) : 0;
    return fail(EXIT_USAGE, "build: unknown or incomplete option '%s'", a);
}

/* A database of a repaired mesh: how many input ids it answers by (nothing
 * when every input id is only itself). */
static void print_input_ids(const gs_db *db, const gs_db_info *i)
{
    uint32_t n = gs_db_num_input_vertices(db), k = 0, a;
    for (uint32_t v = 0; v < n; ++v) k += gs_db_input_aliases(db, v, &a, 1) != 1 || a != v;
    if (n == i->n_vertices && k == 0) return;
    printf("input ids (a repaired mesh): %u input vertices, %u of them answered through other vertices (query "
           "--input-ids)\n",
           n, k);
}

/* One line: the build parameters the database records. */
static void print_params(const gs_db_info *i)
{
    printf("built with: method %s", gs_method_name(i->method));
    if (i->method == GS_METHOD_FMM) printf(" (exact start %g edge lengths)", i->solver.fmm_exact_start);
    if (i->method == GS_METHOD_DGG && i->solver.dgg_eps > 0) printf(" (eps %g)", i->solver.dgg_eps);
    if (i->method == GS_METHOD_HEAT) {
        printf(" (t = %g h^2", i->solver.heat_time);
        if (i->solver.heat_refine) printf(", solved on the patches subdivided 1-to-4 %u time%s", i->solver.heat_refine,
                                          i->solver.heat_refine > 1 ? "s" : "");
        printf(")");
    }
    printf(", %s sources, vmax %u, mmax %u, tol %g, spacing %g", i->vertex_sources ? "vertex" : "sample", i->vmax,
           i->mmax, i->tol, i->sample_spacing);
    if (i->max_samples) printf(", at most %u samples per curve", i->max_samples);
    printf(", seed %u%s%s", i->seed, i->sampled ? ", sampled (SEPsam)" : "", i->leaf_exact ? ", leaf tables" : "");
    if (i->near_radius > 0) printf(", %llu near pairs within %g", (unsigned long long)i->n_near_pairs, i->near_radius);
    printf("\n");
}

int cmd_build(int argc, char **argv)
{
    gs_build_options o;
    gs_build_options_default(&o);
    const char *mesh_path = NULL, *out = NULL;
    int quiet = 0, repair = 0;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_build, stdout), 0;
        if (!strcmp(argv[i], "--repair")) {
            repair = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            int rc = build_option(&o, &out, &quiet, argc, argv, &i);
            if (rc) return rc;
        } else if (!mesh_path)
            mesh_path = argv[i];
        else
            return fail(EXIT_USAGE, "build: unexpected argument '%s'", argv[i]);
    }
    if (!mesh_path || !out) return fail(EXIT_USAGE, "build: need MESH and -o DB (see geosep build --help)");
    gs_mesh *m = NULL;
    gs_repair *rep = NULL;
    int rc = load_mesh_opt(mesh_path, repair, &m, &rep);
    if (rc) return rc;
    bar b = {isatty(2) && !quiet, now(), now(), NULL, -1};
    o.progress = on_progress;
    o.progress_user = &b;
    o.repair = rep; /* --repair: the input ids' aliases go into the database */
    gs_db *db = NULL;
    gs_build_stats st = {0};
    gs_error err = {0};
    rc = gs_db_build(m, &o, &db, &st, &err);
    if (b.tty) fputc('\n', stderr);
    if (rc) {
        gs_mesh_free(m);
        gs_repair_free(rep);
        /* a bad option value is a usage error, whoever detects it */
        return rc == GS_EARG ? fail(EXIT_USAGE, "build: %s", err.message) : lib_fail("build", rc, &err);
    }
    double tw = now();
    rc = gs_db_save(db, out, &err);
    tw = now() - tw;
    if (rc) rc = lib_fail(out, rc, &err);
    gs_db_info info;
    if (!rc && !quiet && gs_db_get_info(db, &info, &err) == GS_OK) {
        printf("%s: %u vertices, %u nodes (%u leaves), %u curves, depth avg %.2f max %u\n", out,
               info.n_vertices, info.n_nodes, info.n_leaves, info.n_curves, info.avg_depth, info.max_depth);
        printf("fields %llu (%s), functions %llu, mean degree %.2f, mean fit error %.3f%%, %llu above tol\n",
               (unsigned long long)st.n_fields, gs_method_name(o.method), (unsigned long long)st.n_functions,
               st.mean_degree, 100 * st.mean_fit_error, (unsigned long long)st.n_over_tol);
        printf("certified fits (error <= 2%% at the samples and within their Lipschitz band between them): "
               "all but %llu; the worst %.2f%%\n",
               (unsigned long long)st.n_uncertified, 100 * st.max_fit_error);
        if (info.near_radius > 0)
            printf("near pairs (exact, within %g of each other, off by > 2%% through the separators): %llu, "
                   "%.2f bytes/vertex, %.2f s\n",
                   info.near_radius, (unsigned long long)info.n_near_pairs,
                   (double)info.near_bytes / info.n_vertices, st.seconds_near);
        printf("time: tree %.2f s, fields %.2f s, fits %.2f s, write %.2f s, total %.2f s\n", st.seconds_tree,
               st.seconds_fields, st.seconds_fits, tw, st.seconds_total + tw);
        printf("size: %llu bytes, %.1f bytes/vertex, cost %.1f numbers/vertex\n",
               (unsigned long long)info.file_bytes, info.bytes_per_vertex, info.cost);
        print_params(&info);
        print_input_ids(db, &info);
    }
    gs_db_free(db);
    gs_mesh_free(m);
    gs_repair_free(rep);
    return rc;
}

/* ---- query / field -------------------------------------------------------- */

static int open_db(const char *path, gs_db **db)
{
    gs_error err = {0};
    int rc = gs_db_open(path, db, &err);
    return rc ? lib_fail(path, rc, &err) : 0;
}

static int query_id(const char *s, uint32_t n, int input, uint32_t *v)
{
    if (parse_u32(s, v)) return fail(EXIT_USAGE, "query: '%s' is not a%s vertex id", s, input ? "n input" : "");
    if (*v >= n)
        return fail(EXIT_USAGE, "query: %svertex %u out of range (the database has %u%s)", input ? "input " : "", *v, n,
                    input ? " input vertices" : "");
    return 0;
}

/* ---- surface points -------------------------------------------------------- */

/* The mesh must be the database's: same vertex count, same positions (as
 * numbers: -0 is where 0 is). */
static int load_db_mesh(const char *path, const gs_db *db, uint32_t n, gs_mesh **m)
{
    int rc = load_mesh(path, m);
    if (rc) return rc;
    uint32_t nm = gs_mesh_num_vertices(*m);
    const double *a = gs_mesh_positions(*m), *b = gs_db_positions(db);
    if (nm != n) rc = fail(EXIT_RUNTIME, "%s: %u vertices, the database has %u: not the mesh it was built from", path, nm, n);
    for (uint32_t v = 0; !rc && v < n; ++v)
        if (a[3 * (size_t)v] != b[3 * (size_t)v] || a[3 * (size_t)v + 1] != b[3 * (size_t)v + 1] ||
            a[3 * (size_t)v + 2] != b[3 * (size_t)v + 2])
            rc = fail(EXIT_RUNTIME, "%s: vertex %u is not where the database has it: not the mesh it was built from", path, v);
    if (rc) gs_mesh_free(*m), *m = NULL;
    return rc;
}

static int query_file(const gs_db *db, const gs_mesh *mesh, uint32_t n, const char *path, int points)
{
    line_reader r;
    int rc = lines_open(&r, path);
    if (!rc) rc = points ? query_points(db, mesh, &r, stdout) : query_pairs(db, n, &r, stdout);
    lines_close(&r);
    return rc;
}

int cmd_verify(int argc, char **argv)
{
    const char *dbp = NULL;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_verify, stdout), 0;
        if (argv[i][0] == '-' && argv[i][1]) return fail(EXIT_USAGE, "verify: unknown option '%s'", argv[i]);
        if (dbp) return fail(EXIT_USAGE, "verify: unexpected argument '%s'", argv[i]);
        dbp = argv[i];
    }
    if (!dbp) return fail(EXIT_USAGE, "verify: need DB");
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs_db_open_ex(dbp, GS_DB_OPEN_VERIFY, &db, &err);
    if (rc) return lib_fail(dbp, rc, &err);
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    printf("%s: ok (format %u, %u vertices, %llu functions, %llu bytes, %.1f bytes/vertex; checksums and records "
           "verified)\n",
           dbp, info.format_version, info.n_vertices, (unsigned long long)info.n_functions,
           (unsigned long long)info.file_bytes, info.bytes_per_vertex);
    print_params(&info);
    print_input_ids(db, &info);
    gs_db_free(db);
    return 0;
}

int cmd_query(int argc, char **argv)
{
    const char *dbp = NULL, *pairs = NULL, *points = NULL, *meshp = NULL, *ids[2] = {NULL, NULL}, *v;
    int n_ids = 0, input = 0;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_query, stdout), 0;
        if (!strcmp(argv[i], "--input-ids")) input = 1;
        else if ((v = opt_value(argc, argv, &i, "--pairs"))) pairs = v;
        else if ((v = opt_value(argc, argv, &i, "--points"))) points = v;
        else if ((v = opt_value(argc, argv, &i, "--mesh"))) meshp = v;
        else if (argv[i][0] == '-' && argv[i][1]) return fail(EXIT_USAGE, "query: unknown or incomplete option '%s'", argv[i]);
        else if (!dbp) dbp = argv[i];
        else if (n_ids < 2) ids[n_ids++] = argv[i];
        else return fail(EXIT_USAGE, "query: unexpected argument '%s'", argv[i]);
    }
    if (!dbp || (!!pairs + !!points + (n_ids > 0)) != 1 || (n_ids && n_ids != 2))
        return fail(EXIT_USAGE, "query: need DB X Y, DB --pairs FILE or DB --points FILE [--mesh MESH]");
    if (meshp && !points) return fail(EXIT_USAGE, "query: --mesh goes with --points");
    if (input && points)
        return fail(EXIT_USAGE, "query: --input-ids goes with X Y or --pairs (surface points name the database's "
                                "own faces and vertices)");
    gs_db *db = NULL;
    int rc = open_db(dbp, &db);
    if (rc) return rc;
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    if (pairs && input) {
        line_reader r;
        if (!(rc = lines_open(&r, pairs))) rc = query_input_pairs(db, &r, stdout);
        lines_close(&r);
    } else if (pairs)
        rc = query_file(db, NULL, info.n_vertices, pairs, 0);
    else if (points) {
        gs_mesh *m = NULL;
        if (!meshp || !(rc = load_db_mesh(meshp, db, info.n_vertices, &m))) rc = query_file(db, m, info.n_vertices, points, 1);
        gs_mesh_free(m);
    } else {
        uint32_t x, y, n = input ? gs_db_num_input_vertices(db) : info.n_vertices;
        if (!(rc = query_id(ids[0], n, input, &x)) && !(rc = query_id(ids[1], n, input, &y)))
            print_distance(stdout, input ? gs_db_input_distance(db, x, y) : gs_db_distance(db, x, y));
    }
    gs_db_free(db);
    return rc;
}

static int field_gt(const gs_db *db, uint32_t n, const char *from, const char *out)
{
    gs_gt *gt = NULL;
    gs_error err = {0};
    int rc = gs_gt_read(from, &gt, &err);
    if (rc) return lib_fail(from, rc, &err);
    double *d = NULL;
    if (gt->n_vertices != n)
        rc = fail(EXIT_RUNTIME, "%s: made for %u vertices, the database has %u", from, gt->n_vertices, n);
    else if (!(d = malloc(((size_t)n * gt->n_sources + 1) * sizeof *d)))
        rc = fail(EXIT_RUNTIME, "out of memory");
    for (uint32_t j = 0; !rc && j < gt->n_sources; ++j)
        if ((rc = gs_db_field(db, gt->sources[j], d + (size_t)j * n, &err))) rc = lib_fail("field", rc, &err);
    if (!rc && (rc = gs_gt_write(out, n, gt->n_sources, gt->sources, d, &err))) rc = lib_fail(out, rc, &err);
    free(d);
    gs_gt_free(gt);
    return rc;
}

static int field_point(const gs_db *db, uint32_t n, const char *opt, const char *spec, const char *meshp,
                       const char *out)
{
    char buf[512], *t[6], why[600];
    gs_mesh *m = NULL;
    int rc = 0;
    const char *form = meshp ? "F:b0,b1,b2 (face id, three barycentric weights)"
                             : "V0,V1,V2:L0,L1,L2 (three vertex ids, three barycentric weights)";
    if (strlen(spec) >= sizeof buf || (strcpy(buf, spec), split_point(buf, meshp != NULL, t)))
        return fail(EXIT_USAGE, "field: %s '%s': expected %s", opt, spec, form);
    if (meshp && (rc = load_db_mesh(meshp, db, n, &m))) return rc;
    gs_surface_point p;
    if (make_point(db, m, t, &p, why, sizeof why)) rc = fail(EXIT_USAGE, "field: %s %s: %s", opt, spec, why);
    double *d = rc ? NULL : malloc((n ? n : 1) * sizeof *d);
    gs_error err = {0};
    if (!rc && !d) rc = fail(EXIT_RUNTIME, "out of memory");
    else if (!rc && (rc = gs_db_point_field(db, &p, d, &err))) rc = lib_fail("field", rc, &err);
    else if (!rc) rc = write_text(out, d, n);
    free(d);
    gs_mesh_free(m);
    return rc;
}

int cmd_field(int argc, char **argv)
{
    const char *dbp = NULL, *out = NULL, *from = NULL, *src = NULL, *fmt = NULL, *point = NULL, *spoint = NULL,
               *meshp = NULL, *v;
    int input = 0;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_field, stdout), 0;
        if (!strcmp(argv[i], "--input-ids")) input = 1;
        else if ((v = opt_value(argc, argv, &i, "-o"))) out = v;
        else if ((v = opt_value(argc, argv, &i, "--source-point"))) spoint = v;
        else if ((v = opt_value(argc, argv, &i, "--source"))) src = v;
        else if ((v = opt_value(argc, argv, &i, "--sources-from"))) from = v;
        else if ((v = opt_value(argc, argv, &i, "--format"))) fmt = v;
        else if ((v = opt_value(argc, argv, &i, "--point"))) point = v;
        else if ((v = opt_value(argc, argv, &i, "--mesh"))) meshp = v;
        else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "field: unknown or incomplete option '%s' (see geosep field --help)", argv[i]);
        else if (!dbp) dbp = argv[i];
        else return fail(EXIT_USAGE, "field: unexpected argument '%s'", argv[i]);
    }
    if (fmt && strcmp(fmt, "gt") && strcmp(fmt, "text"))
        return fail(EXIT_USAGE, "field: unknown --format '%s' (text or gt)", fmt);
    int gt = fmt && !strcmp(fmt, "gt");
    int n_src = !!src + !!point + !!spoint;
    if (!dbp || (gt ? (!from || !out || n_src) : (n_src != 1 || from)))
        return fail(EXIT_USAGE, "field: need DB --source X, DB --point V0,V1,V2:L0,L1,L2, DB --mesh MESH "
                                "--source-point F:b0,b1,b2, or DB --format gt --sources-from FILE.gt -o OUT.gt");
    if (!meshp != !spoint) return fail(EXIT_USAGE, "field: --source-point and --mesh go together");
    if (input && !src) return fail(EXIT_USAGE, "field: --input-ids goes with --source X");
    gs_db *db = NULL;
    int rc = open_db(dbp, &db);
    if (rc) return rc;
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    uint32_t n = input ? gs_db_num_input_vertices(db) : info.n_vertices, x; /* input: with --source only */
    if (gt)
        rc = field_gt(db, n, from, out);
    else if (point || spoint)
        rc = field_point(db, n, point ? "--point" : "--source-point", point ? point : spoint, meshp, out);
    else if (!(rc = query_id(src, n, input, &x))) {
        double *d = malloc((n ? n : 1) * sizeof *d);
        gs_error err = {0};
        if (!d)
            rc = fail(EXIT_RUNTIME, "out of memory");
        else if ((rc = input ? gs_db_input_field(db, x, d, &err) : gs_db_field(db, x, d, &err)))
            rc = lib_fail("field", rc, &err);
        else
            rc = write_text(out, d, n);
        free(d);
    }
    gs_db_free(db);
    return rc;
}

/* ---- eval / land ------------------------------------------------------------ */

/* Average of the per-source errors of fields produced by `field_fn`. */
typedef int (*field_fn)(const void *obj, uint32_t x, double *out, gs_error *err);

static int db_field_fn(const void *obj, uint32_t x, double *out, gs_error *err)
{
    return gs_db_field(obj, x, out, err);
}

static int land_field_fn(const void *obj, uint32_t x, double *out, gs_error *err)
{
    return gs_land_field(obj, x, out, err);
}

/* Near pairs: exact d below this fraction of the median exact d (eval). */
#define NEAR_FRAC 0.1

static int evaluate(const gs_gt *gt, field_fn fn, const void *obj, gs_error_stats *st, double *secs)
{
    uint32_t n = gt->n_vertices;
    double *d = malloc((n ? n : 1) * sizeof *d);
    gs_error_acc *acc = NULL;
    gs_error err = {0};
    if (!d || gs_error_acc_create(&acc, &err)) {
        free(d);
        return fail(EXIT_RUNTIME, "out of memory");
    }
    int rc = 0;
    *secs = 0;
    for (uint32_t j = 0; j < gt->n_sources && !rc; ++j) {
        double t0 = now();
        if ((rc = fn(obj, gt->sources[j], d, &err))) {
            rc = lib_fail("eval", rc, &err);
            break;
        }
        *secs += now() - t0;
        if ((rc = gs_error_acc_add(acc, gt->dist + (size_t)j * n, d, n, gt->sources[j], &err)))
            rc = lib_fail("eval", rc, &err);
    }
    if (!rc && (rc = gs_error_acc_result(acc, NEAR_FRAC, st, &err))) rc = lib_fail("eval", rc, &err);
    gs_error_acc_free(acc);
    free(d);
    return rc;
}

static void print_errors(const gs_error_stats *e)
{
    char near[32] = "- (no near pair)";
    if (e->n_near) snprintf(near, sizeof near, "%.3f%%", 100 * e->near_me);
    printf("ME %.3f%%  RMSE %.3f%%  p99 %.3f%%  p99.9 %.3f%%  max %.3f%%  near-pair ME %s\n", 100 * e->me,
           100 * e->rmse, 100 * e->p99, 100 * e->p999, 100 * e->max, near);
    printf("  (%u sources, %llu pairs, %llu skipped, %llu invalid; ME, RMSE: per source, averaged; p99, p99.9,\n"
           "  max: over all pairs; near pairs: exact d < %g%% of the median exact d %.6g, %llu pairs)\n",
           e->n_fields, (unsigned long long)e->n_used, (unsigned long long)e->n_skipped,
           (unsigned long long)e->n_invalid, 100 * e->near_frac, e->median_d, (unsigned long long)e->n_near);
    printf("  max underestimate %.3f%%, max overestimate %.3f%%; pairs off by > 5%%: %llu under, %llu over\n",
           100 * e->max_under, 100 * e->max_over, (unsigned long long)e->n_under_5pct,
           (unsigned long long)e->n_over_5pct);
}

static int read_gt(const char *path, uint32_t n, gs_gt **gt)
{
    gs_error err = {0};
    int rc = gs_gt_read(path, gt, &err);
    if (rc) return lib_fail(path, rc, &err);
    if ((*gt)->n_vertices != n) {
        rc = fail(EXIT_RUNTIME, "%s: made for %u vertices, but the mesh/database has %u", path,
                  (*gt)->n_vertices, n);
        gs_gt_free(*gt);
        *gt = NULL;
    }
    return rc;
}

int cmd_eval(int argc, char **argv)
{
    const char *dbp = NULL, *gtp = NULL, *v;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_eval, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "--groundtruth"))) gtp = v;
        else if (argv[i][0] == '-')
            return fail(EXIT_USAGE, "eval: unknown or incomplete option '%s' (see geosep eval --help)", argv[i]);
        else if (!dbp) dbp = argv[i];
        else return fail(EXIT_USAGE, "eval: unexpected argument '%s'", argv[i]);
    }
    if (!dbp || !gtp) return fail(EXIT_USAGE, "eval: need DB --groundtruth FILE.gt");
    gs_db *db = NULL;
    int rc = open_db(dbp, &db);
    if (rc) return rc;
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    gs_gt *gt = NULL;
    gs_error_stats e;
    double secs = 0;
    if (!(rc = read_gt(gtp, info.n_vertices, &gt)) && !(rc = evaluate(gt, db_field_fn, db, &e, &secs))) {
        print_errors(&e);
        printf("cost %.1f numbers/vertex, %.1f bytes/vertex, depth avg %.2f max %u, %u leaves, %u curves\n",
               info.cost, info.bytes_per_vertex, info.avg_depth, info.max_depth, info.n_leaves, info.n_curves);
        printf("query time %.1f ns per pair (through %u fields)\n",
               1e9 * secs / ((double)gt->n_sources * info.n_vertices), gt->n_sources);
        print_params(&info);
    }
    gs_gt_free(gt);
    gs_db_free(db);
    return rc;
}

int cmd_land(int argc, char **argv)
{
    const char *mp = NULL, *gtp = NULL, *v;
    uint32_t m = 0;
    gs_method method = GS_METHOD_EXACT;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_land, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "--groundtruth"))) gtp = v;
        else if ((v = opt_value(argc, argv, &i, "--landmarks"))) {
            if (parse_u32(v, &m) || m == 0) return fail(EXIT_USAGE, "land: --landmarks '%s' is not a positive count", v);
        } else if ((v = opt_value(argc, argv, &i, "--method"))) {
            gs_error e = {0};
            if (gs_method_from_name(v, &method, &e)) return fail(EXIT_USAGE, "land: %s", e.message);
        } else if (argv[i][0] == '-')
            return fail(EXIT_USAGE, "land: unknown or incomplete option '%s' (see geosep land --help)", argv[i]);
        else if (!mp) mp = argv[i];
        else return fail(EXIT_USAGE, "land: unexpected argument '%s'", argv[i]);
    }
    if (!mp || !gtp || !m) return fail(EXIT_USAGE, "land: need MESH --landmarks M --groundtruth FILE.gt");
    gs_mesh *mesh = NULL;
    int rc = load_mesh(mp, &mesh);
    if (rc) return rc;
    gs_gt *gt = NULL;
    gs_land *land = NULL;
    gs_error err = {0};
    gs_error_stats e;
    double secs = 0, t0 = now();
    if (!(rc = read_gt(gtp, gs_mesh_num_vertices(mesh), &gt))) {
        if ((rc = gs_land_build(mesh, m, method, &land, &err)))
            rc = lib_fail("land", rc, &err);
        else if (!(rc = evaluate(gt, land_field_fn, land, &e, &secs))) {
            printf("LAND m=%u (build %.2f s)\n", m, now() - t0 - secs);
            print_errors(&e);
        }
    }
    gs_land_free(land);
    gs_gt_free(gt);
    gs_mesh_free(mesh);
    return rc;
}
