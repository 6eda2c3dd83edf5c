/* fuzz_cli_input.c - the geosep command's parsers of untrusted text
 * (cli/query_input.c, compiled in as the command has it) on arbitrary
 * bytes, against a small database built once (a 4 x 4 grid and its mesh).
 * The first byte picks the parser:
 *   0 query --pairs file      1 query --points file (vertex corners)
 *   2 query --points file with --mesh (face ids)
 *   3 field --point V0,V1,V2:L0,L1,L2   4 field --source-point F:b0,b1,b2
 *   5 solve --source-point F:b0,b1,b2
 * Never a crash; a bad line or spec is an error (exit code / -1), a point
 * accepted by the parser is valid for the database (gs_db_point_check) and
 * its distances are finite and >= 0. */
#include "cli.h"
#include "fuzz_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static gs_db *g_db;
static gs_mesh *g_mesh;
static FILE *g_null;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    gs_error err = {0};
    FUZZ_CHECK(gs_mesh_generate("grid:4,4", &g_mesh, &err) == GS_OK);
    gs_build_options o;
    gs_build_options_default(&o);
    o.threads = 1;
    FUZZ_CHECK(gs_db_build(g_mesh, &o, &g_db, NULL, &err) == GS_OK);
    g_null = fopen("/dev/null", "w");
    FUZZ_CHECK(g_null != NULL);
    return 0;
}

static void spec(const char *s, int mode)
{
    char buf[512], *t[6], why[600];
    if (strlen(s) >= sizeof buf) return; /* as field_point: refused before parsing */
    strcpy(buf, s);
    if (mode == 5) {
        gs_source src;
        if (parse_source_point(s, &src) == 0) FUZZ_CHECK(src.face != GS_NONE);
        return;
    }
    const gs_mesh *mesh = mode == 4 ? g_mesh : NULL;
    if (split_point(buf, mesh != NULL, t)) return;
    gs_surface_point p;
    if (make_point(g_db, mesh, t, &p, why, sizeof why)) {
        FUZZ_CHECK(why[0] != 0);
        return;
    }
    FUZZ_CHECK(gs_db_point_check(g_db, &p, NULL) == GS_OK);
    double d = gs_db_point_distance(g_db, &p, &p);
    FUZZ_CHECK(d == 0);
    d = gs_db_point_distance(g_db, &p, &(gs_surface_point){{5, 5, 5}, {1, 0, 0}});
    FUZZ_CHECK(isfinite(d) && d >= 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    int mode = data[0] % 6;
    ++data, --size;
    if (mode >= 3) {
        char *s = malloc(size + 1);
        FUZZ_CHECK(s != NULL);
        memcpy(s, data, size);
        s[size] = 0; /* a command-line argument ends at its first NUL */
        spec(s, mode);
        free(s);
        return 0;
    }
    line_reader r;
    memset(&r, 0, sizeof r);
    r.path = "fuzz-input";
    r.f = size ? fmemopen((void *)data, size, "r") : fopen("/dev/null", "r");
    FUZZ_CHECK(r.f != NULL);
    gs_db_info info;
    FUZZ_CHECK(gs_db_get_info(g_db, &info, NULL) == GS_OK);
    int rc = mode == 0 ? query_pairs(g_db, info.n_vertices, &r, g_null)
                       : query_points(g_db, mode == 2 ? g_mesh : NULL, &r, g_null);
    FUZZ_CHECK(rc == 0 || rc == EXIT_RUNTIME);
    lines_close(&r);
    return 0;
}
