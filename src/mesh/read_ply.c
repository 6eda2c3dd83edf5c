/* read_ply.c - PLY 1.0 reader (ascii, binary_little_endian, binary_big_endian):
 * vertex x,y,z of any numeric type, face vertex_indices / vertex_index lists
 * fanned, every other property and element skipped. Declared counts are
 * checked against the file size before anything is allocated. */
#include "io_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 };
enum { R_SKIP, R_X, R_Y, R_Z, R_INDICES };
enum { F_NONE, F_ASCII, F_LE, F_BE };

static const struct {
    const char *name, *alias;
    int size;
    int64_t lo, hi;
} types[] = {
    {"", "", 0, 0, 0},
    {"char", "int8", 1, INT8_MIN, INT8_MAX},
    {"uchar", "uint8", 1, 0, UINT8_MAX},
    {"short", "int16", 2, INT16_MIN, INT16_MAX},
    {"ushort", "uint16", 2, 0, UINT16_MAX},
    {"int", "int32", 4, INT32_MIN, INT32_MAX},
    {"uint", "uint32", 4, 0, UINT32_MAX},
    {"float", "float32", 4, 0, 0},
    {"double", "float64", 8, 0, 0},
};

static int is_float(int t) { return t == T_F32 || t == T_F64; }

typedef struct ply_prop {
    const char *name;
    int type, count_type, is_list, role;
} ply_prop;

typedef struct ply_elem {
    const char *name;
    uint64_t count;
    ply_prop *props;
    uint32_t np, cap;
    int is_vertex, is_face;
} ply_elem;

typedef struct ply_reader {
    const char *file;
    gs_error *err;
    gs__soup *s;
    int format;
    ply_elem *el;
    uint32_t ne, cap;
    uint32_t nv;
    gs__lines c;                     /* header, then ascii data */
    const unsigned char *p, *end;   /* binary data */
    char *rest;                     /* ascii: rest of the current line */
    const ply_elem *cur;
    uint64_t row;
} ply_reader;

typedef struct ply_val {
    int64_t i;
    double d;
} ply_val;

static void free_header(ply_reader *r)
{
    for (uint32_t i = 0; i < r->ne; ++i) free(r->el[i].props);
    free(r->el);
}

static int type_of(const char *name)
{
    for (int t = T_I8; t <= T_F64; ++t)
        if (strcmp(name, types[t].name) == 0 || strcmp(name, types[t].alias) == 0) return t;
    return T_NONE;
}

/* ---- header ------------------------------------------------------------ */

static int hfail(ply_reader *r, int status, const char *what, const char *arg)
{
    return gs__fail(r->err, status, "%s:%u: %s%.60s", r->file, r->c.line, what, arg);
}

static int parse_format(ply_reader *r, char *rest)
{
    char *f = gs__tok(&rest), *v = gs__tok(&rest);
    if (!f || !v || gs__tok(&rest)) return hfail(r, GS_EPARSE, "malformed format line", "");
    if (strcmp(v, "1.0") != 0) return hfail(r, GS_EFORMAT, "unsupported PLY version ", v);
    if (strcmp(f, "ascii") == 0) r->format = F_ASCII;
    else if (strcmp(f, "binary_little_endian") == 0) r->format = F_LE;
    else if (strcmp(f, "binary_big_endian") == 0) r->format = F_BE;
    else return hfail(r, GS_EFORMAT, "unknown PLY format ", f);
    return GS_OK;
}

static int parse_element(ply_reader *r, char *rest)
{
    char *name = gs__tok(&rest), *cnt = gs__tok(&rest);
    int64_t n;
    if (!name || !cnt || gs__tok(&rest)) return hfail(r, GS_EPARSE, "malformed element line", "");
    if (gs__parse_i64(cnt, 0, &n) || n < 0) return hfail(r, GS_EPARSE, "bad element count ", cnt);
    if (r->ne == r->cap) {
        uint32_t cap = r->cap ? 2 * r->cap : 4;
        ply_elem *e = gs__realloc(r->el, cap, sizeof *e);
        if (!e) return hfail(r, GS_ENOMEM, "out of memory", "");
        r->el = e;
        r->cap = cap;
    }
    ply_elem *e = &r->el[r->ne];
    memset(e, 0, sizeof *e);
    e->name = name;
    e->count = (uint64_t)n;
    e->is_vertex = strcmp(name, "vertex") == 0;
    e->is_face = strcmp(name, "face") == 0;
    for (uint32_t i = 0; i < r->ne; ++i)
        if (strcmp(r->el[i].name, name) == 0)
            return hfail(r, GS_EPARSE, "duplicate element ", name);
    r->ne++;
    return GS_OK;
}

static int prop_role(const ply_elem *e, const ply_prop *p)
{
    if (e->is_vertex && !p->is_list) {
        if (strcmp(p->name, "x") == 0) return R_X;
        if (strcmp(p->name, "y") == 0) return R_Y;
        if (strcmp(p->name, "z") == 0) return R_Z;
    }
    if (e->is_face && p->is_list &&
        (strcmp(p->name, "vertex_indices") == 0 || strcmp(p->name, "vertex_index") == 0))
        return R_INDICES;
    return R_SKIP;
}

static int parse_list_types(ply_reader *r, char **rest, ply_prop *p)
{
    char *ct = gs__tok(rest), *it = gs__tok(rest);
    if (!ct || !it) return hfail(r, GS_EPARSE, "malformed list property", "");
    p->is_list = 1;
    p->count_type = type_of(ct);
    p->type = type_of(it);
    if (p->count_type == T_NONE) return hfail(r, GS_EPARSE, "unknown property type ", ct);
    if (p->type == T_NONE) return hfail(r, GS_EPARSE, "unknown property type ", it);
    if (is_float(p->count_type)) return hfail(r, GS_EPARSE, "list count of float type ", ct);
    return GS_OK;
}

static int add_prop(ply_reader *r, ply_elem *e, const ply_prop *p)
{
    for (uint32_t i = 0; i < e->np; ++i)
        if (strcmp(e->props[i].name, p->name) == 0)
            return hfail(r, GS_EPARSE, "duplicate property ", p->name);
    if (e->np == e->cap) {
        uint32_t cap = e->cap ? 2 * e->cap : 8;
        ply_prop *q = gs__realloc(e->props, cap, sizeof *q);
        if (!q) return hfail(r, GS_ENOMEM, "out of memory", "");
        e->props = q;
        e->cap = cap;
    }
    e->props[e->np++] = *p;
    return GS_OK;
}

static int parse_property(ply_reader *r, char *rest)
{
    if (r->ne == 0) return hfail(r, GS_EPARSE, "property before any element", "");
    ply_elem *e = &r->el[r->ne - 1];
    ply_prop p = {0};
    char *t = gs__tok(&rest);
    if (!t) return hfail(r, GS_EPARSE, "malformed property line", "");
    int rc = GS_OK;
    if (strcmp(t, "list") == 0)
        rc = parse_list_types(r, &rest, &p);
    else if ((p.type = type_of(t)) == T_NONE)
        rc = hfail(r, GS_EPARSE, "unknown property type ", t);
    if (rc) return rc;
    p.name = gs__tok(&rest);
    if (!p.name || gs__tok(&rest)) return hfail(r, GS_EPARSE, "malformed property line", "");
    p.role = prop_role(e, &p);
    if (p.role == R_INDICES && is_float(p.type))
        return hfail(r, GS_EPARSE, "face indices of float type in ", p.name);
    return add_prop(r, e, &p);
}

static int header_line(ply_reader *r, char *line, int *done)
{
    char *rest = line, *kw = gs__tok(&rest);
    if (!kw) return GS_OK;
    if (strcmp(kw, "comment") == 0 || strcmp(kw, "obj_info") == 0) return GS_OK;
    if (strcmp(kw, "format") == 0) return parse_format(r, rest);
    if (strcmp(kw, "element") == 0) return parse_element(r, rest);
    if (strcmp(kw, "property") == 0) return parse_property(r, rest);
    if (strcmp(kw, "end_header") == 0) {
        *done = 1;
        return GS_OK;
    }
    return hfail(r, GS_EPARSE, "unknown header keyword ", kw);
}

static int read_header(ply_reader *r)
{
    char *line;
    int k = gs__lines_next(&r->c, &line), done = 0;
    if (k != 1 || strcmp(line, "ply") != 0)
        return gs__fail(r->err, GS_EFORMAT, "%s: not a PLY file (no 'ply' first line)", r->file);
    while (!done && (k = gs__lines_next(&r->c, &line)) == 1) {
        int rc = header_line(r, line, &done);
        if (rc) return rc;
    }
    if (!done)
        return gs__fail(r->err, GS_EPARSE, "%s:%u: the header has no end_header line", r->file,
                        r->c.line);
    if (r->format == F_NONE)
        return gs__fail(r->err, GS_EPARSE, "%s: the header has no format line", r->file);
    return GS_OK;
}

/* ---- header checks: roles present, counts fit the file ----------------- */

static int check_roles(ply_reader *r)
{
    const ply_elem *v = NULL, *f = NULL;
    for (uint32_t i = 0; i < r->ne; ++i) {
        if (r->el[i].count && r->el[i].np == 0)
            return gs__fail(r->err, GS_EPARSE, "%s: element '%s' has no properties", r->file,
                            r->el[i].name);
        if (r->el[i].is_vertex) v = &r->el[i];
        if (r->el[i].is_face) f = &r->el[i];
    }
    if (!v) return gs__fail(r->err, GS_EPARSE, "%s: no 'vertex' element in the header", r->file);
    int seen[5] = {0};
    for (uint32_t i = 0; i < v->np; ++i) seen[v->props[i].role] = 1;
    if (!seen[R_X] || !seen[R_Y] || !seen[R_Z])
        return gs__fail(r->err, GS_EPARSE, "%s: the vertex element lacks property %c", r->file,
                        !seen[R_X] ? 'x' : !seen[R_Y] ? 'y' : 'z');
    if (f) {
        int has = 0;
        for (uint32_t i = 0; i < f->np; ++i) has |= f->props[i].role == R_INDICES;
        if (!has)
            return gs__fail(r->err, GS_EPARSE, "%s: the face element has no vertex_indices list",
                            r->file);
    }
    return GS_OK;
}

static uint64_t min_row_bytes(const ply_reader *r, const ply_elem *e)
{
    uint64_t n = 0;
    for (uint32_t i = 0; i < e->np; ++i) {
        const ply_prop *p = &e->props[i];
        n += r->format == F_ASCII ? 2 : (uint64_t)types[p->is_list ? p->count_type : p->type].size;
    }
    return n;
}

static void plural(const ply_elem *e, char *buf, size_t n)
{
    if (e->is_vertex) snprintf(buf, n, "vertices");
    else if (e->is_face) snprintf(buf, n, "faces");
    else snprintf(buf, n, "'%.40s' elements", e->name);
}

static int check_counts(ply_reader *r, uint64_t room, uint64_t *n_faces)
{
    char what[64];
    *n_faces = 0;
    for (uint32_t i = 0; i < r->ne; ++i) {
        const ply_elem *e = &r->el[i];
        uint64_t row = min_row_bytes(r, e);
        if (row && e->count > room / row) {
            plural(e, what, sizeof what);
            return gs__fail(r->err, GS_EPARSE,
                            "%s: header claims %llu %s but the file holds at most %llu",
                            r->file, (unsigned long long)e->count, what,
                            (unsigned long long)(room / row));
        }
        room -= e->count * row;
        if (e->is_vertex) {
            if (e->count >= UINT32_MAX)
                return gs__fail(r->err, GS_ELIMIT, "%s: %llu vertices is more than geosep supports",
                                r->file, (unsigned long long)e->count);
            r->nv = (uint32_t)e->count;
        }
        if (e->is_face) *n_faces = e->count;
    }
    return GS_OK;
}

/* ---- data: one value at a time, ascii or binary ------------------------ */

static void where(const ply_reader *r, char *buf, size_t n)
{
    if (r->format == F_ASCII)
        snprintf(buf, n, "%s:%u: %.40s %llu", r->file, r->c.line, r->cur->name,
                 (unsigned long long)r->row);
    else
        snprintf(buf, n, "%s: %.40s %llu", r->file, r->cur->name, (unsigned long long)r->row);
}

static int dfail(ply_reader *r, int status, const char *fmt, ...) GS_PRINTF(3, 4);

static int dfail(ply_reader *r, int status, const char *fmt, ...)
{
    char w[560], msg[200];
    where(r, w, sizeof w);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return gs__fail(r->err, status, "%s: %s", w, msg);
}

static uint64_t load_bytes(const unsigned char *p, int n, int big)
{
    uint64_t u = 0;
    for (int k = 0; k < n; ++k) u |= (uint64_t)p[big ? n - 1 - k : k] << (8 * k);
    return u;
}

static void decode(int type, uint64_t u, ply_val *v)
{
    switch (type) {
    case T_I8: v->i = (int8_t)(uint8_t)u; break;
    case T_I16: v->i = (int16_t)(uint16_t)u; break;
    case T_I32: v->i = (int32_t)(uint32_t)u; break;
    case T_F32: {
        uint32_t b = (uint32_t)u;
        float f;
        memcpy(&f, &b, sizeof f);
        v->d = f;
        return;
    }
    case T_F64: memcpy(&v->d, &u, sizeof v->d); return;
    default: v->i = (int64_t)u; break;
    }
    v->d = (double)v->i;
}

static int get_binary(ply_reader *r, int type, ply_val *v)
{
    int n = types[type].size;
    if (r->end - r->p < n)
        return dfail(r, GS_EPARSE, "the file ends inside this element (truncated?)");
    decode(type, load_bytes(r->p, n, r->format == F_BE), v);
    r->p += n;
    return GS_OK;
}

static int get_ascii(ply_reader *r, int type, ply_val *v)
{
    char *t = gs__tok(&r->rest);
    if (!t) return dfail(r, GS_EPARSE, "too few values on the line");
    if (is_float(type)) {
        if (gs__parse_double(t, &v->d)) return dfail(r, GS_EPARSE, "a value is not a number");
        return GS_OK;
    }
    if (gs__parse_i64(t, 0, &v->i)) return dfail(r, GS_EPARSE, "a value is not an integer");
    if (v->i < types[type].lo || v->i > types[type].hi)
        return dfail(r, GS_EPARSE, "value %lld does not fit its type", (long long)v->i);
    v->d = (double)v->i;
    return GS_OK;
}

static int get_val(ply_reader *r, int type, ply_val *v)
{
    return r->format == F_ASCII ? get_ascii(r, type, v) : get_binary(r, type, v);
}

/* ---- rows ------------------------------------------------------------- */

static int read_list(ply_reader *r, const ply_prop *p)
{
    ply_val v;
    int rc = get_val(r, p->count_type, &v);
    if (rc) return rc;
    int64_t n = v.i;
    if (n < 0) return dfail(r, GS_EPARSE, "negative list length %lld", (long long)n);
    if (r->format != F_ASCII && (uint64_t)n > (uint64_t)(r->end - r->p) / (uint64_t)types[p->type].size)
        return dfail(r, GS_EPARSE, "list of %lld values runs past the end of the file",
                     (long long)n);
    if (p->role == R_INDICES && n < 3)
        return dfail(r, GS_EMESH, "face has %lld vertices (at least 3 needed)", (long long)n);
    gs__fan fan;
    gs__fan_start(&fan);
    uint32_t at = r->format == F_ASCII ? r->c.line : (uint32_t)r->row;
    for (int64_t k = 0; k < n; ++k) {
        if ((rc = get_val(r, p->type, &v)) != GS_OK) return rc;
        if (p->role != R_INDICES) continue;
        if (v.i < 0 || v.i >= (int64_t)r->nv)
            return dfail(r, GS_EMESH, "face index %lld is out of range (mesh has %lld vertices)",
                         (long long)v.i, (long long)r->nv);
        if ((rc = gs__fan_add(&fan, r->s, (uint32_t)v.i, at, r->err)) != GS_OK) return rc;
    }
    return GS_OK;
}

static int read_row(ply_reader *r, const ply_elem *e)
{
    double c[3] = {0, 0, 0};
    for (uint32_t i = 0; i < e->np; ++i) {
        const ply_prop *p = &e->props[i];
        ply_val v;
        int rc = p->is_list ? read_list(r, p) : get_val(r, p->type, &v);
        if (rc) return rc;
        if (!p->is_list && p->role >= R_X && p->role <= R_Z) c[p->role - R_X] = v.d;
    }
    if (r->format == F_ASCII && !gs__blank(r->rest))
        return dfail(r, GS_EPARSE, "extra values at the end of the line");
    if (!e->is_vertex) return GS_OK;
    for (int k = 0; k < 3; ++k)
        if (!isfinite(c[k]))
            return dfail(r, GS_EMESH, "non-finite coordinate %c = %g", "xyz"[k], c[k]);
    return gs__soup_add_vertex(r->s, c[0], c[1], c[2], r->err);
}

static int next_ascii_row(ply_reader *r)
{
    char *line;
    int k;
    while ((k = gs__lines_next(&r->c, &line)) == 1)
        if (!gs__blank(line)) {
            r->rest = line;
            return GS_OK;
        }
    if (k < 0) return dfail(r, GS_EPARSE, "NUL byte in an ascii file");
    return gs__fail(r->err, GS_EPARSE, "%s:%u: the file ends at %s %llu (header declares %llu)",
                    r->file, r->c.line, r->cur->name, (unsigned long long)r->row,
                    (unsigned long long)r->cur->count);
}

static int read_body(ply_reader *r)
{
    for (uint32_t i = 0; i < r->ne; ++i) {
        r->cur = &r->el[i];
        for (r->row = 0; r->row < r->cur->count; ++r->row) {
            int rc = r->format == F_ASCII ? next_ascii_row(r) : GS_OK;
            if (rc == GS_OK) rc = read_row(r, r->cur);
            if (rc) return rc;
        }
    }
    const char *p = r->format == F_ASCII ? r->c.p : (const char *)r->p;
    const char *end = r->format == F_ASCII ? r->c.end : (const char *)r->end;
    for (; p < end; ++p)
        if (!strchr(" \t\r\n", *p) || !*p)
            return gs__fail(r->err, GS_EPARSE, "%s: %zu bytes of unexpected data after the last "
                            "element", r->file, (size_t)(end - p));
    return GS_OK;
}

int gs__read_ply(const char *file, char *data, size_t size, gs__soup *s, gs_error *err)
{
    gs__soup_init(s, file, "line");
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.file = file;
    r.err = err;
    r.s = s;
    gs__lines_init(&r.c, data, size);
    uint64_t n_faces = 0;
    /* header lines ended by a lone CR ("ply\r"): the line cursor takes
     * "end_header\r\n" as one line end, but then the '\n' is binary data */
    int cr_only = size >= 5 && data[3] == '\r' && data[4] != '\n';
    int rc = read_header(&r);
    if (rc == GS_OK && r.format != F_ASCII && cr_only && r.c.p[-1] == '\n') r.c.p--;
    if (rc == GS_OK) rc = check_roles(&r);
    if (rc == GS_OK) {
        uint64_t room = (uint64_t)(r.c.end - r.c.p) + (r.format == F_ASCII);
        rc = check_counts(&r, room, &n_faces);
    }
    if (rc == GS_OK) rc = gs__soup_reserve(s, r.nv, n_faces, err);
    if (rc == GS_OK) {
        s->unit = r.format == F_ASCII ? "line" : "face";
        r.p = (const unsigned char *)r.c.p;
        r.end = (const unsigned char *)r.c.end;
        rc = read_body(&r);
    }
    free_header(&r);
    return rc;
}
