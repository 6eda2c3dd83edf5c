/* path_cmd.c - geosep path: the exact shortest path between two vertices or
 * surface points of a mesh (gs_solver_path), as a polyline. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char usage_path[] =
    "usage: geosep path --exact MESH X Y [--format xyz|faces] [-o OUT]\n"
    "  The exact shortest path on MESH from X to Y, found by the exact solver\n"
    "  (one exact field from X, then backtracked: doc/paths.md). X and Y are\n"
    "  vertex ids (0-based) or surface points F:b0,b1,b2 (face F, 0-based, and\n"
    "  three barycentric weights >= 0 summing to 1, as solve --source-point).\n"
    "  Output (text, atomic with -o): a first line `# length L` (the path's\n"
    "  length, the exact distance; `inf` and no points when Y cannot be reached\n"
    "  from X), then one line per polyline point from X to Y:\n"
    "    --format xyz    `x y z` (default)\n"
    "    --format faces  `face b0 b1 b2`: a face holding the segment to the next\n"
    "                    point (the last point: from the previous one), and the\n"
    "                    point's barycentric weights in it\n"
    "  The points are X, every crossing with an edge, every vertex the path\n"
    "  passes through, and Y; consecutive points share a face.\n"
    "  --exact is required: paths from a database (geosep path DB X Y --mesh\n"
    "  MESH) are planned and will be the form without it.\n";

/* X or Y: a vertex id or F:b0,b1,b2 */
static int parse_end(const char *a, gs_source *s)
{
    uint32_t v;
    if (!parse_u32(a, &v)) {
        *s = gs_source_vertex(v);
        return 0;
    }
    return parse_source_point(a, s);
}

int cmd_path(int argc, char **argv)
{
    const char *pos[3] = {NULL, NULL, NULL}, *out = NULL, *fmt = "xyz";
    int n_pos = 0, exact = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (is_help(a)) return fputs(usage_path, stdout), 0;
        if (!strcmp(a, "--exact")) exact = 1;
        else if ((v = opt_value(argc, argv, &i, "--format"))) fmt = v;
        else if ((v = opt_value(argc, argv, &i, "-o"))) out = v;
        else if (!strcmp(a, "--format") || !strcmp(a, "-o")) return fail(EXIT_USAGE, "path: %s needs a value", a);
        else if (a[0] == '-' && a[1]) return fail(EXIT_USAGE, "path: unknown option '%s' (see geosep path --help)", a);
        else if (n_pos < 3) pos[n_pos++] = a;
        else return fail(EXIT_USAGE, "path: unexpected argument '%s' (expected --exact MESH X Y)", a);
    }
    if (!exact)
        return fail(EXIT_USAGE, "path: give --exact (geosep path --exact MESH X Y); paths from a database "
                                "are not available yet");
    if (n_pos < 3) return fail(EXIT_USAGE, "path: expected --exact MESH X Y (see geosep path --help)");
    int faces = 0;
    if (!strcmp(fmt, "faces")) faces = 1;
    else if (strcmp(fmt, "xyz")) return fail(EXIT_USAGE, "path: --format '%s': expected xyz or faces", fmt);
    gs_source x, y;
    if (parse_end(pos[1], &x))
        return fail(EXIT_USAGE, "path: X '%s': expected a vertex id or F:b0,b1,b2", pos[1]);
    if (parse_end(pos[2], &y))
        return fail(EXIT_USAGE, "path: Y '%s': expected a vertex id or F:b0,b1,b2", pos[2]);

    gs_mesh *mesh = NULL;
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    gs_path *p = NULL;
    gs_error err = {0};
    int rc = load_mesh(pos[0], &mesh);
    if (rc) return rc;
    int lrc = gs_patch_create(mesh, NULL, 0, &patch, &err);
    if (!lrc) lrc = gs_solver_create(patch, GS_METHOD_EXACT, &solver, &err);
    if (!lrc) lrc = gs_solver_path(solver, &x, &y, &p, &err);
    if (lrc) {
        rc = lib_fail("path", lrc, &err);
        goto done;
    }
    out_file o;
    if ((rc = out_open(&o, out))) goto done;
    uint32_t n = gs_path_num_points(p);
    const double *xyz = gs_path_xyz(p), *b = gs_path_bary(p);
    const uint32_t *f = gs_path_faces(p);
    double len = gs_path_length(p);
    if (isinf(len)) fprintf(o.f, "# length inf\n");
    else fprintf(o.f, "# length %.17g\n", len);
    for (uint32_t i = 0; i < n; ++i) {
        if (faces) fprintf(o.f, "%u %.17g %.17g %.17g\n", f[i], b[3 * i], b[3 * i + 1], b[3 * i + 2]);
        else fprintf(o.f, "%.17g %.17g %.17g\n", xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    }
    rc = out_commit(&o);
done:
    gs_path_free(p);
    gs_solver_free(solver);
    gs_patch_free(patch);
    gs_mesh_free(mesh);
    return rc;
}
