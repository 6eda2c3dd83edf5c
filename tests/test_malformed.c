/* test_malformed.c - hostile mesh files: a table of malformed inputs, each
 * with the status and a message fragment it must produce (the file name is
 * always required too), then a deterministic fuzz loop (byte flips and
 * truncations of one valid file per format) that only demands no crash;
 * then database files with every optional section (leaf tables, input-id
 * aliases) damaged in each section: named by the open or by verify. */
#include "check.h"
#include "db/format.h"
#include "geosep.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char g_dir[256];

enum { K_FILE, K_DIR, K_MISSING };

typedef struct bad_case {
    const char *name;   /* what is wrong                                 */
    const char *file;   /* file name (its extension picks the reader)    */
    const char *bytes;  /* content                                       */
    size_t len;         /* content size (literals may hold NUL bytes)    */
    int status;         /* expected status                               */
    const char *substr; /* the message must contain this                 */
    int kind;
} bad_case;

#define CASE(name, file, lit, status, sub) {name, file, lit, sizeof(lit) - 1, status, sub, K_FILE}
#define TRI3 "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
#define PLYH "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n" \
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
#define PLYLE "ply\nformat binary_little_endian 1.0\n"
#define F0 "\0\0\0\0"
#define F1 "\0\0\x80\x3f"
#define HDR80 "binary stl header..............................................................!"
#define OFF3 "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n"
#define STLA "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"

_Static_assert(sizeof HDR80 == 81, "binary STL header is 80 bytes");

/* binary STL, 1 triangle, a NaN coordinate (bytes 84 + 12 + 4 .. +7) */
static const unsigned char STL_NAN[134] = {[80] = 1, [100] = 0, [101] = 0, [102] = 0xc0, [103] = 0x7f};

static const bad_case CASES[] = {
    /* ---- OBJ ---- */
    CASE("obj truncated face", "trunc.obj", TRI3 "f 1 2", GS_EMESH, "trunc.obj:4: face has 2 vertices"),
    CASE("obj truncated vertex", "truncv.obj", "v 0 0 0\nv 1 0", GS_EPARSE, ":2: vertex has 2 coordinates"),
    CASE("obj NaN", "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", GS_EMESH, ":1: vertex 0 has a non-finite"),
    CASE("obj inf", "inf.obj", "v 0 0 0\nv 1 -inf 0\nv 0 1 0\nf 1 2 3\n", GS_EMESH, ":2: vertex 1 has a non-finite"),
    CASE("obj overflow to inf", "ovf.obj", "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n", GS_EMESH, ":3:"),
    CASE("obj index out of range", "range.obj", TRI3 "f 1 2 7\n", GS_EMESH, "range.obj:4: face index 7 is out of range (mesh has 3"),
    CASE("obj index 0", "zero.obj", TRI3 "f 0 1 2\n", GS_EPARSE, ":4: face index 0"),
    CASE("obj negative out of range", "neg.obj", TRI3 "f -1 -2 -9\n", GS_EMESH, "face index -9"),
    CASE("obj huge index", "huge.obj", TRI3 "f 1 2 99999999999999999999\n", GS_EPARSE, "not an index"),
    CASE("obj repeated index", "rep.obj", TRI3 "f 1 2 2\n", GS_EMESH, "line 4: face repeats a vertex"),
    CASE("obj zero area", "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", GS_EMESH, "line 4: zero-area"),
    CASE("obj coordinates 1e300 (4th powers overflow)", "big.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1e300 0\nf 1 2 3\n", GS_EMESH,
         "line 4: edge 0-1 has length 1e+300, outside geosep's range [1e-50, 1e+50]"),
    CASE("obj coordinates -1e308..1e308 (difference overflows)", "ovfd.obj", "v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n", GS_EMESH,
         "line 4: edge 0-1 has length inf, outside"),
    CASE("obj edge above 1e50", "big2.obj", "v 0 0 0\nv 1 0 0\nv 0 2e50 0\nf 1 2 3\n", GS_EMESH, "edge 1-2 has length 2e+50"),
    CASE("obj coordinates 1e-300 (4th powers underflow)", "tiny.obj", "v 0 0 0\nv 1e-300 0 0\nv 0 1e-300 0\nf 1 2 3\n", GS_EMESH,
         "line 4: edge 0-1 has length 1e-300, outside"),
    CASE("obj non-manifold edge", "nme.obj", TRI3 "v 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n", GS_EMESH, "non-manifold edge"),
    CASE("obj non-manifold vertex", "nmv.obj",
         "v 0 0 0\nv 1 0 1\nv -1 1 1\nv -1 -1 1\nv 1 0 -1\nv -1 1 -1\nv -1 -1 -1\n"
         "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 1 6 5\nf 1 7 6\nf 1 5 7\n", GS_EMESH, "non-manifold vertex 0"),
    CASE("obj inconsistent orientation", "orient.obj", TRI3 "v 1 1 0\nf 1 2 3\nf 1 2 4\n", GS_EMESH, "inconsistent orientation"),
    CASE("obj coordinate not a number", "abc.obj", "v 1 2 abc\n", GS_EPARSE, ":1: vertex coordinate z is not a number"),
    CASE("obj corner not an index", "corner.obj", TRI3 "f 1 x 3\n", GS_EPARSE, ":4: face corner 'x'"),
    CASE("obj line continuation", "cont.obj", TRI3 "f 1 2 \\\n3\n", GS_EPARSE, ":4: line continuation"),
    CASE("obj NUL byte", "nul.obj", TRI3 "f 1\0 2 3\n", GS_EPARSE, ":4: NUL byte"),
    CASE("obj vertices but no faces", "nofaces.obj", TRI3, GS_EMESH, "no faces"),
    CASE("obj only comments", "comments.obj", "# one\n# two\n\n", GS_EPARSE, "no vertices and no faces"),
    CASE("obj garbage bytes", "garbage.obj", "\x01\x02\x7f\xff\xfe\n\x80zz", GS_EPARSE, "no vertices and no faces"),
    CASE("empty file", "empty.obj", "", GS_EPARSE, "empty file"),
    /* ---- PLY ---- */
    CASE("ply truncated ascii", "trunc.ply", PLYH "0 0 0\n1 0 0\n", GS_EPARSE, "header claims 3 vertices but the file holds at most 2"),
    CASE("ply truncated ascii row", "truncrow.ply", PLYH "0 0 0\n1 0 0\n0 1 0\n3 0 1", GS_EPARSE, ":13: face 0: too few values"),
    CASE("ply too few values", "few.ply", PLYH "0 0 0\n1 0\n0 1 0\n3 0 1 2\n", GS_EPARSE, ":11: vertex 1: too few values"),
    CASE("ply extra values", "extra.ply", PLYH "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", GS_EPARSE, ":10: vertex 0: extra values"),
    CASE("ply ascii list 200", "list200.ply", PLYH "0 0 0\n1 0 0\n0 1 0\n200 0 1 2\n", GS_EPARSE, ":13: face 0: too few values"),
    CASE("ply 4e9 vertices", "huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n0 0 0\n", GS_EPARSE, "header claims 4000000000 vertices but the file holds at most"),
    CASE("ply binary counts lie", "lie.ply", PLYLE "element vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         F0 F0 F0 F1 F0, GS_EPARSE, "header claims 4 vertices but the file holds at most 1"),
    CASE("ply binary list runs past the end", "list.ply", PLYLE "element vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         F0 F0 F0 F1 F0 F0 F0 F1 F0 "\xc8" "\0\0\0\0\1\0\0\0", GS_EPARSE, "face 0: list of 200 values runs past the end"),
    CASE("ply binary face count 1e9", "bigface.ply", PLYLE "element vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
         F0 F0 F0 F1 F0 F0 F0 F1 F0 "\x00\xca\x9a\x3b" "\0\0\0\0\1\0\0\0\2\0\0\0", GS_EPARSE, "list of 1000000000 values"),
    CASE("ply binary truncated in a row", "truncb.ply", PLYLE "element vertex 3\nproperty double x\nproperty float y\n"
         "property float z\nend_header\n" F0 F0 F0 F0 F0 F0 F0 F0 F0 F0 F0 "\1\2",
         GS_EPARSE, "at most 2"),
    /* structure-level cases of the fz2 campaign (all rejected cleanly; kept as regressions) */
    CASE("ply BE list count 2^32-1", "bemax.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
         F0 F0 F0 "\x3f\x80\0\0" F0 F0 F0 "\x3f\x80\0\0" F0 "\xff\xff\xff\xff" "\0\0\0\0\0\0\0\1\0\0\0\2",
         GS_EPARSE, "face 0: list of 4294967295 values runs past the end of the file"),
    CASE("ply binary negative list count", "negcount.ply", PLYLE "element vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n"
         F0 F0 F0 F1 F0 F0 F0 F1 F0 "\xff\xff\xff\xff" "\0\0\0\0\1\0\0\0\2\0\0\0", GS_EPARSE, "face 0: negative list length -1"),
    CASE("ply binary truncated at a record boundary", "recb.ply", PLYLE "element vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         F0 F0 F0 F1 F0 F0 F0 F1 F0, GS_EPARSE, "header claims 1 faces but the file holds at most 0"),
    CASE("ply binary list count of float type", "fcount.ply", PLYLE "element face 1\nproperty list float int vertex_indices\nend_header\n",
         GS_EPARSE, ":4: list count of float type float"),
    CASE("ply skipped element with a huge list", "skip.ply", PLYLE "element vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement other 1\nproperty list uint uchar junk\nend_header\n"
         F0 F0 F0 F1 F0 F0 F0 F1 F0 "\xff\xff\xff\xff" "0123", GS_EPARSE, "other 0: list of 4294967295 values runs past the end"),
    CASE("stl binary one byte too many", "plus1.stl", HDR80 "\1\0\0\0" F0 F0 F0 F0 F0 F0 F1 F0 F0 F0 F1 F0 "\0\0" "\n",
         GS_EPARSE, "says 1 triangles (134 bytes) but the file has 135"),
    CASE("ply no end_header", "noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", GS_EPARSE, "no end_header"),
    CASE("ply unknown type", "type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\nend_header\n", GS_EPARSE, ":4: unknown property type float128"),
    CASE("ply no format", "nofmt.ply", "ply\nelement vertex 0\nproperty float x\nend_header\n", GS_EPARSE, "no format line"),
    CASE("ply bad version", "version.ply", "ply\nformat ascii 2.0\nend_header\n", GS_EFORMAT, ":2: unsupported PLY version 2.0"),
    CASE("ply missing z", "noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", GS_EPARSE, "lacks property z"),
    CASE("ply float indices", "fidx.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n", GS_EPARSE, "float type"),
    CASE("ply index out of range", "prange.ply", PLYH "0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n", GS_EMESH, ":13: face 0: face index 9 is out of range"),
    CASE("ply NaN", "pnan.ply", PLYH "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", GS_EMESH, ":11: vertex 1: non-finite coordinate y"),
    CASE("ply uchar overflow", "uchar.ply", PLYH "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n", GS_EPARSE, "value 300 does not fit"),
    CASE("ply trailing data", "trail.ply", PLYH "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", GS_EPARSE, "unexpected data after the last element"),
    /* ---- STL ---- */
    CASE("stl empty", "empty.stl", "", GS_EPARSE, "empty file"),
    CASE("stl binary count disagrees with size", "count.stl", HDR80 "\5\0\0\0", GS_EPARSE, "says 5 triangles (334 bytes) but the file has 84"),
    CASE("stl too short", "short.stl", "hello", GS_EPARSE, "too short for a binary STL"),
    CASE("stl missing endloop", "endloop.stl", STLA "endfacet\nendsolid t\n", GS_EPARSE, ":7: expected 'endloop', found 'endfacet'"),
    CASE("stl truncated ascii", "trunc.stl", STLA "endloop\nendfacet\n", GS_EPARSE, "ends before 'endsolid'"),
    CASE("stl ascii NaN", "nan.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 NaN 0\n", GS_EMESH, ":5: vertex has a non-finite"),
    CASE("stl ascii bad number", "num.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0x 0\n", GS_EPARSE, ":5: vertex coordinate y is not a number"),
    CASE("stl ascii two corners", "two.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n", GS_EMESH, ":2: facet has 2 vertices"),
    CASE("stl ascii junk after endsolid", "junk.stl", STLA "endloop\nendfacet\nendsolid t\nsomething\n", GS_EPARSE, ":10: unexpected 'something'"),
    {"stl binary NaN", "bnan.stl", (const char *)STL_NAN, sizeof STL_NAN, GS_EMESH, "triangle 0: corner 0 has a non-finite", K_FILE},
    /* ---- OFF ---- */
    CASE("off bad counts", "counts.off", "OFF\n3 x 0\n", GS_EPARSE, ":2: bad face count 'x'"),
    CASE("off missing counts", "nocounts.off", "OFF\n# nothing\n", GS_EPARSE, "ends before the counts line"),
    CASE("off counts too big", "big.off", "OFF\n1000000 1 0\n0 0 0\n", GS_EPARSE, "header claims 1000000 vertices and 1 faces"),
    CASE("off face k=2", "k2.off", OFF3 "2 0 1    \n", GS_EPARSE, ":6: face 0: vertex count '2'"),
    CASE("off face 1e9 vertices", "k1e9.off", OFF3 "1000000000 0 1 2\n", GS_EPARSE, ":6: face declares 1000000000 vertices but the line has only 3"),
    CASE("off more faces than declared", "more.off", OFF3 "3 0 1 2\n3 0 2 1\n", GS_EPARSE, ":7: unexpected data after the 1 faces"),
    CASE("off fewer faces than declared", "fewer.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n# padding\n", GS_EPARSE, "file ends after 1 of the faces"),
    CASE("off index out of range", "orange.off", OFF3 "3 0 1 5\n", GS_EMESH, ":6: face index 5 is out of range (mesh has 3 vertices)"),
    CASE("off too few coordinates", "coords.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2 # pad\n", GS_EPARSE, ":4: vertex 1: coordinate z is missing"),
    CASE("off binary header", "bin.off", "OFF BINARY\n\1\2", GS_EPARSE, "bad vertex count 'BINARY'"),
    CASE("off 4D", "four.off", "4OFF\n", GS_EFORMAT, "not an OFF file"),
    /* ---- format detection, paths ---- */
    CASE("unknown extension, unknown content", "garbage.xyz", "\x13\x37 nothing to see\n", GS_EFORMAT, "unknown mesh format"),
    {"directory", "adir.obj", NULL, 0, GS_EIO, "is a directory", K_DIR},
    {"missing file", "missing.obj", NULL, 0, GS_EIO, "No such file", K_MISSING},
    /* ---- positive cases: mixed line endings, sniffing ---- */
    CASE("mixed line endings", "mixed.obj", "v 0 0 0\r\nv 1 0 0\rv 0 1 0\n\r\nf 1 2 3\r", GS_OK, ""),
    CASE("sniffed OFF", "shape.mesh", OFF3 "3 0 1 2 # c\n", GS_OK, ""),
    CASE("sniffed ascii STL", "shape.dat", STLA "endloop\nendfacet\nendsolid t\n", GS_OK, ""),
};

static const char *path_of(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", g_dir, name);
    return buf;
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    fclose(f);
}

static void run_case(const bad_case *c)
{
    char path[512];
    snprintf(path, sizeof path, "%s", path_of(c->file));
    if (c->kind == K_FILE) write_file(path, c->bytes, c->len);
    if (c->kind == K_DIR) mkdir(path, 0700);
    gs_mesh *m = (gs_mesh *)&m; /* must be reset to NULL on failure */
    gs_error e = {0, ""};
    int rc = gs_mesh_load(path, GS_FORMAT_AUTO, &m, &e);
    CHECK_MSG(rc == c->status, "%s: status %d, expected %d (%s)", c->name, rc, c->status,
              e.message);
    if (c->status != GS_OK) {
        CHECK_MSG(m == NULL, "%s: *out not NULL on failure", c->name);
        CHECK_MSG(e.status == rc, "%s: err.status %d", c->name, e.status);
        CHECK_MSG(strstr(e.message, c->file) != NULL, "%s: message lacks the file name: %s",
                  c->name, e.message);
        CHECK_MSG(strstr(e.message, c->substr) != NULL, "%s: message lacks '%s': %s", c->name,
                  c->substr, e.message);
    } else {
        gs_mesh_free(m);
    }
    if (c->kind == K_FILE) unlink(path);
    if (c->kind == K_DIR) rmdir(path);
}

/* ---- fuzz-ish: deterministic mutations of valid files ------------------ */

static uint64_t next_rand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static size_t make_base(int fmt, unsigned char *buf)
{
    static const char *const text[] = {
        "# pyramid\nv 0 0 0\nv 1 0 0\nv 0.5 0.5 1\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 2/1 4/1 3/1\n"
        "f 4//1 5//1 3//1\nf -1 -5 -3\nf 1 5 4 2\n",
        "OFF\n5 5 0\n0 0 0\n1 0 0\n0.5 0.5 1\n1 1 0\n0 1 0\n3 0 1 2\n3 1 3 2\n3 3 4 2\n3 4 0 2\n"
        "4 0 4 3 1\n",
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty "
        "float z\nelement face 5\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 "
        "0\n0.5 0.5 1\n1 1 0\n0 1 0\n3 0 1 2\n3 1 3 2\n3 3 4 2\n3 4 0 2\n4 0 4 3 1\n",
        "solid p\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0.5 0.5 1\n"
        "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex "
        "0.5 0.5 1\nendloop\nendfacet\nendsolid p\n"};
    if (fmt < 4) {
        size_t n = strlen(text[fmt]);
        memcpy(buf, text[fmt], n);
        return n;
    }
    size_t n = 0;
    if (fmt == 4) { /* binary PLY, little endian */
        const char *h = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 2\nproperty list uchar "
                        "uint vertex_indices\nend_header\n";
        static const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        static const uint32_t f[6] = {0, 1, 2, 0, 2, 3};
        memcpy(buf, h, strlen(h));
        n = strlen(h);
        memcpy(buf + n, v, sizeof v); /* the test host is little endian (checked) */
        n += sizeof v;
        for (int k = 0; k < 2; ++k) {
            buf[n++] = 3;
            memcpy(buf + n, f + 3 * k, 12);
            n += 12;
        }
        return n;
    }
    /* binary STL, 2 triangles */
    static const float t[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0},
                                   {0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 0}};
    memset(buf, ' ', 80);
    buf[80] = 2;
    buf[81] = buf[82] = buf[83] = 0;
    n = 84;
    for (int k = 0; k < 2; ++k) {
        memcpy(buf + n, t[k], 48);
        buf[n + 48] = buf[n + 49] = 0;
        n += 50;
    }
    return n;
}

static void mutate(unsigned char *buf, size_t *n, uint64_t *rng)
{
    int op = (int)(next_rand(rng) % 4);
    if (op != 1) { /* flip or overwrite a few bytes */
        int flips = 1 + (int)(next_rand(rng) % 4);
        for (int k = 0; k < flips && *n; ++k) {
            size_t at = next_rand(rng) % *n;
            uint64_t r = next_rand(rng);
            if (r & 1)
                buf[at] ^= (unsigned char)(1u << ((r >> 1) % 8));
            else
                buf[at] = (unsigned char)(r >> 8);
        }
    }
    if (op >= 1 && *n) *n = next_rand(rng) % *n; /* truncate */
}

static void fuzz(void)
{
    static const char *const ext[] = {"obj", "off", "ply", "stl", "ply", "stl"};
    const uint16_t one = 1;
    unsigned char little;
    memcpy(&little, &one, 1);
    int loads = 0, ok = 0;
    for (int fmt = 0; fmt < 6; ++fmt) {
        if (fmt == 4 && !little) continue;
        unsigned char base[2048], buf[2048];
        size_t base_n = make_base(fmt, base);
        char name[64];
        snprintf(name, sizeof name, "fuzz.%s", ext[fmt]);
        char path[512];
        snprintf(path, sizeof path, "%s", path_of(name));
        /* the unmutated file must load */
        write_file(path, base, base_n);
        gs_mesh *m = NULL;
        gs_error e = {0, ""};
        int rc = gs_mesh_load(path, GS_FORMAT_AUTO, &m, &e);
        CHECK_MSG(rc == GS_OK, "fuzz base %s: %s", ext[fmt], e.message);
        gs_mesh_free(m);
        for (uint64_t seed = 1; seed <= 400; ++seed) {
            uint64_t rng = seed * 0x9E3779B97F4A7C15u + (uint64_t)fmt;
            size_t n = base_n;
            memcpy(buf, base, n);
            mutate(buf, &n, &rng);
            write_file(path, buf, n);
            e.message[0] = '\0';
            m = NULL;
            rc = gs_mesh_load(path, GS_FORMAT_AUTO, &m, &e);
            loads++;
            ok += rc == GS_OK;
            CHECK_MSG(rc == GS_OK || (rc < 0 && e.message[0] && m == NULL),
                      "fuzz %s seed %llu: status %d, message '%s'", ext[fmt],
                      (unsigned long long)seed, rc, e.message);
            gs_mesh_free(m);
        }
        unlink(path);
    }
    printf("fuzz: %d mutated files loaded, %d accepted, the rest rejected cleanly\n", loads, ok);
}

/* ---- database files: each section of a repaired mesh's database ------- */

static void write_bytes(const char *path, const unsigned char *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    CHECK(f && fwrite(b, 1, n, f) == n);
    if (f) fclose(f);
}

/* A pinched-vertex soup repaired and built with its repair (leaf tables and
 * aliases), saved; then for every section: a byte changed in it is named by
 * verify (its checksum), the file cut inside it is refused at open (no
 * crash, the file named), and a file of format version 3 is refused naming
 * the version and telling to rebuild. */
static void test_db_sections(void)
{
    static const double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 1, 1, 0};
    static const uint32_t tri[] = {0, 1, 2, 0, 3, 4, 1, 5, 2};
    gs_mesh *m = NULL;
    gs_repair *r = NULL;
    gs_db *db = NULL;
    gs_error err = {0};
    CHECK(gs_mesh_repair(xyz, 6, tri, 3, &m, &r, &err) == GS_OK);
    gs_build_options o;
    gs_build_options_default(&o);
    o.threads = 1;
    o.repair = r;
    CHECK_MSG(m && gs_db_build(m, &o, &db, NULL, &err) == GS_OK, "%s", err.message);
    const char *path = path_of("repaired.gsdb");
    CHECK(db && gs_db_save(db, path, &err) == GS_OK);
    gs_db_free(db);
    gs_mesh_free(m);
    gs_repair_free(r);
    FILE *f = fopen(path, "rb");
    unsigned char *good = malloc(1 << 16), *b = malloc(1 << 16);
    size_t n = f ? fread(good, 1, 1 << 16, f) : 0;
    if (f) fclose(f);
    uint32_t n_sec, flags;
    memcpy(&n_sec, good + GS__H_SECTIONS, 4);
    memcpy(&flags, good + GS__H_FLAGS, 4);
    CHECK(n > 0 && n < (1 << 16) && n_sec == GS__SEC_MAX && (flags & GS__DB_FLAG_ALIASES));
    int named = 0, nonempty = 0, named_optional = 0;
    for (uint32_t e = 0; e < n_sec && e < GS__SEC_MAX; ++e) {
        uint32_t id;
        uint64_t off, size;
        const unsigned char *t = good + GS__DB_HEADER_BYTES + GS__DB_ENTRY_BYTES * e;
        memcpy(&id, t, 4), memcpy(&off, t + 8, 8), memcpy(&size, t + 16, 8);
        if (size == 0 || off + size > n) continue; /* one leaf: no curves, no records */
        nonempty++;
        char want[128];
        snprintf(want, sizeof want, "section '%s': checksum mismatch", gs__db_section_name[id]);
        memcpy(b, good, n);
        b[off + size / 2] ^= 0x5A;
        write_bytes(path, b, n);
        gs_db *d = NULL;
        int rc = gs_db_open_ex(path, GS_DB_OPEN_VERIFY, &d, &err);
        CHECK_MSG(rc == GS_EPARSE && d == NULL && strstr(err.message, want) && strstr(err.message, path),
                  "section %s changed: rc %d, '%s'", gs__db_section_name[id], rc, err.message);
        named += rc == GS_EPARSE && strstr(err.message, want) != NULL;
        named_optional += id >= GS__SEC_LEAF_NODES && rc == GS_EPARSE && strstr(err.message, want) != NULL;
        write_bytes(path, good, (size_t)(off + size / 2)); /* cut inside it */
        rc = gs_db_open(path, &d, &err);
        CHECK_MSG(rc == GS_EPARSE && d == NULL && strstr(err.message, path), "section %s cut: rc %d, '%s'",
                  gs__db_section_name[id], rc, err.message);
    }
    CHECK(named == nonempty && named_optional == GS__SEC_MAX - GS__SEC_RECORDS);
    memcpy(b, good, n);
    b[GS__H_VERSION] = 3;
    write_bytes(path, b, n);
    gs_db *d = NULL;
    char want[96];
    snprintf(want, sizeof want, "format_version 3; this geosep reads versions %u to %u", GS__DB_VERSION_MIN,
             GS__DB_VERSION);
    CHECK(gs_db_open(path, &d, &err) == GS_EFORMAT && d == NULL && strstr(err.message, want) &&
          strstr(err.message, "rebuild"));
    printf("database sections: %d of %d damaged sections named by verify (the %d optional ones too), every cut "
           "refused\n",
           named, nonempty, named_optional);
    remove(path);
    free(good);
    free(b);
}

int main(void)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/geosep-bad-XXXXXX");
    if (!mkdtemp(g_dir)) gs__test_skip("cannot create a temporary directory");
    size_t n = sizeof CASES / sizeof *CASES, negative = 0;
    for (size_t i = 0; i < n; ++i) {
        run_case(&CASES[i]);
        negative += CASES[i].status != GS_OK;
    }
    printf("malformed table: %zu cases (%zu must fail)\n", n, negative);
    fuzz();
    test_db_sections();
    CHECK_MSG(rmdir(g_dir) == 0, "temp dir %s not empty", g_dir);
    return gs__test_finish("test_malformed");
}
