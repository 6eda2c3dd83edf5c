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
    "  --mark V          draw a dot at vertex V (repeatable)\n";

typedef struct render_args {
    const char *mesh, *out, *field, *db, *source, *seps, *size, *view;
    uint32_t isolines;
    uint32_t *marks;
    uint32_t n_marks;
} render_args;

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
    if (rc) {
        free(a.marks);
        return rc < 0 ? 0 : rc;
    }
    gs_mesh *m = NULL;
    gs_db *db = NULL, *sep = NULL;
    double *field = NULL, *pts = NULL;
    gs_error err = {0};
    if ((rc = load_mesh(a.mesh, &m))) goto done;
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
    uint32_t np = a.n_marks + (a.db ? 1 : 0);
    if (np && !(pts = malloc(3 * (size_t)np * sizeof *pts))) {
        rc = fail(EXIT_RUNTIME, "out of memory");
        goto done;
    }
    const double *xyz = gs_mesh_positions(m);
    for (uint32_t i = 0; i < np; ++i) {
        uint32_t v = i < a.n_marks ? a.marks[i] : src;
        memcpy(pts + 3 * (size_t)i, xyz + 3 * (size_t)v, 3 * sizeof *pts);
    }
    o.field = field;
    o.separators = sep;
    o.points = pts;
    o.n_points = np;
    if ((rc = gs_render_png(m, &o, a.out, &err))) rc = lib_fail(a.out, rc, &err);
done:
    if (sep != db) gs_db_free(sep);
    gs_db_free(db);
    gs_mesh_free(m);
    free(field);
    free(pts);
    free(a.marks);
    return rc;
}
