/* read_obj.c - Wavefront OBJ reader: `v x y z [w|r g b]` and `f` lines with
 * v, v/vt, v//vn, v/vt/vn corners (negative = relative), polygons fanned;
 * everything else (vt, vn, g, o, s, usemtl, l, p, ...) is ignored. */
#include "io_internal.h"

#include <math.h>
#include <string.h>

static int parse_vertex(const char *file, uint32_t line, char *rest, gs__soup *s,
                        gs_error *err)
{
    double c[3];
    for (int k = 0; k < 3; ++k) {
        char *t = gs__tok(&rest);
        if (!t)
            return gs__fail(err, GS_EPARSE, "%s:%u: vertex has %d coordinates, 3 needed",
                            file, line, k);
        if (gs__parse_double(t, &c[k]))
            return gs__fail(err, GS_EPARSE, "%s:%u: vertex coordinate %c is not a number: '%.40s'",
                            file, line, "xyz"[k], t);
        if (!isfinite(c[k]))
            return gs__fail(err, GS_EMESH,
                            "%s:%u: vertex %u has a non-finite coordinate (%c = %.40s)", file,
                            line, s->nv, "xyz"[k], t);
    }
    /* w or per-vertex colours may follow; they are ignored */
    return gs__soup_add_vertex(s, c[0], c[1], c[2], err);
}

/* One corner "i", "i/t", "i//n" or "i/t/n" -> 0-based vertex id. Positive
 * ids are range-checked at the end (files may refer forward). */
static int parse_corner(const char *file, uint32_t line, const char *t, uint32_t nv,
                        uint32_t *out, gs_error *err)
{
    int64_t i;
    if (gs__parse_i64(t, '/', &i))
        return gs__fail(err, GS_EPARSE, "%s:%u: face corner '%.40s' is not an index", file,
                        line, t);
    if (i == 0)
        return gs__fail(err, GS_EPARSE, "%s:%u: face index 0 is invalid (OBJ indices start at 1)",
                        file, line);
    if (i < 0) {
        if (-i > (int64_t)nv)
            return gs__fail(err, GS_EMESH,
                            "%s:%u: face index %lld is out of range (%u vertices so far)", file,
                            line, (long long)i, nv);
        *out = (uint32_t)((int64_t)nv + i);
        return GS_OK;
    }
    if (i > (int64_t)UINT32_MAX - 1)
        return gs__fail(err, GS_EMESH, "%s:%u: face index %lld is out of range", file, line,
                        (long long)i);
    *out = (uint32_t)(i - 1);
    return GS_OK;
}

static int parse_face(const char *file, uint32_t line, char *rest, gs__soup *s,
                      gs_error *err)
{
    gs__fan fan;
    gs__fan_start(&fan);
    char *t;
    while ((t = gs__tok(&rest)) != NULL) {
        uint32_t v = 0;
        int rc = parse_corner(file, line, t, s->nv, &v, err);
        if (rc == GS_OK) rc = gs__fan_add(&fan, s, v, line, err);
        if (rc) return rc;
    }
    if (fan.n < 3)
        return gs__fail(err, GS_EMESH, "%s:%u: face has %u vertices (at least 3 needed)", file,
                        line, fan.n);
    return GS_OK;
}

static int check_ranges(const gs__soup *s, gs_error *err)
{
    for (size_t k = 0; k < 3 * (size_t)s->nf; ++k)
        if (s->tri[k] >= s->nv)
            return gs__fail(err, GS_EMESH,
                            "%s:%u: face index %u is out of range (mesh has %u vertices)",
                            s->file, s->face_line[k / 3], s->tri[k] + 1, s->nv);
    return GS_OK;
}

static int parse_line(const char *file, uint32_t line, char *text, gs__soup *s,
                      gs_error *err)
{
    gs__strip_comment(text);
    char *rest = text;
    char *kw = gs__tok(&rest);
    if (!kw) return GS_OK;
    int is_v = strcmp(kw, "v") == 0, is_f = strcmp(kw, "f") == 0;
    if (!is_v && !is_f) return GS_OK; /* vt, vn, g, o, s, usemtl, l, ... */
    size_t n = strlen(rest);
    if (n && rest[n - 1] == '\\')
        return gs__fail(err, GS_EPARSE, "%s:%u: line continuation ('\\') is not supported",
                        file, line);
    return is_v ? parse_vertex(file, line, rest, s, err) : parse_face(file, line, rest, s, err);
}

int gs__read_obj(const char *file, char *data, size_t size, gs__soup *s, gs_error *err)
{
    gs__soup_init(s, file, "line");
    gs__lines c;
    gs__lines_init(&c, data, size);
    char *text;
    int r;
    while ((r = gs__lines_next(&c, &text)) == 1) {
        int rc = parse_line(file, c.line, text, s, err);
        if (rc) return rc;
    }
    if (r < 0) return gs__fail(err, GS_EPARSE, "%s:%u: NUL byte in a text file", file, c.line);
    return check_ranges(s, err);
}
