/* query_input.c - the CLI's parsers of untrusted text: query --pairs and
 * --points files, field --point / --source-point and solve --source-point
 * specs. Apart from the commands so that the fuzz target
 * fuzz/fuzz_cli_input.c compiles them as they are. */
#include "cli.h"

#include <math.h>
#include <string.h>

void print_distance(FILE *f, double d)
{
    if (isinf(d))
        fputs("inf\n", f);
    else
        fprintf(f, "%.17g\n", d);
}

/* Lines 'X Y' answered by gs_db_distance (ids below n), or with input ids
 * by gs_db_input_distance (ids below n_input_vertices). */
static int pairs_loop(const gs_db *db, uint32_t n, int input, line_reader *r, FILE *out)
{
    int rc = 0, got = 0;
    while (!rc && (got = lines_next(r)) > 0) {
        char *t[3];
        int k = split_fields(r->line, t, 3);
        if (k == 0) continue;
        uint32_t x, y;
        if (k != 2 || parse_u32(t[0], &x) || parse_u32(t[1], &y) || x >= n || y >= n)
            rc = fail(EXIT_RUNTIME, "%s:%lu: expected two %s ids below %u", r->path, r->ln,
                      input ? "input vertex" : "vertex", n);
        else
            print_distance(out, input ? gs_db_input_distance(db, x, y) : gs_db_distance(db, x, y));
    }
    if (got < 0) rc = EXIT_RUNTIME;
    return rc;
}

int query_pairs(const gs_db *db, uint32_t n, line_reader *r, FILE *out)
{
    return pairs_loop(db, n, 0, r, out);
}

int query_input_pairs(const gs_db *db, line_reader *r, FILE *out)
{
    return pairs_loop(db, gs_db_num_input_vertices(db), 1, r, out);
}

/* A validation message without the library's "surface point: " prefix. */
static const char *point_message(const gs_error *e)
{
    static const char prefix[] = "surface point: ";
    return strncmp(e->message, prefix, sizeof prefix - 1) ? e->message : e->message + sizeof prefix - 1;
}

int make_point(const gs_db *db, const gs_mesh *mesh, char **t, gs_surface_point *p, char *why, size_t n)
{
    int nid = mesh ? 1 : 3;
    uint32_t id[3];
    double w[3];
    char tok[80]; /* the field as the message shows it */
    for (int k = 0; k < nid; ++k)
        if (parse_u32(t[k], &id[k]))
            return snprintf(why, n, "'%s' is not a %s id", shown(t[k], tok, sizeof tok), mesh ? "face" : "vertex"), -1;
    for (int k = 0; k < 3; ++k)
        if (parse_double(t[nid + k], &w[k]))
            return snprintf(why, n, "weight '%s' is not a number", shown(t[nid + k], tok, sizeof tok)), -1;
    gs_error e = {0};
    if (mesh && gs_surface_point_from_face(mesh, id[0], w[0], w[1], w[2], p, &e))
        return snprintf(why, n, "%s", e.message), -1;
    if (!mesh) *p = gs_surface_point_make(id[0], id[1], id[2], w[0], w[1], w[2]);
    if (gs_db_point_check(db, p, &e)) return snprintf(why, n, "%s", point_message(&e)), -1;
    return 0;
}

int query_points(const gs_db *db, const gs_mesh *mesh, line_reader *r, FILE *out)
{
    const int per = mesh ? 4 : 6;
    const char *form = mesh ? "'f b0 b1 b2  g c0 c1 c2' (face id and three weights, twice)"
                            : "'v0 v1 v2 l0 l1 l2  w0 w1 w2 m0 m1 m2' (three vertex ids and three weights, twice)";
    int rc = 0, got = 0;
    while (!rc && (got = lines_next(r)) > 0) {
        char *t[13];
        int k = split_fields(r->line, t, 2 * per + 1);
        if (k == 0) continue;
        if (k != 2 * per) {
            rc = fail(EXIT_RUNTIME, "%s:%lu: expected %d fields %s, got %s%d", r->path, r->ln, 2 * per, form,
                      k > 2 * per ? "more than " : "", k > 2 * per ? 2 * per : k);
            break;
        }
        gs_surface_point p[2];
        char why[600];
        for (int j = 0; j < 2 && !rc; ++j)
            if (make_point(db, mesh, t + j * per, &p[j], why, sizeof why))
                rc = fail(EXIT_RUNTIME, "%s:%lu: %s point: %s", r->path, r->ln, j ? "second" : "first", why);
        if (!rc) print_distance(out, gs_db_point_distance(db, &p[0], &p[1]));
    }
    if (got < 0) rc = EXIT_RUNTIME;
    return rc;
}

int split_point(char *s, int mesh, char **t)
{
    char *c = strchr(s, ':');
    if (!c || strchr(c + 1, ':')) return -1;
    *c = ',';
    int k = 0, want = mesh ? 4 : 6, nid = mesh ? 1 : 3;
    for (char *f = s;; ++k) {
        if (k == want) return -1;
        t[k] = f;
        if (!(f = strchr(f, ','))) break;
        *f++ = 0;
    }
    if (++k != want || t[nid] != c + 1) return -1;
    for (int i = 0; i < want; ++i)
        if (!*t[i]) return -1;
    return 0;
}

int parse_source_point(const char *a, gs_source *s)
{
    char buf[256], *colon, *c1, *c2;
    if (strlen(a) >= sizeof buf) return -1;
    strcpy(buf, a);
    if (!(colon = strchr(buf, ':'))) return -1;
    *colon = 0;
    if (!(c1 = strchr(colon + 1, ',')) || !(c2 = strchr(c1 + 1, ','))) return -1;
    *c1 = *c2 = 0;
    uint32_t f;
    double b[3];
    if (parse_u32(buf, &f) || parse_double(colon + 1, &b[0]) || parse_double(c1 + 1, &b[1]) ||
        parse_double(c2 + 1, &b[2]))
        return -1;
    *s = gs_source_point(f, b[0], b[1], b[2]);
    return 0;
}
