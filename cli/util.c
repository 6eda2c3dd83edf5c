/* util.c - helpers shared by the geosep subcommands: messages, strict number
 * parsing, option values, atomic text output, mesh loading. */
#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int is_help(const char *a) { return !strcmp(a, "--help") || !strcmp(a, "-h"); }

/* Print "geosep: MESSAGE" to stderr and return the exit code. */
int fail(int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("geosep: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return code;
}

/* A library failure: its message, prefixed by `what` unless it names it. */
int lib_fail(const char *what, int rc, const gs_error *err)
{
    const char *msg = err->message[0] ? err->message : gs_status_string(rc);
    if (strstr(msg, what)) return fail(EXIT_RUNTIME, "%s", msg);
    return fail(EXIT_RUNTIME, "%s: %s", what, msg);
}

double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- strict number parsing ---------------------------------------------- */

int parse_u32(const char *s, uint32_t *out)
{
    uint64_t v = 0;
    if (!*s) return -1;
    for (; *s; ++s) {
        if (*s < '0' || *s > '9') return -1;
        v = v * 10 + (uint64_t)(*s - '0');
        if (v > UINT32_MAX - 1) return -1;
    }
    *out = (uint32_t)v;
    return 0;
}

int parse_heat_refine(const char *s, uint32_t *out)
{
    uint32_t n;
    if (!strcmp(s, "auto")) n = GS_HEAT_REFINE_AUTO;
    else if (parse_u32(s, &n) || n > GS_HEAT_REFINE_MAX) return -1;
    *out = n;
    return 0;
}

int parse_double(const char *s, double *out)
{
    char *end;
    if (isspace((unsigned char)*s)) return -1; /* strtod would skip it */
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || isnan(v)) return -1;
    *out = v;
    return 0;
}

/* ---- atomic text output: temporary file + rename ------------------------ */

int out_open(out_file *o, const char *path)
{
    o->f = stdout;
    o->tmp = NULL;
    o->path = (path && strcmp(path, "-")) ? path : NULL;
    if (!o->path) return 0;
    /* as the library's writer: the rename would replace whatever the path
     * names, so a device, a pipe or a folder is refused, not swapped for a
     * regular file (a symbolic link is followed for this check) */
    struct stat old;
    if (stat(path, &old) == 0 && !S_ISREG(old.st_mode))
        return fail(EXIT_RUNTIME, "%s: exists and is not a regular file (not replaced)", path);
    size_t n = strlen(path) + 16;
    o->tmp = malloc(n);
    if (!o->tmp) return fail(EXIT_RUNTIME, "out of memory");
    snprintf(o->tmp, n, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(o->tmp);
    if (fd < 0) {
        int e = errno;
        free(o->tmp);
        o->tmp = NULL;
        return fail(EXIT_RUNTIME, "%s: cannot create: %s", path, strerror(e));
    }
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    o->f = fdopen(fd, "w");
    if (!o->f) {
        close(fd);
        unlink(o->tmp);
        free(o->tmp);
        return fail(EXIT_RUNTIME, "%s: cannot open: %s", path, strerror(errno));
    }
    return 0;
}

void out_abort(out_file *o)
{
    if (!o->path) return;
    fclose(o->f);
    unlink(o->tmp);
    free(o->tmp);
}

int out_commit(out_file *o)
{
    if (!o->path) return fflush(stdout) || ferror(stdout) ? fail(EXIT_RUNTIME, "write error on stdout") : 0;
    int bad = fflush(o->f) != 0 || ferror(o->f) || fsync(fileno(o->f)) != 0;
    int e = errno;
    bad |= fclose(o->f) != 0;
    if (!bad && rename(o->tmp, o->path) != 0) {
        e = errno;
        bad = 1;
    }
    if (bad) unlink(o->tmp);
    free(o->tmp);
    return bad ? fail(EXIT_RUNTIME, "%s: write failed: %s", o->path, strerror(e)) : 0;
}

/* ---- line-by-line input (query --pairs, --points) ------------------------ */

int lines_open(line_reader *r, const char *path)
{
    r->path = path;
    r->ln = 0;
    r->f = strcmp(path, "-") ? fopen(path, "r") : stdin;
    if (!r->f) return fail(EXIT_RUNTIME, "%s: cannot open: %s", path, strerror(errno));
    struct stat st; /* a folder opens, then fails to read */
    if (fstat(fileno(r->f), &st) == 0 && S_ISDIR(st.st_mode)) {
        lines_close(r);
        return fail(EXIT_RUNTIME, "%s: is a directory", path);
    }
    return 0;
}

int lines_next(line_reader *r)
{
    size_t n = 0;
    int c;
    r->ln++;
    while ((c = getc(r->f)) != EOF && c != '\n') {
        if (c == 0) return fail(EXIT_RUNTIME, "%s:%lu: NUL byte in the line", r->path, r->ln), -1;
        if (n == sizeof r->line - 1)
            return fail(EXIT_RUNTIME, "%s:%lu: line longer than %zu bytes", r->path, r->ln, sizeof r->line - 1), -1;
        r->line[n++] = (char)c;
    }
    if (c == EOF && ferror(r->f)) return fail(EXIT_RUNTIME, "%s:%lu: read error: %s", r->path, r->ln, strerror(errno)), -1;
    r->line[n] = 0;
    return c == EOF && n == 0 ? 0 : 1;
}

void lines_close(line_reader *r)
{
    if (r->f && r->f != stdin) fclose(r->f);
    r->f = NULL;
}

const char *shown(const char *s, char *buf, size_t n)
{
    size_t k = 0;
    for (; *s && k + 8 < n; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c >= 0x20 && c < 0x7f) buf[k++] = (char)c;
        else k += (size_t)snprintf(buf + k, n - k, "\\x%02x", c);
    }
    if (*s) k += (size_t)snprintf(buf + k, n - k, "...");
    buf[k < n ? k : n - 1] = 0;
    return buf;
}

int split_fields(char *s, char **t, int max)
{
    int k = 0;
    char *save = NULL;
    for (char *tok = strtok_r(s, " \t\r\v\f", &save); tok && k < max; tok = strtok_r(NULL, " \t\r\v\f", &save))
        t[k++] = tok;
    return k;
}

int load_mesh(const char *path, gs_mesh **m)
{
    gs_error err = {0};
    int rc = gs_mesh_load(path, GS_FORMAT_AUTO, m, &err);
    return rc ? lib_fail(path, rc, &err) : 0;
}

/* Value of option argv[*i] ("--opt VALUE" or "--opt=VALUE"); NULL if absent. */
const char *opt_value(int argc, char **argv, int *i, const char *name)
{
    size_t n = strlen(name);
    if (strncmp(argv[*i], name, n)) return NULL;
    if (argv[*i][n] == '=') return argv[*i] + n + 1;
    if (argv[*i][n] || *i + 1 >= argc) return NULL;
    return argv[++*i];
}

int is_opt(const char *arg, const char *name)
{
    size_t n = strlen(name);
    return !strncmp(arg, name, n) && (arg[n] == 0 || arg[n] == '=');
}

int write_text(const char *path, const double *d, uint32_t n)
{
    out_file o;
    int rc = out_open(&o, path);
    if (rc) return rc;
    for (uint32_t v = 0; v < n; ++v) {
        if (isinf(d[v]))
            fputs("inf\n", o.f);
        else
            fprintf(o.f, "%.17g\n", d[v]);
    }
    if (ferror(o.f)) {
        out_abort(&o);
        return fail(EXIT_RUNTIME, "%s: write failed", path ? path : "stdout");
    }
    return out_commit(&o);
}

