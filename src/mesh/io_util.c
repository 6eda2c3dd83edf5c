/* io_util.c - helpers shared by the mesh readers: reading a whole file with
 * size checks, the line cursor and tokenizer, strict number parsing, and the
 * growing triangle soup with its fan triangulation. */
#include "io_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int io_fail(gs_error *err, const char *path, const char *what, int e)
{
    char buf[128];
    if (strerror_r(e, buf, sizeof buf) != 0) snprintf(buf, sizeof buf, "error %d", e);
    return gs__fail(err, GS_EIO, "%s: %s: %s", path, what, buf);
}

static int read_all(int fd, char *buf, size_t size, const char *path, gs_error *err)
{
    size_t got = 0;
    while (got < size) {
        size_t chunk = size - got > ((size_t)1 << 30) ? ((size_t)1 << 30) : size - got;
        ssize_t r = read(fd, buf + got, chunk);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) return io_fail(err, path, "cannot read", errno);
        if (r == 0)
            return gs__fail(err, GS_EIO, "%s: file shrank while being read", path);
        got += (size_t)r;
    }
    return GS_OK;
}

static int check_stat(int fd, const char *path, size_t *size, gs_error *err)
{
    struct stat st;
    if (fstat(fd, &st) != 0) return io_fail(err, path, "cannot stat", errno);
    if (S_ISDIR(st.st_mode)) return gs__fail(err, GS_EIO, "%s: is a directory", path);
    if (!S_ISREG(st.st_mode))
        return gs__fail(err, GS_EIO, "%s: not a regular file", path);
    if (st.st_size < 0 || (uint64_t)st.st_size > GS_IO_MAX_FILE ||
        (uint64_t)st.st_size >= SIZE_MAX)
        return gs__fail(err, GS_ELIMIT, "%s: file of %lld bytes is larger than geosep reads",
                        path, (long long)st.st_size);
    *size = (size_t)st.st_size;
    return GS_OK;
}

int gs__read_file(const char *path, char **data, size_t *size, gs_error *err)
{
    *data = NULL;
    *size = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return io_fail(err, path, "cannot open", errno);
    size_t n = 0;
    int rc = check_stat(fd, path, &n, err);
    char *buf = NULL;
    if (rc == GS_OK) {
        buf = gs__malloc(n + 1, 1);
        if (!buf)
            rc = gs__fail(err, GS_ENOMEM, "%s: out of memory reading %zu bytes", path, n);
    }
    if (rc == GS_OK) rc = read_all(fd, buf, n, path, err);
    close(fd);
    if (rc) {
        free(buf);
        return rc;
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return GS_OK;
}

/* ---- lines and tokens -------------------------------------------------- */

void gs__lines_init(gs__lines *c, char *data, size_t size)
{
    c->p = data;
    c->end = data + size;
    c->line = 0;
}

int gs__lines_next(gs__lines *c, char **line)
{
    if (c->p >= c->end) return 0;
    char *s = c->p, *q = s;
    while (q < c->end && *q != '\n' && *q != '\r' && *q != '\0') ++q;
    c->line++;
    if (q < c->end && *q == '\0') return -1;
    char *next = q;
    if (q < c->end) {
        next = q + 1;
        if (*q == '\r' && next < c->end && *next == '\n') ++next;
        *q = '\0';
    }
    c->p = next;
    *line = s;
    return 1;
}

static int is_blank_char(char ch)
{
    return ch == ' ' || ch == '\t' || ch == '\v' || ch == '\f';
}

char *gs__tok(char **s)
{
    char *p = *s;
    while (is_blank_char(*p)) ++p;
    if (!*p) {
        *s = p;
        return NULL;
    }
    char *t = p;
    while (*p && !is_blank_char(*p)) ++p;
    if (*p) *p++ = '\0';
    *s = p;
    return t;
}

void gs__strip_comment(char *line)
{
    char *h = strchr(line, '#');
    if (h) *h = '\0';
}

int gs__blank(const char *s)
{
    while (is_blank_char(*s)) ++s;
    return *s == '\0';
}

int gs__parse_double(const char *tok, double *out)
{
    if (!tok || !*tok || is_blank_char(*tok)) return -1;
    char *end = NULL;
    errno = 0;
    double v = strtod(tok, &end);
    if (end == tok || *end != '\0') return -1;
    /* ERANGE: overflow gives +-HUGE_VAL (rejected later as non-finite),
     * underflow a subnormal or zero, which is the nearest value anyway. */
    *out = v;
    return 0;
}

int gs__parse_i64(const char *tok, char stop, int64_t *out)
{
    if (!tok || !*tok || is_blank_char(*tok) || *tok == stop) return -1;
    char *end = NULL;
    errno = 0;
    long long v = strtoll(tok, &end, 10);
    if (end == tok || errno == ERANGE) return -1;
    if (*end != '\0' && !(stop && *end == stop)) return -1;
    *out = (int64_t)v;
    return 0;
}

/* ---- the triangle soup ------------------------------------------------- */

void gs__soup_init(gs__soup *s, const char *file, const char *unit)
{
    memset(s, 0, sizeof *s);
    s->file = file;
    s->unit = unit;
}

void gs__soup_free(gs__soup *s)
{
    free(s->xyz);
    free(s->tri);
    free(s->face_line);
    s->xyz = NULL;
    s->tri = s->face_line = NULL;
    s->nv = s->nf = 0;
    s->cap_v = s->cap_f = 0;
}

/* Triangles are limited so that 3 * nf stays below UINT32_MAX (half-edge
 * ids), vertices so that GS_NONE is never a valid id. */
#define GS_MAX_TRI ((UINT32_MAX - 1) / 3)
#define GS_MAX_VERT (UINT32_MAX - 1)

static int grow_vertices(gs__soup *s, uint64_t need, gs_error *err)
{
    if (need > GS_MAX_VERT)
        return gs__fail(err, GS_ELIMIT, "%s: more than %u vertices is more than geosep supports",
                        s->file, (unsigned)GS_MAX_VERT);
    if (need <= s->cap_v) return GS_OK;
    uint64_t cap = s->cap_v ? 2 * (uint64_t)s->cap_v : 64;
    if (cap < need) cap = need;
    if (cap > GS_MAX_VERT) cap = GS_MAX_VERT;
    double *x = gs__realloc(s->xyz, 3 * (size_t)cap, sizeof *x);
    if (!x) return gs__fail(err, GS_ENOMEM, "%s: out of memory for %llu vertices", s->file,
                            (unsigned long long)cap);
    s->xyz = x;
    s->cap_v = (size_t)cap;
    return GS_OK;
}

static int grow_faces(gs__soup *s, uint64_t need, gs_error *err)
{
    if (need > GS_MAX_TRI)
        return gs__fail(err, GS_ELIMIT, "%s: more than %u triangles is more than geosep supports",
                        s->file, (unsigned)GS_MAX_TRI);
    if (need <= s->cap_f) return GS_OK;
    uint64_t cap = s->cap_f ? 2 * (uint64_t)s->cap_f : 64;
    if (cap < need) cap = need;
    if (cap > GS_MAX_TRI) cap = GS_MAX_TRI;
    uint32_t *t = gs__realloc(s->tri, 3 * (size_t)cap, sizeof *t);
    if (t) s->tri = t;
    uint32_t *l = t ? gs__realloc(s->face_line, (size_t)cap, sizeof *l) : NULL;
    if (!t || !l) return gs__fail(err, GS_ENOMEM, "%s: out of memory for %llu triangles",
                                  s->file, (unsigned long long)cap);
    s->face_line = l;
    s->cap_f = (size_t)cap;
    return GS_OK;
}

int gs__soup_reserve(gs__soup *s, uint64_t nv, uint64_t nf, gs_error *err)
{
    int rc = grow_vertices(s, (uint64_t)s->nv + nv, err);
    return rc ? rc : grow_faces(s, (uint64_t)s->nf + nf, err);
}

int gs__soup_add_vertex(gs__soup *s, double x, double y, double z, gs_error *err)
{
    if (s->nv >= s->cap_v) {
        int rc = grow_vertices(s, (uint64_t)s->nv + 1, err);
        if (rc) return rc;
    }
    double *p = s->xyz + 3 * (size_t)s->nv++;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return GS_OK;
}

int gs__soup_add_tri(gs__soup *s, uint32_t a, uint32_t b, uint32_t c, uint32_t where,
                     gs_error *err)
{
    if (s->nf >= s->cap_f) {
        int rc = grow_faces(s, (uint64_t)s->nf + 1, err);
        if (rc) return rc;
    }
    uint32_t *t = s->tri + 3 * (size_t)s->nf;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    s->face_line[s->nf++] = where;
    return GS_OK;
}

int gs__fan_add(gs__fan *f, gs__soup *s, uint32_t v, uint32_t where, gs_error *err)
{
    int rc = GS_OK;
    if (f->n == 0)
        f->first = v;
    else if (f->n >= 2)
        rc = gs__soup_add_tri(s, f->first, f->prev, v, where, err);
    f->prev = v;
    f->n++;
    return rc;
}
