/* within_cmd.c - geosep within: every vertex within a radius of a vertex,
 * by the database's distances (gs_db_within), one "id distance" line each,
 * by increasing distance. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>

const char usage_within[] =
    "usage: geosep within DB X R [-o OUT]\n"
    "  Every vertex whose database distance from vertex X is at most R (X\n"
    "  itself at 0; R a number >= 0, or inf for every vertex connected to X),\n"
    "  one 'id distance' line each, by increasing distance (ties: lower id\n"
    "  first), to OUT (written atomically) or stdout. Exactly the vertices of\n"
    "  'geosep field DB --source X' at most R; whole parts of the database's\n"
    "  tree are skipped by stored lower bounds, so a small radius costs a\n"
    "  small part of a field.\n";

int cmd_within(int argc, char **argv)
{
    const char *dbp = NULL, *xs = NULL, *rs = NULL, *outp = NULL, *v;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_within, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "-o"))) outp = v;
        else if (argv[i][0] == '-' && argv[i][1] && !(xs && !rs)) /* R may be negative: refused below */
            return fail(EXIT_USAGE, "within: unknown or incomplete option '%s' (see geosep within --help)", argv[i]);
        else if (!dbp) dbp = argv[i];
        else if (!xs) xs = argv[i];
        else if (!rs) rs = argv[i];
        else return fail(EXIT_USAGE, "within: unexpected argument '%s'", argv[i]);
    }
    if (!dbp || !xs || !rs) {
        fputs(usage_within, stderr);
        return fail(EXIT_USAGE, "within: need DB X R");
    }
    uint32_t x;
    double r;
    if (parse_u32(xs, &x)) return fail(EXIT_USAGE, "within: X '%s' is not a vertex id", xs);
    if (parse_double(rs, &r) || !(r >= 0.0))
        return fail(EXIT_USAGE, "within: R '%s' is not a distance (a number >= 0, or inf)", rs);
    if (outp && !*outp) return fail(EXIT_USAGE, "within: empty file name");
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs_db_open(dbp, &db, &err);
    if (rc) return lib_fail(dbp, rc, &err);
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    if (x >= info.n_vertices) {
        gs_db_free(db);
        return fail(EXIT_USAGE, "within: vertex %u out of range (the database has %u)", x, info.n_vertices);
    }
    gs_neighbors *nb = NULL;
    rc = gs_db_within(db, x, r, &nb, &err);
    if (rc) {
        rc = lib_fail(dbp, rc, &err);
    } else {
        out_file o;
        rc = out_open(&o, outp);
        if (!rc) {
            for (size_t i = 0; i < nb->n; ++i) fprintf(o.f, "%u %.17g\n", nb->ids[i], nb->dist[i]);
            if (outp && ferror(o.f)) {
                out_abort(&o);
                rc = fail(EXIT_RUNTIME, "%s: write failed", outp);
            } else {
                rc = out_commit(&o);
            }
        }
    }
    gs_neighbors_free(nb);
    gs_db_free(db);
    return rc;
}
