/* cli.h - what the geosep subcommands share: exit codes, messages, strict
 * parsing, atomic output, and the commands themselves. */
#ifndef GEOSEP_CLI_H
#define GEOSEP_CLI_H

#include "geosep.h"

#include <stdio.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

#if defined(__GNUC__)
#define CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define CLI_PRINTF(a, b)
#endif

/* Print "geosep: MESSAGE" to stderr and return the exit code. */
int fail(int code, const char *fmt, ...) CLI_PRINTF(2, 3);
/* A library failure: its message, prefixed by `what` unless it names it. */
int lib_fail(const char *what, int rc, const gs_error *err);
double now(void);
int is_help(const char *a);
int parse_u32(const char *s, uint32_t *out);
int parse_double(const char *s, double *out);
/* --heat-refine's value: "auto" (GS_HEAT_REFINE_AUTO) or 0 to
 * GS_HEAT_REFINE_MAX; -1 for anything else (*out untouched). */
int parse_heat_refine(const char *s, uint32_t *out);
/* Value of option argv[*i] ("--opt VALUE" or "--opt=VALUE"); NULL if absent. */
const char *opt_value(int argc, char **argv, int *i, const char *name);
int is_opt(const char *arg, const char *name);
int load_mesh(const char *path, gs_mesh **m);
/* load_mesh, or with repair != 0 gs_mesh_repair_file with its summary on
 * stderr; *info (if info is not NULL) receives the repair (NULL without
 * repair; caller frees). 0 or an exit code (message printed). */
int load_mesh_opt(const char *path, int repair, gs_mesh **m, gs_repair **info);
/* The vertex map file (doc/repair.md), written atomically. */
int write_vertex_map(const char *path, const gs_repair *r);

/* Atomic text output (temporary file + rename); path NULL or "-": stdout. */
typedef struct out_file {
    FILE *f;
    char *tmp;
    const char *path; /* NULL: stdout */
} out_file;
int out_open(out_file *o, const char *path);
void out_abort(out_file *o);
int out_commit(out_file *o);
/* One distance per line ("%.17g", "inf"). */
int write_text(const char *path, const double *d, uint32_t n);

/* Line-by-line text input: path or "-" (stdin); a folder is refused. Each
 * line is read whole into line[] (without its '\n'): a NUL byte, a line
 * longer than sizeof line - 1 bytes or a read error is an error naming the
 * file and line, never a silently cut or split line. */
typedef struct line_reader {
    FILE *f;
    const char *path;
    unsigned long ln; /* number of the line in line[] (1-based) */
    char line[4096];
} line_reader;
/* 0, or an exit code (message printed). */
int lines_open(line_reader *r, const char *path);
/* 1: the next line is in r->line; 0: end of input; -1: an error (printed). */
int lines_next(line_reader *r);
void lines_close(line_reader *r);
/* s for a message: printable ASCII as is, other bytes as \xNN, cut with
 * "..." to fit buf (n >= 16 bytes). Returns buf. */
const char *shown(const char *s, char *buf, size_t n);
/* The blank-separated fields of s (modified in place) into t[0..max-1]:
 * their number, max if there are max or more. */
int split_fields(char *s, char **t, int max);

/* Parsers of untrusted text (query_input.c; fuzzed by fuzz/fuzz_cli_input.c). */
/* One distance per line ("%.17g", "inf"). */
void print_distance(FILE *f, double d);
/* query --pairs: "X Y" per line (blank lines skipped) from r, each answer
 * printed to out; stops at the first bad line. 0, or an exit code (message
 * printed). r stays open. */
int query_pairs(const gs_db *db, uint32_t n, line_reader *r, FILE *out);
/* The same by input vertex ids (gs_db_input_distance; ids below
 * gs_db_num_input_vertices). */
int query_input_pairs(const gs_db *db, line_reader *r, FILE *out);
/* query --points: two points per line (mesh: "f b0 b1 b2" each, else
 * "v0 v1 v2 l0 l1 l2"), as query_pairs. */
int query_points(const gs_db *db, const gs_mesh *mesh, line_reader *r, FILE *out);
/* A point from text fields: with a mesh, a face id and three weights
 * (t[0..3]); without, three vertex ids and three weights (t[0..5]). 0, or
 * -1 with the reason in why (n bytes). */
int make_point(const gs_db *db, const gs_mesh *mesh, char **t, gs_surface_point *p, char *why, size_t n);
/* "V0,V1,V2:L0,L1,L2" (no mesh) or "F:b0,b1,b2" (with the mesh) split in
 * place into the fields make_point reads (t: 6 or 4): exactly one ':', the
 * counts of fields, none empty. 0 or -1. */
int split_point(char *s, int mesh, char **t);
/* solve --source-point "F:b0,b1,b2" into *s; 0 or -1. */
int parse_source_point(const char *a, gs_source *s);

/* Database commands (db_cmds.c). */
int cmd_build(int argc, char **argv);
int cmd_query(int argc, char **argv);
int cmd_verify(int argc, char **argv);
int cmd_field(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_land(int argc, char **argv);
int cmd_repair(int argc, char **argv);
extern const char usage_repair[];
extern const char usage_build[], usage_query[], usage_verify[], usage_field[], usage_eval[], usage_land[];

/* Exact paths (path_cmd.c). */
int cmd_path(int argc, char **argv);
extern const char usage_path[];

/* Farthest-point sampling (sample_cmd.c). */
int cmd_sample(int argc, char **argv);
extern const char usage_sample[];

/* Neighbourhoods (within_cmd.c). */
int cmd_within(int argc, char **argv);
extern const char usage_within[];

/* Pictures (render_cmd.c). */
int cmd_render(int argc, char **argv);
extern const char usage_render[];

#endif
