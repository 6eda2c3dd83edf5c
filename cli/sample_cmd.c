/* sample_cmd.c - geosep sample: farthest-point sampling by a database's
 * distances (gs_db_farthest_point_sampling), the ids printed in order. */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

const char usage_sample[] =
    "usage: geosep sample DB K [--seed S] [-o OUT]\n"
    "  Farthest-point sampling by the database's distances: the first sample is\n"
    "  S (a vertex id, default 0), each next one the vertex farthest from the\n"
    "  samples so far (a vertex of a component without a sample yet counts as\n"
    "  infinitely far, so every component is sampled first; ties go to the\n"
    "  lowest id; vertices used by no face are never chosen). Prints the K\n"
    "  vertex ids in order, one per line, to OUT (written atomically) or\n"
    "  stdout. K may not exceed the vertices used by faces. Costs a distance\n"
    "  field for the first sample (and each component's first), then for each\n"
    "  sample the vertices within its distance to the ones before (geosep\n"
    "  within), and 16 bytes per vertex.\n";

int cmd_sample(int argc, char **argv)
{
    const char *dbp = NULL, *ks = NULL, *seeds = NULL, *outp = NULL, *v;
    for (int i = 1; i < argc; ++i) {
        if (is_help(argv[i])) return fputs(usage_sample, stdout), 0;
        if ((v = opt_value(argc, argv, &i, "--seed"))) seeds = v;
        else if ((v = opt_value(argc, argv, &i, "-o"))) outp = v;
        else if (argv[i][0] == '-' && argv[i][1])
            return fail(EXIT_USAGE, "sample: unknown or incomplete option '%s' (see geosep sample --help)", argv[i]);
        else if (!dbp) dbp = argv[i];
        else if (!ks) ks = argv[i];
        else return fail(EXIT_USAGE, "sample: unexpected argument '%s'", argv[i]);
    }
    if (!dbp || !ks) {
        fputs(usage_sample, stderr);
        return fail(EXIT_USAGE, "sample: need DB K");
    }
    uint32_t k, seed = 0;
    if (parse_u32(ks, &k)) return fail(EXIT_USAGE, "sample: K '%s' is not a count", ks);
    if (seeds && parse_u32(seeds, &seed)) return fail(EXIT_USAGE, "sample: --seed '%s' is not a vertex id", seeds);
    if (outp && !*outp) return fail(EXIT_USAGE, "sample: empty file name");
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs_db_open(dbp, &db, &err);
    if (rc) return lib_fail(dbp, rc, &err);
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    uint32_t *ids = malloc((k ? k : 1) * sizeof *ids);
    if (!ids) {
        gs_db_free(db);
        return fail(EXIT_RUNTIME, "out of memory (K = %u)", k);
    }
    rc = gs_db_farthest_point_sampling(db, k, seed, ids, &err);
    if (rc == GS_EARG) {
        /* the message names the bad K or seed */
        const char *m = err.message, *p = strstr(m, ": ");
        rc = fail(EXIT_USAGE, "sample: %s (%s)", p ? p + 2 : m, dbp);
    } else if (rc) {
        rc = lib_fail(dbp, rc, &err);
    } else {
        out_file o;
        rc = out_open(&o, outp);
        if (!rc) {
            for (uint32_t i = 0; i < k; ++i) fprintf(o.f, "%u\n", ids[i]);
            if (outp && ferror(o.f)) {
                out_abort(&o);
                rc = fail(EXIT_RUNTIME, "%s: write failed", outp);
            } else {
                rc = out_commit(&o);
            }
        }
    }
    free(ids);
    gs_db_free(db);
    return rc;
}
