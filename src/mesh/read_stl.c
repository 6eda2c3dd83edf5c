/* read_stl.c - STL reader, ascii ("solid ... facet normal ... outer loop
 * vertex ... endloop endfacet ... endsolid") and binary (80-byte header, uint32
 * count, 50 bytes per triangle). Corners are welded by exact position in order
 * of first appearance (-0.0 == 0.0), with an open-addressing hash table. */
#include "io_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- welding ---------------------------------------------------------- */

typedef struct weld {
    uint32_t *slot; /* vertex id or GS_NONE */
    size_t mask;    /* capacity - 1 (a power of two) */
} weld;

static uint64_t hash3(const double *p)
{
    uint64_t h = 0x9E3779B97F4A7C15u;
    for (int k = 0; k < 3; ++k) {
        uint64_t b;
        memcpy(&b, &p[k], sizeof b);
        h = (h ^ b) * 0xBF58476D1CE4E5B9u;
        h ^= h >> 31;
    }
    return h;
}

static size_t probe(const weld *w, const gs__soup *s, const double *p)
{
    size_t i = (size_t)hash3(p) & w->mask;
    while (w->slot[i] != GS_NONE && memcmp(s->xyz + 3 * (size_t)w->slot[i], p, 3 * sizeof *p))
        i = (i + 1) & w->mask;
    return i;
}

static int weld_alloc(weld *w, size_t cap, const char *file, gs_error *err)
{
    w->slot = gs__malloc(cap, sizeof *w->slot);
    if (!w->slot) return gs__fail(err, GS_ENOMEM, "%s: out of memory welding vertices", file);
    for (size_t i = 0; i < cap; ++i) w->slot[i] = GS_NONE;
    w->mask = cap - 1;
    return GS_OK;
}

static int weld_grow(weld *w, const gs__soup *s, gs_error *err)
{
    weld bigger;
    if ((w->mask + 1) > SIZE_MAX / 4) return gs__fail(err, GS_ENOMEM, "%s: too many vertices", s->file);
    int rc = weld_alloc(&bigger, 2 * (w->mask + 1), s->file, err);
    if (rc) return rc;
    for (uint32_t v = 0; v < s->nv; ++v) bigger.slot[probe(&bigger, s, s->xyz + 3 * (size_t)v)] = v;
    free(w->slot);
    *w = bigger;
    return GS_OK;
}

/* The id of position p (x, y, z finite), adding it if new. */
static int weld_vertex(weld *w, gs__soup *s, const double *p, uint32_t *id, gs_error *err)
{
    double q[3] = {p[0] + 0.0, p[1] + 0.0, p[2] + 0.0}; /* -0.0 -> +0.0 */
    size_t i = probe(w, s, q);
    if (w->slot[i] != GS_NONE) {
        *id = w->slot[i];
        return GS_OK;
    }
    int rc = gs__soup_add_vertex(s, q[0], q[1], q[2], err);
    if (rc) return rc;
    *id = s->nv - 1;
    w->slot[i] = *id;
    if (2 * (size_t)s->nv > w->mask) return weld_grow(w, s, err);
    return GS_OK;
}

/* ---- binary ----------------------------------------------------------- */

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

int gs__stl_is_binary(const char *data, size_t size)
{
    if (size < 84) return 0;
    uint64_t n = le32((const unsigned char *)data + 80);
    return 84 + 50 * n == (uint64_t)size;
}

static int binary_triangle(const unsigned char *t, uint32_t i, weld *w, gs__soup *s,
                           gs_error *err)
{
    uint32_t id[3];
    for (int c = 0; c < 3; ++c) {
        double p[3];
        for (int k = 0; k < 3; ++k) {
            uint32_t b = le32(t + 12 + 12 * c + 4 * k);
            float f;
            memcpy(&f, &b, sizeof f);
            p[k] = f;
            if (!isfinite(p[k]))
                return gs__fail(err, GS_EMESH, "%s: triangle %u: corner %d has a non-finite "
                                "coordinate (%c = %g)", s->file, i, c, "xyz"[k], p[k]);
        }
        int rc = weld_vertex(w, s, p, &id[c], err);
        if (rc) return rc;
    }
    return gs__soup_add_tri(s, id[0], id[1], id[2], i, err);
}

static int read_binary(const unsigned char *d, gs__soup *s, gs_error *err)
{
    uint32_t n = le32(d + 80);
    int rc = gs__soup_reserve(s, 0, n, err);
    size_t cap = 1024;
    while (cap < 6 * (size_t)n && cap < SIZE_MAX / 4) cap *= 2;
    weld w = {NULL, 0};
    if (rc == GS_OK) rc = weld_alloc(&w, cap, s->file, err);
    for (uint32_t i = 0; rc == GS_OK && i < n; ++i)
        rc = binary_triangle(d + 84 + 50 * (size_t)i, i, &w, s, err);
    free(w.slot);
    return rc;
}

/* ---- ascii ------------------------------------------------------------ */

typedef struct stl_text {
    char *p, *end;
    uint32_t line;     /* line of the read position                    */
    uint32_t tok_line; /* line of the last token returned                */
    const char *file;
    gs_error *err;
} stl_text;

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

/* Consume one whitespace char at p, counting line ends (\n, \r\n, \r). */
static void eat_space(stl_text *t)
{
    char c = *t->p++;
    if (c == '\n') t->line++;
    if (c == '\r') {
        t->line++;
        if (t->p < t->end && *t->p == '\n') t->p++;
    }
}

/* Next token (terminated in place) or NULL at the end; *bad on a NUL byte. */
static char *next_tok(stl_text *t, int *bad)
{
    while (t->p < t->end && is_space(*t->p)) eat_space(t);
    *bad = t->p < t->end && *t->p == '\0';
    t->tok_line = t->line;
    if (t->p >= t->end || *bad) return NULL;
    char *s = t->p;
    while (t->p < t->end && *t->p && !is_space(*t->p)) t->p++;
    if (t->p < t->end && *t->p == '\0') {
        *bad = 1;
        return NULL;
    }
    if (t->p < t->end) { /* the data is followed by a '\0', so s ends there */
        char *q = t->p;
        eat_space(t);
        *q = '\0';
    }
    return s;
}

static void skip_line(stl_text *t)
{
    while (t->p < t->end && *t->p != '\n' && *t->p != '\r' && *t->p) t->p++;
}

static int eq_ci(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b) {
        char x = (*a >= 'A' && *a <= 'Z') ? (char)(*a - 'A' + 'a') : *a;
        if (x != *b) return 0;
    }
    return *a == *b;
}

static int expect(stl_text *t, const char *word, char **got)
{
    int bad;
    char *s = next_tok(t, &bad);
    if (got) *got = s;
    if (bad) return gs__fail(t->err, GS_EPARSE, "%s:%u: NUL byte in an ascii STL", t->file, t->line);
    if (word && (!s || !eq_ci(s, word)))
        return gs__fail(t->err, GS_EPARSE, "%s:%u: expected '%s', found %s%.40s%s", t->file,
                        t->tok_line, word, s ? "'" : "the end of the file", s ? s : "", s ? "'" : "");
    return GS_OK;
}

static int read_point(stl_text *t, const char *what, double *p)
{
    for (int k = 0; k < 3; ++k) {
        char *s;
        int rc = expect(t, NULL, &s);
        if (rc) return rc;
        if (!s || gs__parse_double(s, &p[k]))
            return gs__fail(t->err, GS_EPARSE, "%s:%u: %s coordinate %c is %s '%.40s'", t->file,
                            t->tok_line, what, "xyz"[k], s ? "not a number:" : "missing", s ? s : "");
        if (!isfinite(p[k]) && strcmp(what, "vertex") == 0)
            return gs__fail(t->err, GS_EMESH, "%s:%u: vertex has a non-finite coordinate (%c = %.40s)",
                            t->file, t->tok_line, "xyz"[k], s);
    }
    return GS_OK;
}

static int read_facet(stl_text *t, weld *w, gs__soup *s)
{
    uint32_t at = t->tok_line; /* of the 'facet' keyword */
    double p[3];
    int rc = expect(t, "normal", NULL);
    if (rc == GS_OK) rc = read_point(t, "normal", p);
    if (rc == GS_OK) rc = expect(t, "outer", NULL);
    if (rc == GS_OK) rc = expect(t, "loop", NULL);
    gs__fan fan;
    gs__fan_start(&fan);
    char *tok = NULL;
    while (rc == GS_OK && (rc = expect(t, NULL, &tok)) == GS_OK && tok && eq_ci(tok, "vertex")) {
        uint32_t id;
        rc = read_point(t, "vertex", p);
        if (rc == GS_OK) rc = weld_vertex(w, s, p, &id, t->err);
        if (rc == GS_OK) rc = gs__fan_add(&fan, s, id, at, t->err);
    }
    if (rc) return rc;
    if (!tok || !eq_ci(tok, "endloop"))
        return gs__fail(t->err, GS_EPARSE, "%s:%u: expected 'endloop', found %s%.40s%s", t->file,
                        t->tok_line, tok ? "'" : "the end of the file", tok ? tok : "", tok ? "'" : "");
    if (fan.n < 3)
        return gs__fail(t->err, GS_EMESH, "%s:%u: facet has %u vertices (3 needed)", t->file,
                        at, fan.n);
    return expect(t, "endfacet", NULL);
}

static int read_solids(stl_text *t, weld *w, gs__soup *s)
{
    int rc = expect(t, "solid", NULL);
    skip_line(t);
    char *tok;
    while (rc == GS_OK && (rc = expect(t, NULL, &tok)) == GS_OK) {
        if (!tok)
            return gs__fail(t->err, GS_EPARSE, "%s:%u: the file ends before 'endsolid'", t->file,
                            t->line);
        if (eq_ci(tok, "facet")) {
            rc = read_facet(t, w, s);
            continue;
        }
        if (!eq_ci(tok, "endsolid"))
            return gs__fail(t->err, GS_EPARSE, "%s:%u: expected 'facet' or 'endsolid', found "
                            "'%.40s'", t->file, t->tok_line, tok);
        skip_line(t);
        if ((rc = expect(t, NULL, &tok)) != GS_OK || !tok) return rc;
        if (!eq_ci(tok, "solid"))
            return gs__fail(t->err, GS_EPARSE, "%s:%u: unexpected '%.40s' after 'endsolid'",
                            t->file, t->tok_line, tok);
        skip_line(t);
    }
    return rc;
}

static int read_ascii(char *data, size_t size, gs__soup *s, gs_error *err)
{
    stl_text t = {data, data + size, 1, 1, s->file, err};
    weld w = {NULL, 0};
    int rc = weld_alloc(&w, 1024, s->file, err);
    if (rc == GS_OK) rc = read_solids(&t, &w, s);
    free(w.slot);
    return rc;
}

static int starts_with_solid(const char *d, size_t size)
{
    size_t i = 0;
    while (i < size && is_space(d[i])) ++i;
    if (size - i < 5) return 0;
    char w[6];
    memcpy(w, d + i, 5);
    w[5] = '\0';
    return eq_ci(w, "solid");
}

int gs__read_stl(const char *file, char *data, size_t size, gs__soup *s, gs_error *err)
{
    gs__soup_init(s, file, "triangle");
    if (gs__stl_is_binary(data, size)) return read_binary((const unsigned char *)data, s, err);
    s->unit = "line";
    if (starts_with_solid(data, size) && !memchr(data, '\0', size))
        return read_ascii(data, size, s, err);
    if (size < 84)
        return gs__fail(err, GS_EPARSE, "%s: %zu bytes is too short for a binary STL and the "
                        "file is not ascii STL", file, size);
    uint64_t n = le32((const unsigned char *)data + 80);
    return gs__fail(err, GS_EPARSE, "%s: binary STL header says %llu triangles (%llu bytes) "
                    "but the file has %zu bytes", file, (unsigned long long)n,
                    (unsigned long long)(84 + 50 * n), size);
}
