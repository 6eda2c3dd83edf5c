/* render_cmd.c - geosep render: a PNG picture of a mesh, coloured by a
 * distance field (a text file, or a database's field from a vertex) with
 * isolines, optionally with a database's separator curves. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char usage_render[] =
    "usage: geosep render MESH -o OUT.png [--field FILE | --db DB --source V] [--isolines K]\n"
    "                     [--separators DB] [--size WxH] [--view AZIMUTH,ELEVATION] [--mark V ...]\n"
    "                     [--path FILE ...] [--points FILE ...]\n"
    "  Draw the mesh, shaded, into a PNG image (written atomically).\n"
    "  --field FILE      colour by a field: one value per vertex and line, as\n"
    "                    `geosep solve -o FILE` writes it (\"inf\": unreachable, grey)\n"
    "  --db DB --source V  colour by the database's distances from vertex V\n"
    "                    (V is marked with a dot)\n"
    "  --isolines K      K dark isolines, evenly spaced between the field's\n"
    "                    smallest and largest values (default 10; 0: none)\n"
    "  --separators DB   draw the database's separator curves (the root's red and\n"
    "                    widest, deeper ones thinner); DB must be built from MESH\n"
    "  --size WxH        image size in pixels, 16 to 8192 each (default 640x480)\n"
    "  --view AZ,EL      view direction in degrees, y up (default 30,20): 0,0 looks\n"
    "                    from +z, 90,0 from +x, 0,90 from above (+y)\n"
    "  --mark V          draw a dot at vertex V (repeatable)\n"
    "  --path FILE       draw a polyline: `x y z` per line, as `geosep path` writes\n"
    "                    it (lines starting with # skipped; a blank line starts\n"
    "                    another polyline); white in a dark border (repeatable)\n"
    "  --points FILE     draw a dot at each `x y z` line of FILE (repeatable)\n";

typedef struct render_args {
    const char *mesh, *out, *field, *db, *source, *seps, *size, *view;
    uint32_t isolines;
    uint32_t *marks;
    uint32_t n_marks;
    const char **paths, **points; /* files */
    uint32_t n_path_files, n_point_files;
} render_args;

static int add_name(const char ***list, uint32_t *n, const char *v)
{
    const char **p = realloc(*list, (*n + 1) * sizeof *p);
    if (!p) return fail(EXIT_RUNTIME, "out of memory");
    *list = p;
    p[(*n)++] = v;
    return 0;
}

/* Points read from `x y z` files: coordinates, and where each polyline starts. */
typedef struct xyz_list {
    double *xyz;
    uint32_t n, cap;
    uint32_t *start; /* n_runs + 1 */
    uint32_t n_runs, run_cap;
} xyz_list;

static int xyz_push(xyz_list *l, const double *p)
{
    if (l->n == l->cap) {
        uint32_t c = l->cap ? 2 * l->cap : 256;
        double *q = c > l->cap ? realloc(l->xyz, 3 * (size_t)c * sizeof *q) : NULL;
        if (!q) return fail(EXIT_RUNTIME, "out of memory");
        l->xyz = q, l->cap = c;
    }
    memcpy(l->xyz + 3 * (size_t)l->n++, p, 3 * sizeof *p);
    return 0;
}

/* Close the current polyline (if it has points) */
static int xyz_cut(xyz_list *l)
{
    uint32_t last = l->n_runs ? l->start[l->n_runs] : 0;
    if (!l->start) {
        if (!(l->start = calloc(16, sizeof *l->start))) return fail(EXIT_RUNTIME, "out of memory");
        l->run_cap = 15;
    }
    if (l->n == last) return 0;
    if (l->n_runs == l->run_cap) {
        uint32_t *q = realloc(l->start, (2 * (size_t)l->run_cap + 1) * sizeof *q);
        if (!q) return fail(EXIT_RUNTIME, "out of memory");
        l->start = q, l->run_cap *= 2;
    }
    l->start[++l->n_runs] = l->n;
    return 0;
}

/* Read `x y z` lines of path into l; with runs, a blank line ends a polyline
 * (and so does the end of the file). */
static int read_xyz(const char *path, int runs, xyz_list *l)
{
    line_reader r;
    int rc = lines_open(&r, path), got;
    if (!rc && runs) rc = xyz_cut(l);
    while (!rc && (got = lines_next(&r)) != 0) {
        if (got < 0) {
            rc = EXIT_RUNTIME;
            break;
        }
        char *t[4], show[80];
        int nt = split_fields(r.line, t, 4);
        if (nt == 0) {
            if (runs) rc = xyz_cut(l);
            continue;
        }
        if (t[0][0] == '#') continue;
        double p[3];
        if (nt != 3) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: %d fields (expected `x y z`)", path, r.ln, nt > 3 ? 4 : nt);
            break;
        }
        for (int k = 0; k < 3 && !rc; ++k)
            if (parse_double(t[k], &p[k]) || !isfinite(p[k]))
                rc = fail(EXIT_RUNTIME, "%s:%lu: '%s' is not a finite number (expected `x y z`)", path, r.ln,
                          shown(t[k], show, sizeof show));
        if (!rc) rc = xyz_push(l, p);
    }
    lines_close(&r);
    if (!rc && runs) rc = xyz_cut(l);
    return rc;
}

/* "WxH" */
static int parse_size(const char *s, uint32_t *w, uint32_t *h)
{
    char buf[64];
    const char *x = strchr(s, 'x');
    if (!x || (size_t)(x - s) >= sizeof buf) return -1;
    memcpy(buf, s, (size_t)(x - s));
    buf[x - s] = 0;
    return parse_u32(buf, w) || parse_u32(x + 1, h) ? -1 : 0;
}

/* "AZ,EL" */
static int parse_view(const char *s, double *az, double *el)
{
    char buf[128];
    const char *c = strchr(s, ',');
    if (!c || (size_t)(c - s) >= sizeof buf) return -1;
    memcpy(buf, s, (size_t)(c - s));
    buf[c - s] = 0;
    if (parse_double(buf, az) || parse_double(c + 1, el)) return -1;
    return isfinite(*az) && isfinite(*el) ? 0 : -1;
}

static int parse_render(render_args *a, gs_render_options *o, int argc, char **argv)
{
    const char *v;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_render, stdout), -1;
        if ((v = opt_value(argc, argv, &i, "-o"))) a->out = v;
        else if ((v = opt_value(argc, argv, &i, "--field"))) a->field = v;
        else if ((v = opt_value(argc, argv, &i, "--db"))) a->db = v;
        else if ((v = opt_value(argc, argv, &i, "--source"))) a->source = v;
        else if ((v = opt_value(argc, argv, &i, "--separators"))) a->seps = v;
        else if ((v = opt_value(argc, argv, &i, "--isolines"))) {
            if (parse_u32(v, &o->isolines) || o->isolines > GS_RENDER_MAX_ISOLINES)
                return fail(EXIT_USAGE, "render: --isolines '%s': expected an integer from 0 to %u", v,
                            GS_RENDER_MAX_ISOLINES);
        } else if ((v = opt_value(argc, argv, &i, "--size"))) {
            if (parse_size(v, &o->width, &o->height) || o->width < GS_RENDER_MIN_SIZE ||
                o->width > GS_RENDER_MAX_SIZE || o->height < GS_RENDER_MIN_SIZE || o->height > GS_RENDER_MAX_SIZE)
                return fail(EXIT_USAGE, "render: --size '%s': expected WxH, each from %u to %u (e.g. 640x480)", v,
                            GS_RENDER_MIN_SIZE, GS_RENDER_MAX_SIZE);
        } else if ((v = opt_value(argc, argv, &i, "--view"))) {
            if (parse_view(v, &o->azimuth_deg, &o->elevation_deg))
                return fail(EXIT_USAGE, "render: --view '%s': expected AZIMUTH,ELEVATION in degrees (e.g. 30,20)", v);
        } else if ((v = opt_value(argc, argv, &i, "--mark"))) {
            uint32_t x, *p;
            if (parse_u32(v, &x)) return fail(EXIT_USAGE, "render: --mark '%s': expected a vertex id", v);
            if (!(p = realloc(a->marks, (a->n_marks + 1) * sizeof *p))) return fail(EXIT_RUNTIME, "out of memory");
            a->marks = p;
            a->marks[a->n_marks++] = x;
        } else if ((v = opt_value(argc, argv, &i, "--path"))) {
            if (add_name(&a->paths, &a->n_path_files, v)) return EXIT_RUNTIME;
        } else if ((v = opt_value(argc, argv, &i, "--points"))) {
            if (add_name(&a->points, &a->n_point_files, v)) return EXIT_RUNTIME;
        } else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "render: unknown or incomplete option '%s' (see geosep render --help)", argv[i]);
        else if (!a->mesh) a->mesh = argv[i];
        else return fail(EXIT_USAGE, "render: unexpected argument '%s' (one MESH only)", argv[i]);
    }
    if (!a->mesh || !a->out) {
        fputs(usage_render, stderr);
        return fail(EXIT_USAGE, "render: %s", !a->mesh ? "missing MESH" : "missing -o OUT.png");
    }
    if (a->field && (a->db || a->source))
        return fail(EXIT_USAGE, "render: --field and --db/--source exclude each other (one field)");
    if (!a->db != !a->source) return fail(EXIT_USAGE, "render: --db and --source go together");
    return 0;
}

/* The text field of `geosep solve -o`: n values, one per line. */
static int read_field(const char *path, uint32_t n, double *f)
{
    line_reader r;
    int rc = lines_open(&r, path), got;
    uint32_t k = 0;
    while (!rc && (got = lines_next(&r)) != 0) {
        if (got < 0) {
            rc = EXIT_RUNTIME;
            break;
        }
        char *t[2], show[80];
        int nt = split_fields(r.line, t, 2);
        if (nt == 0) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: empty line (expected one value per vertex)", path, r.ln);
        } else if (nt > 1) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: more than one value on the line (expected one value per line)", path, r.ln);
        } else if (parse_double(t[0], &f[k < n ? k : 0])) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: '%s' is not a number (expected one value per line)", path, r.ln,
                      shown(t[0], show, sizeof show));
        } else if (k == n) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: more values than the mesh's %u vertices", path, r.ln, n);
        } else {
            k++;
        }
    }
    lines_close(&r);
    if (!rc && k != n) rc = fail(EXIT_RUNTIME, "%s: %u values, the mesh has %u vertices", path, k, n);
    return rc;
}

static int open_db_for(const char *path, const gs_mesh *m, const char *mesh_path, gs_db **db)
{
    gs_error err = {0};
    int rc = gs_db_open(path, db, &err);
    if (rc) return lib_fail(path, rc, &err);
    gs_db_info info;
    gs_db_get_info(*db, &info, NULL);
    uint32_t nv = gs_mesh_num_vertices(m);
    const double *a = gs_mesh_positions(m), *b = gs_db_positions(*db);
    int same = info.n_vertices == nv;
    for (size_t i = 0; same && i < 3 * (size_t)nv; ++i) same = a[i] == b[i];
    if (!same) return fail(EXIT_RUNTIME, "%s: not built from %s (different vertices)", path, mesh_path);
    return 0;
}

int cmd_render(int argc, char **argv)
{
    render_args a = {0};
    gs_render_options o;
    gs_render_options_default(&o);
    int rc = parse_render(&a, &o, argc, argv);
    xyz_list lines = {0}, dots = {0};
    if (rc) {
        free(a.marks), free(a.paths), free(a.points);
        return rc < 0 ? 0 : rc;
    }
    for (uint32_t i = 0; i < a.n_path_files && !rc; ++i) rc = read_xyz(a.paths[i], 1, &lines);
    for (uint32_t i = 0; i < a.n_point_files && !rc; ++i) rc = read_xyz(a.points[i], 0, &dots);
    gs_mesh *m = NULL;
    gs_db *db = NULL, *sep = NULL;
    double *field = NULL, *pts = NULL;
    gs_error err = {0};
    if (rc || (rc = load_mesh(a.mesh, &m))) goto done;
    uint32_t nv = gs_mesh_num_vertices(m), src = 0;
    if (a.source && (parse_u32(a.source, &src) || src >= nv)) {
        rc = fail(EXIT_USAGE, "render: --source '%s': expected a vertex id below %u", a.source, nv);
        goto done;
    }
    for (uint32_t i = 0; i < a.n_marks; ++i)
        if (a.marks[i] >= nv) {
            rc = fail(EXIT_USAGE, "render: --mark %u: vertex out of range (the mesh has %u vertices)", a.marks[i], nv);
            goto done;
        }
    if ((a.field || a.db) && !(field = malloc((nv ? nv : 1) * sizeof *field))) {
        rc = fail(EXIT_RUNTIME, "out of memory");
        goto done;
    }
    if (a.field && (rc = read_field(a.field, nv, field))) goto done;
    if (a.db) {
        if ((rc = open_db_for(a.db, m, a.mesh, &db))) goto done;
        if ((rc = gs_db_field(db, src, field, &err))) {
            rc = lib_fail("render", rc, &err);
            goto done;
        }
    }
    if (a.seps) {
        if (a.db && !strcmp(a.db, a.seps)) sep = db;
        else if ((rc = open_db_for(a.seps, m, a.mesh, &sep))) goto done;
    }
    uint32_t np = a.n_marks + (a.db ? 1 : 0) + dots.n;
    if (np && !(pts = malloc(3 * (size_t)np * sizeof *pts))) {
        rc = fail(EXIT_RUNTIME, "out of memory");
        goto done;
    }
    const double *xyz = gs_mesh_positions(m);
    for (uint32_t i = 0; i < np - dots.n; ++i) {
        uint32_t v = i < a.n_marks ? a.marks[i] : src;
        memcpy(pts + 3 * (size_t)i, xyz + 3 * (size_t)v, 3 * sizeof *pts);
    }
    if (dots.n) memcpy(pts + 3 * (size_t)(np - dots.n), dots.xyz, 3 * (size_t)dots.n * sizeof *pts);
    o.field = field;
    o.separators = sep;
    o.points = pts;
    o.n_points = np;
    o.paths = lines.xyz;
    o.path_starts = lines.start;
    o.n_paths = lines.n_runs;
    if ((rc = gs_render_png(m, &o, a.out, &err))) rc = lib_fail(a.out, rc, &err);
done:
    if (sep != db) gs_db_free(sep);
    gs_db_free(db);
    gs_mesh_free(m);
    free(field);
    free(pts);
    free(a.marks), free(a.paths), free(a.points);
    free(lines.xyz), free(lines.start), free(dots.xyz), free(dots.start);
    return rc;
}
