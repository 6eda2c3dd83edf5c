/* path_cmd.c - geosep path: a geodesic path between two vertices or surface
 * points, as a polyline: from a database and its mesh (gs_db_path), or
 * exact (gs_solver_path). */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char usage_path[] =
    "usage: geosep path DB X Y --mesh MESH [--exact] [--format xyz|faces] [-o OUT]\n"
    "       geosep path --exact MESH X Y [--format xyz|faces] [-o OUT]\n"
    "  A geodesic path from X to Y (doc/paths.md). X and Y are vertex ids\n"
    "  (0-based) or surface points F:b0,b1,b2 (face F, 0-based, and three\n"
    "  barycentric weights >= 0 summing to 1, as solve --source-point).\n"
    "  DB X Y --mesh MESH: from the database DB of MESH (the mesh it was built\n"
    "                    from: the database stores no faces), without solving\n"
    "                    a field: locally shortest, never shorter than the exact\n"
    "                    distance, within 1% of it on the meshes measured\n"
    "  --exact           the exact shortest path on MESH instead (one exact\n"
    "                    field from X, then backtracked); with DB, DB must be\n"
    "                    MESH's database\n"
    "  Output (text, atomic with -o): a first line `# length L` (the path's\n"
    "  length; `inf` and no points when Y cannot be reached from X), then one\n"
    "  line per polyline point from X to Y:\n"
    "    --format xyz    `x y z` (default)\n"
    "    --format faces  `face b0 b1 b2`: a face holding the segment to the next\n"
    "                    point (the last point: from the previous one), and the\n"
    "                    point's barycentric weights in it\n"
    "  The points are X, every crossing with an edge, every vertex the path\n"
    "  passes through, and Y; consecutive points share a face.\n";

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
    const char *pos[3] = {NULL, NULL, NULL}, *out = NULL, *fmt = "xyz", *mesh_path = NULL;
    int n_pos = 0, exact = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v;
        if (is_help(a)) return fputs(usage_path, stdout), 0;
        if (!strcmp(a, "--exact")) exact = 1;
        else if ((v = opt_value(argc, argv, &i, "--format"))) fmt = v;
        else if ((v = opt_value(argc, argv, &i, "--mesh"))) mesh_path = v;
        else if ((v = opt_value(argc, argv, &i, "-o"))) out = v;
        else if (!strcmp(a, "--format") || !strcmp(a, "-o") || !strcmp(a, "--mesh"))
            return fail(EXIT_USAGE, "path: %s needs a value", a);
        else if (a[0] == '-' && a[1]) return fail(EXIT_USAGE, "path: unknown option '%s' (see geosep path --help)", a);
        else if (n_pos < 3) pos[n_pos++] = a;
        else return fail(EXIT_USAGE, "path: unexpected argument '%s' (expected DB X Y --mesh MESH)", a);
    }
    if (!mesh_path && !exact)
        return fail(EXIT_USAGE, "path: give the database's mesh (geosep path DB X Y --mesh MESH), or --exact "
                                "(geosep path --exact MESH X Y)");
    if (n_pos < 3)
        return fail(EXIT_USAGE, "path: expected %s (see geosep path --help)",
                    mesh_path ? "DB X Y --mesh MESH" : "--exact MESH X Y");
    int faces = 0;
    if (!strcmp(fmt, "faces")) faces = 1;
    else if (strcmp(fmt, "xyz")) return fail(EXIT_USAGE, "path: --format '%s': expected xyz or faces", fmt);
    gs_source x, y;
    if (parse_end(pos[1], &x))
        return fail(EXIT_USAGE, "path: X '%s': expected a vertex id or F:b0,b1,b2", pos[1]);
    if (parse_end(pos[2], &y))
        return fail(EXIT_USAGE, "path: Y '%s': expected a vertex id or F:b0,b1,b2", pos[2]);
    const char *db_path = mesh_path ? pos[0] : NULL;
    if (!mesh_path) mesh_path = pos[0];

    gs_mesh *mesh = NULL;
    gs_db *db = NULL;
    gs_patch *patch = NULL;
    gs_solver *solver = NULL;
    gs_path *p = NULL;
    gs_error err = {0};
    int rc = load_mesh(mesh_path, &mesh), lrc = GS_OK;
    if (rc) return rc;
    if (db_path) {
        if ((lrc = gs_db_open(db_path, &db, &err))) {
            rc = lib_fail(db_path, lrc, &err);
            goto done;
        }
        if ((lrc = gs_db_check_mesh(db, mesh, &err))) {
            rc = fail(EXIT_RUNTIME, "%s and %s: %s", db_path, mesh_path, err.message);
            goto done;
        }
    }
    if (exact) {
        lrc = gs_patch_create(mesh, NULL, 0, &patch, &err);
        if (!lrc) lrc = gs_solver_create(patch, GS_METHOD_EXACT, &solver, &err);
        if (!lrc) lrc = gs_solver_path(solver, &x, &y, &p, &err);
    } else {
        lrc = gs_db_path(db, mesh, &x, &y, &p, &err);
    }
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
    gs_db_free(db);
    gs_mesh_free(mesh);
    return rc;
}
