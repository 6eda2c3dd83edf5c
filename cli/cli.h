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
/* Value of option argv[*i] ("--opt VALUE" or "--opt=VALUE"); NULL if absent. */
const char *opt_value(int argc, char **argv, int *i, const char *name);
int is_opt(const char *arg, const char *name);
int load_mesh(const char *path, gs_mesh **m);

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

/* Database commands (db_cmds.c). */
int cmd_build(int argc, char **argv);
int cmd_query(int argc, char **argv);
int cmd_field(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_land(int argc, char **argv);
extern const char usage_build[], usage_query[], usage_field[], usage_eval[], usage_land[];

#endif
