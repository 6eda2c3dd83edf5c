/* geosep.c - the geosep command: mesh health reports, generated meshes and
 * geodesic distance fields (text, or GEOGT1 ground-truth files), built on
 * the public API only. Exit status: 0 ok, 1 runtime error, 2 usage error. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>


/* ---- messages ----------------------------------------------------------- */


/* ---- usage -------------------------------------------------------------- */

static const char usage_info[] =
    "usage: geosep info MESH [--repair]\n"
    "  Print the mesh health report: counts, components, boundary loops, Euler\n"
    "  characteristic, genus, corner angles, edge lengths, bounding box.\n"
    "  MESH: .obj .off .ply .stl\n"
    "  --repair: repair the mesh in memory first (geosep repair --help says how;\n"
    "  what was done goes to stderr) and report on the repaired mesh.\n";

static const char usage_generate[] =
    "usage: geosep generate SPEC -o OUT.obj\n"
    "  Write a generated mesh as OBJ. SPEC is one of:\n"
    "    grid:NX,NY[,W,H]  peaks:N[,W]  plate:N  cylinder:NU,NV[,R,H]  cone:NU,NV[,R,H]\n"
    "    cube:N[,S]  torus:NU,NV[,R,r]  knot:NU,NV[,r]  sphere:N  two:N  graded:N[,P]\n";

static const char usage_subdivide[] =
    "usage: geosep subdivide MESH -o OUT.obj [--times N]\n"
    "  Split every face into four by its edge midpoints, N times (default 1, at\n"
    "  most 4): the same polyhedral surface, so the same geodesic distances, with\n"
    "  about 4^N times the faces. Vertex ids are kept; each level appends its\n"
    "  edges' midpoints in order of first appearance. (The scaling benchmark's\n"
    "  homer-60k x4 and x16 are `--times 1` and `--times 2` of homer-60k.)\n";

static const char usage_solve[] =
    "usage: geosep solve MESH --source V [--source V ...] [--source-point F:b0,b1,b2 ...]\n"
    "                    [--method exact|graph|fmm|heat|dgg] [--max-distance D] [-o OUT] [--verbose] [--repair]\n"
    "       geosep solve MESH --format gt (--sources-from FILE.gt | --random K [--seed S] | --all) -o OUT.gt\n"
    "                    [--method exact|graph|fmm|heat|dgg] [--verbose]\n"
    "       method parameters: [--heat-time M] [--heat-refine N|auto] [--fmm-start R] [--dgg-eps E]\n"
    "  Geodesic distances from the sources to every vertex. Text output: one\n"
    "  distance per line in vertex order (\"%.17g\", \"inf\" if unreachable), the\n"
    "  minimum over all sources, to OUT or stdout. --source V is a vertex id\n"
    "  (0-based); --source-point F:b0,b1,b2 is a point of face F (0-based) with\n"
    "  barycentric coordinates b >= 0 summing to 1. --max-distance D > 0 stops\n"
    "  at D (vertices farther away print a value > D or inf; 0 = no bound).\n"
    "  --format gt: solve each source listed in FILE.gt (GEOGT1), or K sources\n"
    "  drawn as the shared ground truth draws them (splitmix64, --seed, default\n"
    "  0), or with --all every vertex used by a face (for errors over all vertex\n"
    "  pairs: n fields of n distances), separately, and write all fields to OUT.gt. Files are written\n"
    "  atomically. --heat-time M: heat method time step t = M h^2 (h: mean edge\n"
    "  length weighted by triangle area; default 1). --heat-refine N: solve\n"
    "  heat on the mesh subdivided 1-to-4 N times (midpoint subdivision: the\n"
    "  same surface; 0 to 3, default 0; h is then the subdivided mesh's) and\n"
    "  read the distances back at the vertices; auto: as geosep build chooses\n"
    "  by default (N subdivisions to reach 32,000 vertices, at most 2), for the\n"
    "  fields its databases reproduce. --fmm-start R: fast\n"
    "  marching starts from exact distances within R mean edge lengths of the\n"
    "  sources (default 4; 0: the plain march from the source vertices).\n"
    "  --dgg-eps E: dgg (discrete geodesic graph) target relative error: the\n"
    "  graph is pruned to within 1 + E, and E sets the radius of the exact\n"
    "  local runs that build it (default 0.001; 1e-5 to 0.5; smaller: slower\n"
    "  to build, more accurate).\n"
    "  --repair (text output): repair the mesh in memory first (geosep repair\n"
    "  --help; what was done goes to stderr). Ids stay the input's: a source\n"
    "  vertex stands for every vertex it became (a split vertex: all its copies),\n"
    "  a source face for the face it became; one line per input vertex, its\n"
    "  distance (a split vertex: the least over its copies; a welded vertex: the\n"
    "  vertex it was welded into).\n";

static void print_usage(FILE *f)
{
    fprintf(f,
            "geosep %s - geodesic distances on triangle meshes\n\n"
            "usage: geosep COMMAND [ARGS]   (geosep help COMMAND, geosep COMMAND --help)\n\n"
            "commands:\n"
            "  info MESH                       mesh health report\n"
            "  repair MESH -o OUT.obj          repair a flawed mesh, say what was done\n"
            "  generate SPEC -o OUT.obj        write a generated test mesh\n"
            "  subdivide MESH -o OUT.obj       1-to-4 midpoint subdivision (same surface)\n"
            "  solve MESH --source V ...       distance field from sources\n"
            "  path DB X Y --mesh MESH         geodesic path from a database (a polyline)\n"
            "  path --exact MESH X Y           exact shortest path (a polyline)\n"
            "  build MESH -o DB                build a query database\n"
            "  query DB X Y                    approximate geodesic distance\n"
            "  query DB --points FILE          ... between surface points (face, weights)\n"
            "  verify DB                       check a database whole (checksums, records)\n"
            "  field DB --source X             distances from X through the database\n"
            "  within DB X R                   every vertex within distance R of X\n"
            "  sample DB K [--seed S]          farthest-point sampling: K vertex ids\n"
            "  eval DB --groundtruth F.gt      accuracy against exact distances\n"
            "  land MESH --landmarks M ...     the LAND baseline, evaluated\n"
            "  render MESH -o OUT.png ...      a picture: field, isolines, separators\n"
            "  help [COMMAND]                  this text, or a command's usage\n"
            "  version                         print the version\n",
            gs_version_string());
}


/* ---- info --------------------------------------------------------------- */

static void print_report(const char *path, const gs_mesh_report *r)
{
    printf("mesh           %s\n", path);
    printf("vertices       %u (%u unreferenced)\n", r->n_vertices, r->n_unreferenced);
    printf("faces          %u\n", r->n_faces);
    printf("edges          %u\n", r->n_edges);
    printf("components     %u\n", r->n_components);
    printf("boundary       %u edges in %u loops\n", r->n_boundary_edges, r->n_boundary_loops);
    printf("euler          %d\n", r->euler);
    printf("genus          %d\n", r->genus);
    printf("angles (deg)   min %.6g max %.6g\n", r->min_angle_deg, r->max_angle_deg);
    printf("edge length    min %.6g mean %.6g max %.6g\n", r->min_edge, r->mean_edge, r->max_edge);
    printf("bbox           [%.6g, %.6g, %.6g] - [%.6g, %.6g, %.6g]\n", r->bbox_min[0], r->bbox_min[1],
           r->bbox_min[2], r->bbox_max[0], r->bbox_max[1], r->bbox_max[2]);
}

static int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int repair = 0, n_args = 0;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_info, stdout), 0;
        if (!strcmp(argv[i], "--repair")) repair = 1;
        else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "info: unknown option '%s' (see geosep info --help)", argv[i]);
        else path = argv[i], n_args++;
    }
    if (n_args != 1) {
        fputs(usage_info, stderr);
        return fail(EXIT_USAGE, "info: expected exactly one MESH argument");
    }
    gs_mesh *m = NULL;
    int rc = load_mesh_opt(path, repair, &m, NULL);
    if (rc) return rc;
    gs_mesh_report r;
    gs_error err = {0};
    rc = gs_mesh_get_report(m, &r, &err);
    if (rc == GS_OK) print_report(path, &r);
    gs_mesh_free(m);
    return rc ? lib_fail("info", rc, &err) : 0;
}

/* ---- generate ----------------------------------------------------------- */

static int cmd_generate(int argc, char **argv)
{
    const char *spec = NULL, *out = NULL;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_generate, stdout), 0;
        if (!strcmp(argv[i], "-o")) {
            if (++i == argc) return fail(EXIT_USAGE, "generate: -o needs a file name");
            out = argv[i];
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return fail(EXIT_USAGE, "generate: unknown option '%s' (see geosep generate --help)", argv[i]);
        } else if (!spec) {
            spec = argv[i];
        } else {
            return fail(EXIT_USAGE, "generate: unexpected argument '%s'", argv[i]);
        }
    }
    if (!spec || !out) {
        fputs(usage_generate, stderr);
        return fail(EXIT_USAGE, "generate: %s", !spec ? "missing SPEC" : "missing -o OUT.obj");
    }
    gs_mesh *m = NULL;
    gs_error err = {0};
    int rc = gs_mesh_generate(spec, &m, &err);
    if (rc) return fail(rc == GS_EARG ? EXIT_USAGE : EXIT_RUNTIME, "generate: %s", err.message);
    rc = gs_mesh_save_obj(m, out, &err);
    gs_mesh_free(m);
    return rc ? lib_fail("generate", rc, &err) : 0;
}

/* ---- subdivide ---------------------------------------------------------- */

#define SUBDIVIDE_MAX 4

static int cmd_subdivide(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *v;
    uint32_t times = 1;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_subdivide, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "-o"))) out = v;
        else if ((v = opt_value(argc, argv, &i, "--times"))) {
            if (parse_u32(v, &times) || times < 1 || times > SUBDIVIDE_MAX)
                return fail(EXIT_USAGE, "subdivide: --times '%s' must be an integer from 1 to %d", v, SUBDIVIDE_MAX);
        } else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "subdivide: unknown or incomplete option '%s' (see geosep subdivide --help)",
                        argv[i]);
        else if (!in) in = argv[i];
        else return fail(EXIT_USAGE, "subdivide: unexpected argument '%s'", argv[i]);
    }
    if (!in || !out) {
        fputs(usage_subdivide, stderr);
        return fail(EXIT_USAGE, "subdivide: %s", !in ? "missing MESH" : "missing -o OUT.obj");
    }
    gs_mesh *m = NULL;
    int rc = load_mesh(in, &m);
    if (rc) return rc;
    gs_error err = {0};
    for (uint32_t k = 0; k < times && rc == GS_OK; ++k) {
        gs_mesh *next = NULL;
        rc = gs_mesh_subdivide(m, &next, &err);
        gs_mesh_free(m);
        m = next;
    }
    if (rc == GS_OK) rc = gs_mesh_save_obj(m, out, &err);
    if (rc == GS_OK)
        printf("%s: %u vertices, %u faces\n", out, gs_mesh_num_vertices(m), gs_mesh_num_faces(m));
    gs_mesh_free(m);
    return rc ? lib_fail("subdivide", rc, &err) : 0;
}

/* ---- solve: options ------------------------------------------------------ */

typedef struct solve_opts {
    const char *mesh, *out, *sources_from;
    gs_method method;
    gs_solver_options sopt;
    double max_d;
    int gt, verbose, all, repair;
    uint32_t random_k, seed; /* --random K --seed S (GEOGT1 output) */
    gs_source *src;
    uint32_t n_src, cap_src;
    const char **src_arg; /* the argument each source came from */
} solve_opts;

static int add_source(solve_opts *o, gs_source s, const char *arg)
{
    if (o->n_src == o->cap_src) {
        uint32_t cap = o->cap_src ? 2 * o->cap_src : 8;
        gs_source *p = realloc(o->src, cap * sizeof *p);
        const char **q = p ? realloc(o->src_arg, cap * sizeof *q) : NULL;
        if (p) o->src = p;
        if (!p || !q) return fail(EXIT_RUNTIME, "out of memory");
        o->src_arg = q;
        o->cap_src = cap;
    }
    o->src_arg[o->n_src] = arg;
    o->src[o->n_src++] = s;
    return 0;
}

/* "F:b0,b1,b2" */
static int solve_option(solve_opts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--all")) return o->all = 1, 0;
    static const char *const with_value[] = {"--source", "--source-point", "--method", "--max-distance",
                                             "--format", "--sources-from", "--random", "--seed", "-o",
                                             "--heat-time", "--fmm-start", "--heat-refine", "--dgg-eps"};
    for (size_t k = 0; k < sizeof with_value / sizeof *with_value; ++k) {
        if (!is_opt(a, with_value[k])) continue;
        if (!(v = opt_value(argc, argv, i, with_value[k])) || !*v)
            return fail(EXIT_USAGE, "solve: %s needs a value", with_value[k]);
        switch (k) {
        case 0: {
            uint32_t x;
            if (parse_u32(v, &x)) return fail(EXIT_USAGE, "solve: --source '%s': expected a vertex id (integer >= 0)", v);
            return add_source(o, gs_source_vertex(x), v);
        }
        case 1: {
            gs_source s;
            if (parse_source_point(v, &s))
                return fail(EXIT_USAGE, "solve: --source-point '%s': expected F:b0,b1,b2 (face id, three barycentric coordinates)", v);
            return add_source(o, s, v);
        }
        case 2: {
            gs_error err = {0};
            if (gs_method_from_name(v, &o->method, &err))
                return fail(EXIT_USAGE, "solve: --method '%s': expected exact, graph, fmm, heat or dgg", v);
            return 0;
        }
        case 3:
            if (parse_double(v, &o->max_d) || o->max_d < 0)
                return fail(EXIT_USAGE, "solve: --max-distance '%s': expected a number >= 0 (0 or inf: no bound)", v);
            return 0;
        case 4:
            if (strcmp(v, "gt") && strcmp(v, "text"))
                return fail(EXIT_USAGE, "solve: --format '%s': expected text or gt", v);
            o->gt = !strcmp(v, "gt");
            return 0;
        case 5: o->sources_from = v; return 0;
        case 6:
            if (parse_u32(v, &o->random_k) || o->random_k == 0)
                return fail(EXIT_USAGE, "solve: --random '%s': expected a positive count", v);
            return 0;
        case 7:
            if (parse_u32(v, &o->seed)) return fail(EXIT_USAGE, "solve: --seed '%s': expected an integer >= 0", v);
            return 0;
        case 9:
            if (parse_double(v, &o->sopt.heat_time) || !(o->sopt.heat_time >= GS_HEAT_TIME_MIN) ||
                !(o->sopt.heat_time <= GS_HEAT_TIME_MAX))
                return fail(EXIT_USAGE, "solve: --heat-time '%s': expected a number in [%g, %g]", v, GS_HEAT_TIME_MIN,
                            GS_HEAT_TIME_MAX);
            return 0;
        case 10:
            if (parse_double(v, &o->sopt.fmm_exact_start) || !(o->sopt.fmm_exact_start >= 0) ||
                !isfinite(o->sopt.fmm_exact_start))
                return fail(EXIT_USAGE, "solve: --fmm-start '%s': expected a number >= 0", v);
            return 0;
        case 11:
            if (parse_heat_refine(v, &o->sopt.heat_refine))
                return fail(EXIT_USAGE, "solve: --heat-refine '%s': expected 0 to %d or auto", v, GS_HEAT_REFINE_MAX);
            return 0;
        case 12:
            if (parse_double(v, &o->sopt.dgg_eps) || !(o->sopt.dgg_eps >= GS_DGG_EPS_MIN) ||
                !(o->sopt.dgg_eps <= GS_DGG_EPS_MAX))
                return fail(EXIT_USAGE, "solve: --dgg-eps '%s': expected a number in [%g, %g]", v, GS_DGG_EPS_MIN,
                            GS_DGG_EPS_MAX);
            return 0;
        default: o->out = v; return 0;
        }
    }
    if (!strcmp(a, "--verbose") || !strcmp(a, "-v")) return o->verbose = 1, 0;
    if (!strcmp(a, "--repair")) return o->repair = 1, 0;
    return fail(EXIT_USAGE, "solve: unknown option '%s' (see geosep solve --help)", a);
}

static int check_solve_opts(const solve_opts *o)
{
    if (!o->mesh) return fail(EXIT_USAGE, "solve: missing MESH");
    if (o->gt) {
        if (o->repair)
            return fail(EXIT_USAGE, "solve: --repair answers by input vertex in text output; --format gt is not "
                        "supported with it (repair the file with geosep repair, then solve the repaired mesh)");
        if ((o->sources_from != NULL) + (o->random_k != 0) + o->all != 1)
            return fail(EXIT_USAGE, "solve: --format gt needs one of --sources-from FILE.gt, --random K, --all");
        if (!o->out || !strcmp(o->out, "-")) return fail(EXIT_USAGE, "solve: --format gt needs -o OUT.gt");
        if (o->n_src) return fail(EXIT_USAGE, "solve: --format gt takes its sources from --sources-from, not --source");
        if (o->max_d != 0 && !isinf(o->max_d))
            return fail(EXIT_USAGE, "solve: --format gt writes complete fields; --max-distance is not allowed");
        return 0;
    }
    if (o->sources_from) return fail(EXIT_USAGE, "solve: --sources-from needs --format gt");
    if (o->random_k) return fail(EXIT_USAGE, "solve: --random needs --format gt");
    if (o->all) return fail(EXIT_USAGE, "solve: --all needs --format gt");
    if (!o->n_src) return fail(EXIT_USAGE, "solve: no source given (--source V or --source-point F:b0,b1,b2)");
    return 0;
}

static int parse_solve(solve_opts *o, int argc, char **argv)
{
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_solve, stdout), -1;
        if (argv[i][0] == '-' && argv[i][1]) {
            int rc = solve_option(o, argc, argv, &i);
            if (rc) return rc;
        } else if (!o->mesh) {
            o->mesh = argv[i];
        } else {
            return fail(EXIT_USAGE, "solve: unexpected argument '%s' (one MESH only)", argv[i]);
        }
    }
    return check_solve_opts(o);
}

/* Range checks that need the mesh: exit status 2, naming the argument. */
static int check_sources(const solve_opts *o, const gs_mesh *m, const gs_repair *r)
{
    uint32_t nv = r ? r->n_input_vertices : gs_mesh_num_vertices(m), nf = r ? r->n_input_faces : gs_mesh_num_faces(m);
    for (uint32_t i = 0; i < o->n_src; ++i) {
        const gs_source *s = &o->src[i];
        if (s->face == GS_NONE) {
            if (s->vertex >= nv)
                return fail(EXIT_USAGE, "solve: --source %s: vertex out of range (the mesh has %u vertices: 0..%u)",
                            o->src_arg[i], nv, nv - 1);
            continue;
        }
        if (s->face >= nf)
            return fail(EXIT_USAGE, "solve: --source-point %s: face out of range (the mesh has %u faces)",
                        o->src_arg[i], nf);
        double sum = s->bary[0] + s->bary[1] + s->bary[2];
        if (!(s->bary[0] >= 0 && s->bary[1] >= 0 && s->bary[2] >= 0) || !(fabs(sum - 1) <= 1e-9))
            return fail(EXIT_USAGE, "solve: --source-point %s: barycentric coordinates must be >= 0 and sum to 1 (sum %.17g)",
                        o->src_arg[i], sum);
    }
    return 0;
}

/* ---- solve: running ----------------------------------------------------- */

typedef struct run_ctx {
    gs_mesh *mesh;
    gs_repair *rep; /* --repair: what was done, the vertex map */
    gs_patch *patch;
    gs_solver *solver;
    double t_load, t_solve;
    uint64_t windows;
} run_ctx;

static int prepare(const solve_opts *o, run_ctx *c)
{
    double t0 = now();
    int rc = load_mesh_opt(o->mesh, o->repair, &c->mesh, &c->rep);
    if (rc) return rc;
    c->t_load = now() - t0;
    gs_error err = {0};
    if ((rc = gs_patch_create(c->mesh, NULL, 0, &c->patch, &err)) ||
        (rc = gs_solver_create_ex(c->patch, o->method, &o->sopt, &c->solver, &err)))
        return lib_fail("solve", rc, &err);
    return 0;
}

static int run_solve(run_ctx *c, const gs_source *s, uint32_t n, double max_d, double *dist)
{
    gs_error err = {0};
    double t0 = now();
    int rc = gs_solver_solve(c->solver, s, n, max_d, dist, &err);
    c->t_solve += now() - t0;
    uint64_t w = 0;
    gs_solver_last_stats(c->solver, &w, NULL, NULL);
    c->windows += w;
    return rc ? lib_fail("solve", rc, &err) : 0;
}

/* --repair: the sources by input id as sources on the repaired mesh (a
 * vertex: every vertex it became; a point: on the face its face became). */
static int repaired_sources(const solve_opts *o, const gs_repair *r, gs_source **out, uint32_t *n_out)
{
    uint32_t n = 0, cap = 0;
    gs_source *s = NULL;
    for (uint32_t i = 0; i < o->n_src; ++i) {
        const gs_source *x = &o->src[i];
        uint32_t k0 = 0, k1 = 1;
        if (x->face == GS_NONE) k0 = r->alias_start[x->vertex], k1 = r->alias_start[x->vertex + 1];
        for (uint32_t k = k0; k < k1; ++k) {
            if (n == cap) {
                cap = cap ? 2 * cap : 16;
                gs_source *p = realloc(s, cap * sizeof *p);
                if (!p) return free(s), fail(EXIT_RUNTIME, "out of memory");
                s = p;
            }
            if (x->face == GS_NONE) {
                s[n++] = gs_source_vertex(r->alias[k]);
                continue;
            }
            uint32_t g = GS_NONE, hits = 0;
            for (uint32_t f = 0; f < r->n_faces; ++f)
                if (r->face_origin[f] == x->face) g = f, hits++;
            const char *why = !hits ? "was removed by the repair (zero-area, duplicate or repeating a vertex)"
                              : r->face_change[g] == GS_REPAIR_FACE_SPLIT ? "was split by the repair"
                                                                          : NULL;
            if (why) {
                free(s);
                return fail(EXIT_USAGE, "solve: --source-point %s: face %u %s; give a vertex source instead",
                            o->src_arg[i], x->face, why);
            }
            if (r->face_change[g] == GS_REPAIR_FACE_FLIPPED)
                s[n++] = gs_source_point(g, x->bary[0], x->bary[2], x->bary[1]);
            else
                s[n++] = gs_source_point(g, x->bary[0], x->bary[1], x->bary[2]);
        }
    }
    *out = s;
    *n_out = n;
    return 0;
}

static int solve_text(const solve_opts *o, run_ctx *c)
{
    uint32_t n = gs_mesh_num_vertices(c->mesh);
    double *d = malloc((n ? n : 1) * sizeof *d);
    if (!d) return fail(EXIT_RUNTIME, "out of memory");
    const gs_repair *r = c->rep;
    gs_source *src = o->src;
    uint32_t n_src = o->n_src;
    int rc = r ? repaired_sources(o, r, &src, &n_src) : 0;
    if (!rc) rc = run_solve(c, src, n_src, o->max_d, d);
    if (!rc && r) { /* by input vertex: the least over what it became */
        double *byin = malloc(((size_t)r->n_input_vertices + 1) * sizeof *byin);
        if (!byin) rc = fail(EXIT_RUNTIME, "out of memory");
        for (uint32_t v = 0; byin && v < r->n_input_vertices; ++v) {
            double best = INFINITY;
            for (uint32_t k = r->alias_start[v]; k < r->alias_start[v + 1]; ++k)
                if (d[r->alias[k]] < best) best = d[r->alias[k]];
            byin[v] = best;
        }
        free(d);
        d = byin;
        n = r->n_input_vertices;
    }
    if (!rc) rc = write_text(o->out, d, n);
    if (src != o->src) free(src);
    free(d);
    return rc;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The sources of a GEOGT1 run: those of --sources-from, --random K, or
 * --all (every vertex used by a face, in increasing id order). */
static int gt_sources(const solve_opts *o, const gs_mesh *m, uint32_t **src, uint32_t *k)
{
    gs_error err = {0};
    uint32_t n = gs_mesh_num_vertices(m);
    if (o->all) {
        gs_mesh_report r;
        int rc = gs_mesh_get_report(m, &r, &err);
        if (rc) return lib_fail(o->mesh, rc, &err);
        *k = n - r.n_unreferenced;
        if (!*k) return fail(EXIT_USAGE, "solve: --all: no vertex of %s is used by a face", o->mesh);
        if (!(*src = malloc(*k * sizeof **src))) return fail(EXIT_RUNTIME, "out of memory");
        if ((rc = gs_mesh_random_vertices(m, *k, 0, *src, &err))) return lib_fail(o->mesh, rc, &err);
        qsort(*src, *k, sizeof **src, cmp_u32);
        return 0;
    }
    if (o->random_k) {
        *k = o->random_k;
        if (!(*src = malloc(*k * sizeof **src))) return fail(EXIT_RUNTIME, "out of memory");
        int rc = gs_mesh_random_vertices(m, *k, o->seed, *src, &err);
        return rc ? fail(EXIT_USAGE, "solve: --random: %s", err.message) : 0;
    }
    gs_gt *gt = NULL;
    int rc = gs_gt_read(o->sources_from, &gt, &err);
    if (rc) return lib_fail(o->sources_from, rc, &err);
    if (gt->n_vertices != n)
        rc = fail(EXIT_RUNTIME, "%s: made for %u vertices, but %s has %u", o->sources_from, gt->n_vertices,
                  o->mesh, n);
    *k = gt->n_sources;
    *src = gt->sources; /* taken over */
    gt->sources = NULL;
    gs_gt_free(gt);
    return rc;
}

static int solve_gt(const solve_opts *o, run_ctx *c)
{
    uint32_t *src = NULL, k = 0, n = gs_mesh_num_vertices(c->mesh);
    gs_error err = {0};
    double *d = NULL;
    int rc = gt_sources(o, c->mesh, &src, &k);
    if (!rc && !(d = malloc(((size_t)n * k + 1) * sizeof *d)))
        rc = fail(EXIT_RUNTIME, "out of memory for %u fields of %u vertices", k, n);
    for (uint32_t j = 0; !rc && j < k; ++j) {
        gs_source s = gs_source_vertex(src[j]);
        rc = run_solve(c, &s, 1, 0, d + (size_t)j * n);
    }
    if (!rc && (rc = gs_gt_write(o->out, n, k, src, d, &err))) rc = lib_fail(o->out, rc, &err);
    free(d);
    free(src);
    return rc;
}

static int cmd_solve(int argc, char **argv)
{
    solve_opts o = {0};
    o.method = GS_METHOD_EXACT;
    gs_solver_options_default(&o.sopt);
    run_ctx c = {0};
    int rc = parse_solve(&o, argc, argv);
    if (rc < 0) {
        rc = 0; /* --help */
        goto done;
    }
    if (rc) goto done;
    if ((rc = prepare(&o, &c)) || (rc = check_sources(&o, c.mesh, c.rep))) goto done;
    rc = o.gt ? solve_gt(&o, &c) : solve_text(&o, &c);
    if (!rc && o.verbose) { /* windows: the exact solver's (fmm's exact start included) */
        fprintf(stderr, "geosep: %s, %u vertices, %s: load %.3f s, solve %.3f s", o.mesh, gs_mesh_num_vertices(c.mesh),
                gs_method_name(o.method), c.t_load, c.t_solve);
        if (o.method == GS_METHOD_EXACT || c.windows) fprintf(stderr, ", %llu windows", (unsigned long long)c.windows);
        fputc('\n', stderr);
    }
done:
    gs_solver_free(c.solver);
    gs_patch_free(c.patch);
    gs_mesh_free(c.mesh);
    gs_repair_free(c.rep);
    free(o.src);
    free(o.src_arg);
    return rc;
}

/* ---- dispatch ----------------------------------------------------------- */

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *usage;
} command;

static const command commands[] = {
    {"info", cmd_info, usage_info},
    {"repair", cmd_repair, usage_repair},
    {"generate", cmd_generate, usage_generate},
    {"subdivide", cmd_subdivide, usage_subdivide},
    {"solve", cmd_solve, usage_solve},
    {"path", cmd_path, usage_path},
    {"build", cmd_build, usage_build},
    {"query", cmd_query, usage_query},
    {"verify", cmd_verify, usage_verify},
    {"field", cmd_field, usage_field},
    {"within", cmd_within, usage_within},
    {"sample", cmd_sample, usage_sample},
    {"eval", cmd_eval, usage_eval},
    {"land", cmd_land, usage_land},
    {"render", cmd_render, usage_render},
};

static const command *find_command(const char *name)
{
    for (size_t i = 0; i < sizeof commands / sizeof *commands; ++i)
        if (!strcmp(commands[i].name, name)) return &commands[i];
    return NULL;
}

static int cmd_help(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "help")) return print_usage(stdout), 0;
    const command *c = find_command(argv[1]);
    if (!c) return fail(EXIT_USAGE, "help: unknown command '%s'", argv[1]);
    fputs(c->usage, stdout);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_usage(stderr);
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (is_help(cmd) || !strcmp(cmd, "help")) return cmd_help(argc - 1, argv + 1);
    if (!strcmp(cmd, "version") || !strcmp(cmd, "--version")) return printf("geosep %s\n", gs_version_string()), 0;
    const command *c = find_command(cmd);
    if (!c) return fail(EXIT_USAGE, "unknown command '%s' (try geosep --help)", cmd);
    int rc = c->run(argc - 1, argv + 1);
    /* what went to stdout (answers, reports) must have arrived */
    if ((fflush(stdout) != 0 || ferror(stdout)) && !rc) rc = fail(EXIT_RUNTIME, "write error on stdout");
    return rc;
}
