/* read_off.c - OFF reader: header OFF / COFF / NOFF / CNOFF / STOFF ... (3D,
 * ascii), counts "nv nf ne", one vertex per line (extra values ignored),
 * faces "k i1 ... ik [colour]" fanned; '#' comments and blank lines skipped. */
#include "io_internal.h"

#include <math.h>
#include <string.h>

typedef struct off_reader {
    const char *file;
    gs__lines c;
    gs__soup *s;
    gs_error *err;
} off_reader;

/* Next line with content (comments stripped); 0 at end, <0 error. */
static int next_content(off_reader *r, char **line)
{
    int k;
    while ((k = gs__lines_next(&r->c, line)) == 1) {
        gs__strip_comment(*line);
        if (!gs__blank(*line)) return 1;
    }
    if (k < 0)
        return gs__fail(r->err, GS_EPARSE, "%s:%u: NUL byte in a text file", r->file, r->c.line);
    return 0;
}

/* "OFF" with optional ST, C, N prefixes; 4OFF/nOFF/binary are refused. */
static int header_ok(const char *kw)
{
    size_t n = strlen(kw);
    if (n < 3 || strcmp(kw + n - 3, "OFF") != 0) return 0;
    const char *p = kw;
    if (strncmp(p, "ST", 2) == 0) p += 2;
    if (*p == 'C') ++p;
    if (*p == 'N') ++p;
    return strcmp(p, "OFF") == 0;
}

static int parse_count(off_reader *r, char *t, const char *what, uint64_t *out)
{
    int64_t v;
    if (!t || gs__parse_i64(t, 0, &v) || v < 0 || v > (int64_t)UINT32_MAX)
        return gs__fail(r->err, GS_EPARSE, "%s:%u: bad %s count '%.40s'", r->file, r->c.line,
                        what, t ? t : "(missing)");
    *out = (uint64_t)v;
    return GS_OK;
}

/* Counts line (possibly on the header line); checked against the file size:
 * a vertex line takes at least 6 bytes ("0 0 0\n"), a face line 8. */
static int read_counts(off_reader *r, char *rest, uint64_t *nv, uint64_t *nf)
{
    if (gs__blank(rest)) {
        int k = next_content(r, &rest);
        if (k <= 0)
            return k ? k : gs__fail(r->err, GS_EPARSE, "%s:%u: file ends before the counts line",
                                    r->file, r->c.line);
    }
    uint64_t ne;
    int rc = parse_count(r, gs__tok(&rest), "vertex", nv);
    if (rc == GS_OK) rc = parse_count(r, gs__tok(&rest), "face", nf);
    if (rc == GS_OK && !gs__blank(rest)) rc = parse_count(r, gs__tok(&rest), "edge", &ne);
    if (rc) return rc;
    uint64_t room = (uint64_t)(r->c.end - r->c.p) + 1;
    if (*nv * 6 + *nf * 8 > room)
        return gs__fail(r->err, GS_EPARSE,
                        "%s:%u: header claims %llu vertices and %llu faces but only %llu bytes "
                        "follow", r->file, r->c.line, (unsigned long long)*nv,
                        (unsigned long long)*nf, (unsigned long long)(room - 1));
    return GS_OK;
}

static int read_vertex(off_reader *r, uint32_t i)
{
    char *line, *t;
    int k = next_content(r, &line);
    if (k <= 0)
        return k ? k : gs__fail(r->err, GS_EPARSE,
                                "%s:%u: file ends after %u of the vertices the header declares",
                                r->file, r->c.line, i);
    double c[3];
    for (int j = 0; j < 3; ++j) {
        t = gs__tok(&line);
        if (!t || gs__parse_double(t, &c[j]))
            return gs__fail(r->err, GS_EPARSE, "%s:%u: vertex %u: coordinate %c is %s", r->file,
                            r->c.line, i, "xyz"[j], t ? "not a number" : "missing");
        if (!isfinite(c[j]))
            return gs__fail(r->err, GS_EMESH,
                            "%s:%u: vertex %u has a non-finite coordinate (%c = %.40s)", r->file,
                            r->c.line, i, "xyz"[j], t);
    }
    return gs__soup_add_vertex(r->s, c[0], c[1], c[2], r->err);
}

static int read_face(off_reader *r, uint32_t i, uint32_t nv)
{
    char *line, *t;
    int k = next_content(r, &line);
    if (k <= 0)
        return k ? k : gs__fail(r->err, GS_EPARSE,
                                "%s:%u: file ends after %u of the faces the header declares",
                                r->file, r->c.line, i);
    int64_t n, idx;
    t = gs__tok(&line);
    if (gs__parse_i64(t, 0, &n) || n < 3)
        return gs__fail(r->err, GS_EPARSE, "%s:%u: face %u: vertex count '%.40s' (at least 3 "
                        "needed)", r->file, r->c.line, i, t);
    gs__fan fan;
    gs__fan_start(&fan);
    for (int64_t j = 0; j < n; ++j) {
        t = gs__tok(&line);
        if (!t)
            return gs__fail(r->err, GS_EPARSE, "%s:%u: face declares %lld vertices but the line "
                            "has only %lld", r->file, r->c.line, (long long)n, (long long)j);
        if (gs__parse_i64(t, 0, &idx))
            return gs__fail(r->err, GS_EPARSE, "%s:%u: face index '%.40s' is not an integer",
                            r->file, r->c.line, t);
        if (idx < 0 || idx >= (int64_t)nv)
            return gs__fail(r->err, GS_EMESH, "%s:%u: face index %lld is out of range (mesh has "
                            "%u vertices)", r->file, r->c.line, (long long)idx, nv);
        int rc = gs__fan_add(&fan, r->s, (uint32_t)idx, r->c.line, r->err);
        if (rc) return rc;
    }
    return GS_OK; /* colour values may follow */
}

int gs__read_off(const char *file, char *data, size_t size, gs__soup *s, gs_error *err)
{
    gs__soup_init(s, file, "line");
    off_reader r = {file, {0}, s, err};
    gs__lines_init(&r.c, data, size);
    char *line;
    int k = next_content(&r, &line);
    if (k < 0) return k;
    char *kw = k ? gs__tok(&line) : NULL;
    if (!kw || !header_ok(kw))
        return gs__fail(err, GS_EFORMAT, "%s:%u: not an OFF file (header '%.20s'; only 3D "
                        "ascii OFF, COFF, NOFF, STOFF... are read)", file, r.c.line,
                        kw ? kw : "");
    uint64_t nv, nf;
    int rc = read_counts(&r, line, &nv, &nf);
    if (rc == GS_OK) rc = gs__soup_reserve(s, nv, nf, err);
    for (uint32_t i = 0; rc == GS_OK && i < nv; ++i) rc = read_vertex(&r, i);
    for (uint32_t i = 0; rc == GS_OK && i < nf; ++i) rc = read_face(&r, i, (uint32_t)nv);
    if (rc) return rc;
    k = next_content(&r, &line);
    if (k < 0) return k;
    if (k)
        return gs__fail(err, GS_EPARSE, "%s:%u: unexpected data after the %llu faces the "
                        "header declares", file, r.c.line, (unsigned long long)nf);
    return GS_OK;
}
