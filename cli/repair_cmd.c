/* repair_cmd.c - geosep repair (a flawed mesh file in, a valid OBJ out, the
 * report and the vertex map), and what info, solve and build share for
 * their --repair: loading with repair, the summary on stderr, the vertex
 * map file. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

const char usage_repair[] =
    "usage: geosep repair MESH -o OUT.obj [--report FILE] [--map FILE] [--quiet]\n"
    "  Repair a mesh that geosep info refuses, knowingly (doc/repair.md): faces\n"
    "  naming a vertex twice and duplicate faces are dropped; zero-area faces are\n"
    "  removed without opening holes where possible; boundary edges at exactly\n"
    "  the same positions as one other boundary edge are glued (unwelded seams);\n"
    "  edges of more than two faces keep their best-aligned pair and detach the\n"
    "  others; each component is oriented consistently (a non-orientable one is\n"
    "  cut open); a vertex whose faces form several fans becomes one vertex per\n"
    "  fan. Every input vertex keeps its id and position in OUT.obj; copies are\n"
    "  appended. Prints what was done, each kind of change with its count and\n"
    "  examples (file lines, 0-based vertex ids), to stdout (--quiet: not);\n"
    "  --report FILE writes the same text to FILE; --map FILE the vertex map\n"
    "  (one line per input vertex: its id, then every repaired vertex it became).\n"
    "  Files are written atomically.\n";

int load_mesh_opt(const char *path, int repair, gs_mesh **m, gs_repair **info)
{
    *m = NULL;
    if (info) *info = NULL;
    if (!repair) return load_mesh(path, m);
    gs_error err = {0};
    gs_repair *r = NULL;
    int rc = gs_mesh_repair_file(path, GS_FORMAT_AUTO, m, &r, &err);
    if (rc) return lib_fail(path, rc, &err);
    size_t n = gs_repair_format(r, NULL, 0) + 1;
    char *text = malloc(n);
    if (text) {
        gs_repair_format(r, text, n);
        fprintf(stderr, "geosep: %s", text);
        free(text);
    }
    if (info) *info = r;
    else gs_repair_free(r);
    return 0;
}

int write_vertex_map(const char *path, const gs_repair *r)
{
    out_file o;
    int rc = out_open(&o, path);
    if (rc) return rc;
    fprintf(o.f, "# geosep vertex map: %u input vertices -> %u repaired vertices\n", r->n_input_vertices,
            r->n_vertices);
    fprintf(o.f, "# input_id repaired_id [further repaired ids of the same input vertex]\n");
    for (uint32_t v = 0; v < r->n_input_vertices; ++v) {
        fprintf(o.f, "%u", v);
        for (uint32_t k = r->alias_start[v]; k < r->alias_start[v + 1]; ++k) fprintf(o.f, " %u", r->alias[k]);
        fputc('\n', o.f);
    }
    if (ferror(o.f)) {
        out_abort(&o);
        return fail(EXIT_RUNTIME, "%s: write failed", path);
    }
    return out_commit(&o);
}

static int write_report(const char *path, const gs_repair *r)
{
    size_t n = gs_repair_format(r, NULL, 0) + 1;
    char *text = malloc(n);
    if (!text) return fail(EXIT_RUNTIME, "out of memory");
    gs_repair_format(r, text, n);
    int rc = 0;
    if (path) {
        out_file o;
        rc = out_open(&o, path);
        if (!rc) {
            fputs(text, o.f);
            if (ferror(o.f)) {
                out_abort(&o);
                rc = fail(EXIT_RUNTIME, "%s: write failed", path);
            } else {
                rc = out_commit(&o);
            }
        }
    } else {
        fputs(text, stdout);
    }
    free(text);
    return rc;
}

int cmd_repair(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *report = NULL, *map = NULL, *v;
    int quiet = 0;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_repair, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "-o")) || (v = opt_value(argc, argv, &i, "--output"))) out = v;
        else if ((v = opt_value(argc, argv, &i, "--report"))) report = v;
        else if ((v = opt_value(argc, argv, &i, "--map"))) map = v;
        else if (!strcmp(argv[i], "--quiet")) quiet = 1;
        else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "repair: unknown or incomplete option '%s' (see geosep repair --help)", argv[i]);
        else if (!in) in = argv[i];
        else return fail(EXIT_USAGE, "repair: unexpected argument '%s' (one MESH only)", argv[i]);
    }
    if (!in || !out) {
        fputs(usage_repair, stderr);
        return fail(EXIT_USAGE, "repair: %s", !in ? "missing MESH" : "missing -o OUT.obj");
    }
    if ((report && !*report) || (map && !*map) || !*out) return fail(EXIT_USAGE, "repair: empty file name");
    gs_mesh *m = NULL;
    gs_repair *r = NULL;
    gs_error err = {0};
    int rc = gs_mesh_repair_file(in, GS_FORMAT_AUTO, &m, &r, &err);
    if (rc) return lib_fail(in, rc, &err);
    rc = gs_mesh_save_obj(m, out, &err);
    if (rc) rc = lib_fail(out, rc, &err);
    if (!rc && report) rc = write_report(report, r);
    if (!rc && map) rc = write_vertex_map(map, r);
    if (!rc && !quiet) rc = write_report(NULL, r);
    gs_mesh_free(m);
    gs_repair_free(r);
    return rc;
}
