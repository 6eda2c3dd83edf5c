/* test_mesh_io.c - mesh file input/output: one closed pyramid (a quad base)
 * written in every format and variant (OBJ, OFF, PLY ascii/LE/BE, STL
 * ascii/binary) must load to identical positions and faces; gs_mesh_save_obj
 * round trips bit-exact; health reports; the shared meshes' table. */
#include "check.h"
#include "geosep.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#ifndef M_E
#define M_E 2.7182818284590452354
#endif

static char g_dir[256];

/* ---- the reference pyramid: apex 2, base 0 1 3 4 (quad 0 4 3 1) -------- */
static const double REF_XYZ[15] = {-1.25, -0.5, 0, 2.75, -0.5, 0, 0.5, 1.5, 3,
                                   2.75,  3.5,  0, -1.25, 3.5, 0};
static const uint32_t REF_TRI[18] = {0, 1, 2, 1, 3, 2, 3, 4, 2, 4, 0, 2, 0, 4, 3, 0, 3, 1};
/* the same faces as polygons: four triangles and the base quad */
static const int POLY_N[5] = {3, 3, 3, 3, 4};
static const int POLY[16] = {0, 1, 2, 1, 3, 2, 3, 4, 2, 4, 0, 2, 0, 4, 3, 1};

static const char *path_of(const char *name)
{
    static char buf[512];
    snprintf(buf, sizeof buf, "%s/%s", g_dir, name);
    return buf;
}

static const char *write_bytes(const char *name, const void *data, size_t n)
{
    const char *p = path_of(name);
    FILE *f = fopen(p, "wb");
    if (!f || fwrite(data, 1, n, f) != n) {
        fprintf(stderr, "cannot write %s\n", p);
        exit(1);
    }
    fclose(f);
    return p;
}

static const char *write_text(const char *name, const char *text)
{
    return write_bytes(name, text, strlen(text));
}

/* ---- a growing byte buffer for binary files ---------------------------- */
typedef struct bytes {
    unsigned char d[8192];
    size_t n;
} bytes;

static void put(bytes *b, const void *p, size_t n)
{
    memcpy(b->d + b->n, p, n);
    b->n += n;
}
static void put_str(bytes *b, const char *s) { put(b, s, strlen(s)); }
static void put_uint(bytes *b, uint64_t u, int n, int big)
{
    for (int k = 0; k < n; ++k) b->d[b->n + (big ? n - 1 - k : k)] = (unsigned char)(u >> (8 * k));
    b->n += (size_t)n;
}
static void put_f32(bytes *b, double x, int big)
{
    float f = (float)x;
    uint32_t u;
    memcpy(&u, &f, 4);
    put_uint(b, u, 4, big);
}
static void put_f64(bytes *b, double x, int big)
{
    uint64_t u;
    memcpy(&u, &x, 8);
    put_uint(b, u, 8, big);
}

/* ---- comparison -------------------------------------------------------- */

static void check_mesh(const char *label, const char *path, gs_mesh_format fmt)
{
    gs_mesh *m = NULL;
    gs_error e = {0, ""};
    int rc = gs_mesh_load(path, fmt, &m, &e);
    CHECK_MSG(rc == GS_OK, "%s: load failed: %s", label, e.message);
    if (rc) return;
    CHECK_MSG(gs_mesh_num_vertices(m) == 5, "%s: %u vertices", label, gs_mesh_num_vertices(m));
    CHECK_MSG(gs_mesh_num_faces(m) == 6, "%s: %u faces", label, gs_mesh_num_faces(m));
    if (gs_mesh_num_vertices(m) == 5 && gs_mesh_num_faces(m) == 6) {
        const double *x = gs_mesh_positions(m);
        int same = 1;
        for (int i = 0; i < 15; ++i) same &= x[i] == REF_XYZ[i];
        CHECK_MSG(same, "%s: positions differ", label);
        CHECK_MSG(memcmp(gs_mesh_faces(m), REF_TRI, sizeof REF_TRI) == 0, "%s: faces differ", label);
    }
    gs_mesh_free(m);
}

/* ---- OBJ ---------------------------------------------------------------- */

static void obj_vertices(char *s, const char *eol, const char *extra)
{
    for (int v = 0; v < 5; ++v)
        sprintf(s + strlen(s), "v %.17g %.17g %.17g%s%s", REF_XYZ[3 * v], REF_XYZ[3 * v + 1],
                REF_XYZ[3 * v + 2], extra, eol);
}

static void obj_faces(char *s, const char *eol, int form, int negative)
{
    for (int f = 0, k = 0; f < 5; k += POLY_N[f++]) {
        strcat(s, "f");
        for (int j = 0; j < POLY_N[f]; ++j) {
            int i = negative ? POLY[k + j] - 5 : POLY[k + j] + 1;
            static const char *const forms[] = {" %d", " %d/1", " %d//2", " %d/1/2"};
            sprintf(s + strlen(s), forms[(form + j) % 4], i);
        }
        strcat(s, eol);
    }
}

static void test_obj(void)
{
    char s[4096] = "";
    obj_vertices(s, "\n", "");
    obj_faces(s, "\n", 0, 0);
    check_mesh("obj plain", write_text("plain.obj", s), GS_FORMAT_AUTO);

    strcpy(s, "# a comment\nmtllib x.mtl\no pyramid\n\n");
    obj_vertices(s, "\n", " 1.0");
    strcat(s, "vt 0 0\nvt 1 0\nvn 0 0 1\nvn 0 1 0\ng base\ns off\nusemtl red\n");
    obj_faces(s, "   # trailing comment\n", 1, 0);
    strcat(s, "l 1 2\np 3\n");
    check_mesh("obj all face forms", write_text("forms.obj", s), GS_FORMAT_AUTO);

    strcpy(s, "");
    obj_vertices(s, "\n", " 0.5 0.25 1");
    obj_faces(s, "\n", 3, 1);
    check_mesh("obj negative", write_text("negative.OBJ", s), GS_FORMAT_AUTO);

    strcpy(s, "");
    obj_vertices(s, "\r\n", "");
    obj_faces(s, "\r\n", 2, 0);
    check_mesh("obj crlf", write_text("crlf.obj", s), GS_FORMAT_AUTO);

    strcpy(s, "#mixed\r");
    obj_vertices(s, "\r", "");
    obj_faces(s, "\n", 0, 0);
    strcat(s, "\r\n\r\n");
    check_mesh("obj mixed endings", write_text("mixed.obj", s), GS_FORMAT_AUTO);
    check_mesh("obj by sniffing", write_text("mixed.mesh", s), GS_FORMAT_AUTO);
    check_mesh("obj explicit", write_text("mixed.txt", s), GS_FORMAT_OBJ);
}

/* ---- OFF --------------------------------------------------------------- */

static void off_text(char *s, const char *head, const char *vextra, const char *fextra)
{
    sprintf(s, "%s# comment\n\n", head);
    for (int v = 0; v < 5; ++v)
        sprintf(s + strlen(s), "%.17g %.17g %.17g%s\n", REF_XYZ[3 * v], REF_XYZ[3 * v + 1],
                REF_XYZ[3 * v + 2], vextra);
    for (int f = 0, k = 0; f < 5; k += POLY_N[f++]) {
        sprintf(s + strlen(s), "%d", POLY_N[f]);
        for (int j = 0; j < POLY_N[f]; ++j) sprintf(s + strlen(s), " %d", POLY[k + j]);
        sprintf(s + strlen(s), "%s\n", fextra);
    }
}

static void test_off(void)
{
    char s[4096];
    off_text(s, "OFF\n5 5 8\n", "", "");
    check_mesh("off", write_text("plain.off", s), GS_FORMAT_AUTO);
    off_text(s, "COFF\n5 5 0 # counts\n", " 255 0 0 255", " 0.5 0.5 0.5");
    check_mesh("coff", write_text("colour.off", s), GS_FORMAT_AUTO);
    off_text(s, "NOFF 5 5 0\n", " 0 0 1", "");
    check_mesh("noff counts on header line", write_text("noff.dat", s), GS_FORMAT_AUTO);
}

/* ---- PLY --------------------------------------------------------------- */

static void test_ply_ascii(void)
{
    char s[4096] = "ply\nformat ascii 1.0\ncomment made by hand\nobj_info x\n"
                   "element vertex 5\nproperty double x\nproperty float nx\nproperty float y\n"
                   "property float z\nproperty list uchar int uv\nproperty uchar red\n"
                   "element face 5\nproperty list uchar int vertex_indices\nproperty int flags\n"
                   "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
                   "element material 1\nproperty list uint float kd\nend_header\n";
    for (int v = 0; v < 5; ++v)
        sprintf(s + strlen(s), "%.17g 0.5 %.17g %.17g 2 7 8 255\n", REF_XYZ[3 * v],
                REF_XYZ[3 * v + 1], REF_XYZ[3 * v + 2]);
    for (int f = 0, k = 0; f < 5; k += POLY_N[f++]) {
        sprintf(s + strlen(s), "%d", POLY_N[f]);
        for (int j = 0; j < POLY_N[f]; ++j) sprintf(s + strlen(s), " %d", POLY[k + j]);
        strcat(s, " -3\n");
    }
    strcat(s, "0 1\n1 2\n3 0.1 0.2 0.3\n");
    check_mesh("ply ascii", write_text("ascii.ply", s), GS_FORMAT_AUTO);
}

/* Binary PLY: LE uses double x,y,z, uchar/int faces; BE float x,y,z and
 * uint/ushort "vertex_index"; both with extra properties and elements. */
static void ply_binary(bytes *b, int big)
{
    put_str(b, big ? "ply\nformat binary_big_endian 1.0\n" : "ply\r\nformat binary_little_endian 1.0\r\n");
    put_str(b, "element material 1\nproperty list uchar float kd\n");
    put_str(b, big ? "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                   : "element vertex 5\nproperty double x\nproperty uchar q\nproperty double y\n"
                     "property double z\nproperty list int short extra\n");
    put_str(b, big ? "element face 5\nproperty list uint ushort vertex_index\nproperty char c\n"
                   : "element face 5\nproperty float w\nproperty list uchar int vertex_indices\n");
    put_str(b, "element edge 1\nproperty int a\nproperty int b\n");
    put_str(b, big ? "end_header\n" : "end_header\r\n");
    put_uint(b, 2, 1, big);
    put_f32(b, 0.25, big);
    put_f32(b, 0.5, big);
    for (int v = 0; v < 5; ++v) {
        for (int k = 0; k < 3; ++k) {
            if (big) put_f32(b, REF_XYZ[3 * v + k], 1);
            else put_f64(b, REF_XYZ[3 * v + k], 0);
            if (!big && k == 0) put_uint(b, 9, 1, 0);
        }
        if (!big) {
            put_uint(b, 1, 4, 0);
            put_uint(b, 0xFFFF, 2, 0);
        }
    }
    for (int f = 0, k = 0; f < 5; k += POLY_N[f++]) {
        if (!big) put_f32(b, 1.5, 0);
        put_uint(b, (uint64_t)POLY_N[f], big ? 4 : 1, big);
        for (int j = 0; j < POLY_N[f]; ++j) put_uint(b, (uint64_t)POLY[k + j], big ? 2 : 4, big);
        if (big) put_uint(b, 0x80, 1, 1);
    }
    put_uint(b, 1, 4, big);
    put_uint(b, 2, 4, big);
}

static void test_ply(void)
{
    test_ply_ascii();
    bytes b = {.n = 0};
    ply_binary(&b, 0);
    check_mesh("ply binary LE", write_bytes("le.ply", b.d, b.n), GS_FORMAT_AUTO);
    b.n = 0;
    ply_binary(&b, 1);
    check_mesh("ply binary BE", write_bytes("be.PLY", b.d, b.n), GS_FORMAT_AUTO);
    check_mesh("ply sniffed", write_bytes("be.bin", b.d, b.n), GS_FORMAT_AUTO);

    /* integer coordinates (short) */
    const char *s = "ply\nformat ascii 1.0\nelement vertex 4\nproperty short x\nproperty int16 y\n"
                    "property int z\nelement face 1\nproperty list uint8 uint32 vertex_indices\n"
                    "end_header\n-3 0 0\n4 0 0\n4 5 0\n-3 5 0\n4 0 1 2 3\n";
    gs_mesh *m = NULL;
    gs_error e = {0, ""};
    int rc = gs_mesh_load(write_text("int.ply", s), GS_FORMAT_AUTO, &m, &e);
    CHECK_MSG(rc == GS_OK, "int ply: %s", e.message);
    if (m) {
        CHECK(gs_mesh_num_faces(m) == 2);
        CHECK(gs_mesh_positions(m)[0] == -3 && gs_mesh_positions(m)[7] == 5);
    }
    gs_mesh_free(m);

    /* binary PLY whose header lines end with a lone CR and whose first data
     * byte is '\n' (x = 10): that byte is data, not the rest of a CRLF */
    b.n = 0;
    put_str(&b, "ply\rformat binary_little_endian 1.0\relement vertex 3\rproperty uchar x\r"
                "property float y\rproperty float z\relement face 1\r"
                "property list uchar int vertex_indices\rend_header\r");
    const double cr_xyz[9] = {10, 0, 0, 11, 0, 0, 10, 1, 0};
    for (int v = 0; v < 3; ++v) {
        put_uint(&b, (uint64_t)cr_xyz[3 * v], 1, 0);
        put_f32(&b, cr_xyz[3 * v + 1], 0);
        put_f32(&b, cr_xyz[3 * v + 2], 0);
    }
    put_uint(&b, 3, 1, 0);
    for (int k = 0; k < 3; ++k) put_uint(&b, (uint64_t)k, 4, 0);
    m = NULL;
    rc = gs_mesh_load(write_bytes("cr.ply", b.d, b.n), GS_FORMAT_AUTO, &m, &e);
    CHECK_MSG(rc == GS_OK, "CR-only binary ply: %s", e.message);
    if (m) CHECK(gs_mesh_num_vertices(m) == 3 && memcmp(gs_mesh_positions(m), cr_xyz, sizeof cr_xyz) == 0);
    gs_mesh_free(m);
}

/* ---- STL --------------------------------------------------------------- */

static void test_stl(void)
{
    char s[8192] = "solid pyramid\n";
    for (int t = 0; t < 6; ++t) {
        strcat(s, t == 3 ? "  FACET NORMAL 0 0 -1\n  OUTER LOOP\n" : "  facet normal 0 0 1\n    outer loop\n");
        for (int c = 0; c < 3; ++c) {
            const double *p = REF_XYZ + 3 * REF_TRI[3 * t + c];
            /* -0 must weld with 0 */
            sprintf(s + strlen(s), "      vertex %.9g %.9g %s%.9g\n", p[0], p[1],
                    (p[2] == 0 && t == 5) ? "-" : "", p[2]);
        }
        strcat(s, "    endloop\n  endfacet\n");
    }
    strcat(s, "endsolid pyramid\n");
    check_mesh("stl ascii", write_text("ascii.stl", s), GS_FORMAT_AUTO);

    bytes b = {.n = 0};
    put_str(&b, "solid but binary");
    while (b.n < 80) put_str(&b, " ");
    put_uint(&b, 6, 4, 0);
    for (int t = 0; t < 6; ++t) {
        for (int k = 0; k < 3; ++k) put_f32(&b, 0, 0);
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) {
                double x = REF_XYZ[3 * REF_TRI[3 * t + c] + k];
                put_f32(&b, (x == 0 && c == 1) ? -0.0 : x, 0);
            }
        put_uint(&b, 0, 2, 0);
    }
    check_mesh("stl binary", write_bytes("binary.stl", b.d, b.n), GS_FORMAT_AUTO);
    check_mesh("stl binary sniffed", write_bytes("binary.dat", b.d, b.n), GS_FORMAT_AUTO);
}

/* ---- save / round trip ------------------------------------------------- */

static void test_round_trip(void)
{
    double xyz[15] = {0.1, 1.0 / 3, -2e-300, 1e300 / 7e299, -0.0, 5e-324 * 1e10,
                      M_PI, M_E, 1e-5 / 3, 2.0 / 3, 12345678.123456789, -0.7};
    xyz[12] = 0.3;
    xyz[13] = 0.4;
    xyz[14] = 9.0 / 7;
    const uint32_t tri[12] = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    gs_mesh *m = NULL, *back = NULL;
    gs_error e = {0, ""};
    int rc = gs_mesh_create(xyz, 5, tri, 4, &m, &e);
    CHECK_MSG(rc == GS_OK, "create: %s", e.message);
    if (rc) return;
    const char *p = path_of("round.obj");
    char saved[512];
    snprintf(saved, sizeof saved, "%s", p);
    write_text("round.obj", "old content\n");
    rc = gs_mesh_save_obj(m, saved, &e);
    CHECK_MSG(rc == GS_OK, "save: %s", e.message);
    rc = gs_mesh_load(saved, GS_FORMAT_AUTO, &back, &e);
    CHECK_MSG(rc == GS_OK, "reload: %s", e.message);
    if (back) {
        CHECK(gs_mesh_num_vertices(back) == 5 && gs_mesh_num_faces(back) == 4);
        CHECK(memcmp(gs_mesh_positions(back), gs_mesh_positions(m), sizeof xyz) == 0);
        CHECK(memcmp(gs_mesh_faces(back), tri, sizeof tri) == 0);
        gs_mesh_report r;
        gs_mesh_get_report(back, &r, NULL);
        CHECK(r.n_unreferenced == 1);
    }
    gs_mesh_free(back);

    /* a failed save leaves nothing behind */
    char bad[600];
    snprintf(bad, sizeof bad, "%s/no-such-dir/x.obj", g_dir);
    rc = gs_mesh_save_obj(m, bad, &e);
    CHECK(rc == GS_EIO && strstr(e.message, "no-such-dir") != NULL);
    CHECK(gs_mesh_save_obj(NULL, saved, &e) == GS_EARG);
    gs_mesh_free(m);
}

/* ---- health reports ---------------------------------------------------- */

static void check_report(const char *label, const char *path, uint32_t nv, uint32_t nf,
                         uint32_t comps, uint32_t loops, int32_t genus, uint32_t unref,
                         int32_t euler)
{
    gs_mesh *m = NULL;
    gs_error e = {0, ""};
    int rc = gs_mesh_load(path, GS_FORMAT_AUTO, &m, &e);
    CHECK_MSG(rc == GS_OK, "%s: %s", label, e.message);
    if (rc) return;
    gs_mesh_report r;
    CHECK(gs_mesh_get_report(m, &r, &e) == GS_OK);
    CHECK_MSG(r.n_vertices == nv && r.n_faces == nf, "%s: V=%u F=%u", label, r.n_vertices, r.n_faces);
    CHECK_MSG(r.n_components == comps, "%s: %u components", label, r.n_components);
    CHECK_MSG(r.n_boundary_loops == loops, "%s: %u loops", label, r.n_boundary_loops);
    CHECK_MSG(r.genus == genus, "%s: genus %d", label, r.genus);
    CHECK_MSG(r.n_unreferenced == unref, "%s: %u unreferenced", label, r.n_unreferenced);
    CHECK_MSG(euler == INT32_MIN || r.euler == euler, "%s: euler %d", label, r.euler);
    gs_mesh_free(m);
}

static void write_torus(const char *name, int nu, int nv)
{
    char *s = malloc(64 * (size_t)(nu * nv) * 2 + 64);
    s[0] = '\0';
    size_t n = 0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double a = 2 * M_PI * i / nu, b = 2 * M_PI * j / nv;
            n += (size_t)sprintf(s + n, "v %.17g %.17g %.17g\n", (3 + cos(b)) * cos(a),
                                 (3 + cos(b)) * sin(a), sin(b));
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            int a = j * nu + i + 1, b = j * nu + (i + 1) % nu + 1;
            int c = ((j + 1) % nv) * nu + (i + 1) % nu + 1, d = ((j + 1) % nv) * nu + i + 1;
            n += (size_t)sprintf(s + n, "f %d %d %d %d\n", a, b, c, d);
        }
    write_text(name, s);
    free(s);
}

static void test_reports(void)
{
    const char *tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    check_report("tetrahedron", write_text("tet.obj", tet), 4, 4, 1, 0, 0, 0, 2);
    const char *sq = "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\n"
                     "v 2 2 0\nf 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\n";
    check_report("open square", write_text("square.obj", sq), 9, 8, 1, 1, 0, 0, 1);
    write_torus("torus.obj", 12, 8);
    check_report("torus", path_of("torus.obj"), 96, 192, 1, 0, 1, 0, 0);
    const char *unref = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nv 0 0 1\nf 1 3 2\nf 1 2 5\nf 2 3 5\n"
                        "f 3 1 5\n";
    check_report("unreferenced vertex", write_text("unref.obj", unref), 5, 4, 1, 0, 0, 1, 2);
    const char *two = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 1 2 3\nf 4 5 6\n";
    check_report("two components", write_text("two.obj", two), 6, 2, 2, 2, 0, 0, 2);
}

/* ---- the shared meshes ------------------------------------------------- */

static void test_shared(void)
{
    static const struct {
        const char *name;
        uint32_t nv, nf;
        int32_t genus;
        uint32_t loops, comps, unref;
    } table[] = {
        {"stanford-bunny.obj", 35947, 69451, 0, 5, 1, 1113},
        {"bunny-5k.obj", 5051, 9939, 0, 5, 1, 0},
        {"bunny-10k.obj", 10000, 19816, 0, 5, 1, 0},
        {"bunny-20k.obj", 20000, 39804, 0, 5, 1, 0},
        {"spot.obj", 2930, 5856, 0, 0, 1, 0},
        {"fandisk.obj", 6475, 12946, 0, 0, 1, 0},
        {"homer.obj", 6002, 12000, 0, 0, 1, 0},
        {"rocker-arm.obj", 10044, 20088, 1, 0, 1, 0},
        {"homer-60k.obj", 60010, 120016, 0, 0, 1, 0},
    };
    if (!gs__test_shared_path("meshes/spot.obj")) {
        printf("shared meshes not found (set GEOSEP_SHARED): table check skipped\n");
        return;
    }
    for (size_t i = 0; i < sizeof table / sizeof *table; ++i) {
        char rel[128];
        snprintf(rel, sizeof rel, "meshes/%s", table[i].name);
        const char *p = gs__test_shared_path(rel);
        CHECK_MSG(p != NULL, "%s missing", table[i].name);
        if (!p) continue;
        check_report(table[i].name, p, table[i].nv, table[i].nf, table[i].comps,
                     table[i].loops, table[i].genus, table[i].unref, INT32_MIN);
    }
}

static void cleanup(void)
{
    static const char *const names[] = {
        "plain.obj", "forms.obj", "negative.OBJ", "crlf.obj", "mixed.obj", "mixed.mesh",
        "mixed.txt", "plain.off", "colour.off", "noff.dat", "ascii.ply", "le.ply", "be.PLY",
        "be.bin", "int.ply", "cr.ply", "ascii.stl", "binary.stl", "binary.dat", "round.obj", "tet.obj",
        "square.obj", "torus.obj", "unref.obj", "two.obj"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) unlink(path_of(names[i]));
    CHECK_MSG(rmdir(g_dir) == 0, "temp dir %s not empty (a temp file left behind?)", g_dir);
}

/* Ground-truth files: a round trip; a folder, a missing file and a short
 * file are refused with the path in the message (a folder was read as a
 * file of LONG_MAX bytes: "too short ... (9223372036854775807 bytes)"). */
static void test_gt_files(void)
{
    char dir[] = "/tmp/geosep-gt-XXXXXX", path[64];
    if (!mkdtemp(dir)) return;
    snprintf(path, sizeof path, "%s/a.gt", dir);
    uint32_t src[2] = {1, 2};
    double d[6] = {1, 0, 2, 3, 4, 0};
    gs_gt *gt = NULL;
    gs_error e = {0};
    CHECK(gs_gt_write(path, 3, 2, src, d, &e) == GS_OK);
    CHECK(gs_gt_read(path, &gt, &e) == GS_OK && gt && gt->n_vertices == 3 && gt->n_sources == 2 &&
          gt->sources[1] == 2 && memcmp(gt->dist, d, sizeof d) == 0);
    gs_gt_free(gt);
    gt = NULL;
    CHECK(gs_gt_read(dir, &gt, &e) == GS_EIO && !gt && strstr(e.message, "not a regular file") && strstr(e.message, dir));
    CHECK(truncate(path, 10) == 0);
    CHECK(gs_gt_read(path, &gt, &e) == GS_EPARSE && strstr(e.message, "too short for a GEOGT1 header (10 bytes)"));
    unlink(path);
    CHECK(gs_gt_read(path, &gt, &e) == GS_EIO && strstr(e.message, "cannot open"));
    rmdir(dir);
}

/* Meshes at the ends of the accepted scale (GS_MESH_MIN_EDGE .. MAX_EDGE):
 * a closed icosphere scaled so that its edges are near 1e47 and 1e-47 loads,
 * and its distances (exact and graph) are the unit mesh's times the scale. */
static void test_scale_limits(void)
{
    gs_mesh *unit = NULL;
    gs_error e = {0, ""};
    CHECK(gs_mesh_generate("sphere:1", &unit, &e) == GS_OK);
    if (!unit) return;
    uint32_t n = gs_mesh_num_vertices(unit), nf = gs_mesh_num_faces(unit);
    double *x = malloc(3 * sizeof *x * n), *d0 = malloc(sizeof *d0 * n), *d = malloc(sizeof *d * n);
    const double scales[2] = {1e48, 1e-46};
    for (int meth = 0; meth < 2; ++meth) {
        gs_patch *pt = NULL;
        gs_source s = gs_source_vertex(3);
        CHECK(gs_patch_create(unit, NULL, 0, &pt, &e) == GS_OK);
        CHECK(gs_distance_field(pt, meth ? GS_METHOD_GRAPH : GS_METHOD_EXACT, &s, 1, 0, d0, &e) == GS_OK);
        gs_patch_free(pt);
        for (int k = 0; k < 2; ++k) {
            for (uint32_t i = 0; i < 3 * n; ++i) x[i] = gs_mesh_positions(unit)[i] * scales[k];
            gs_mesh *m = NULL;
            int rc = gs_mesh_create(x, n, gs_mesh_faces(unit), nf, &m, &e);
            CHECK_MSG(rc == GS_OK, "scale %g: %s", scales[k], e.message);
            if (rc) continue;
            pt = NULL;
            CHECK(gs_patch_create(m, NULL, 0, &pt, &e) == GS_OK);
            rc = gs_distance_field(pt, meth ? GS_METHOD_GRAPH : GS_METHOD_EXACT, &s, 1, 0, d, &e);
            CHECK_MSG(rc == GS_OK, "scale %g: %s", scales[k], e.message);
            for (uint32_t i = 0; rc == GS_OK && i < n; ++i)
                CHECK_NEAR(d[i] / scales[k], d0[i], 1e-13);
            gs_patch_free(pt);
            gs_mesh_free(m);
        }
    }
    /* one step beyond either end: a clear error naming the limit */
    for (int k = 0; k < 2; ++k) {
        for (uint32_t i = 0; i < 3 * n; ++i) x[i] = gs_mesh_positions(unit)[i] * (k ? 1e-52 : 1e52);
        gs_mesh *m = NULL;
        CHECK(gs_mesh_create(x, n, gs_mesh_faces(unit), nf, &m, &e) == GS_EMESH && !m);
        CHECK_MSG(strstr(e.message, "outside geosep's range [1e-50, 1e+50] (rescale the mesh)"), "%s", e.message);
    }
    free(x);
    free(d0);
    free(d);
    gs_mesh_free(unit);
}

/* No faces: gs_mesh_create refuses them like gs_mesh_load (GS_EMESH). */
static void test_create_no_faces(void)
{
    const double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    gs_error e = {0, ""};
    for (uint32_t nv = 0; nv <= 3; nv += 3) {
        gs_mesh *m = (gs_mesh *)&e; /* must be reset to NULL */
        CHECK(gs_mesh_create(xyz, nv, NULL, 0, &m, &e) == GS_EMESH && m == NULL);
        CHECK_MSG(strstr(e.message, "no faces"), "%s", e.message);
    }
}

int main(void)
{
    test_gt_files();
    snprintf(g_dir, sizeof g_dir, "/tmp/geosep-io-XXXXXX");
    if (!mkdtemp(g_dir)) gs__test_skip("cannot create a temporary directory");
    test_obj();
    test_off();
    test_ply();
    test_stl();
    test_round_trip();
    test_reports();
    test_scale_limits();
    test_create_no_faces();
    test_shared();
    cleanup();
    return gs__test_finish("test_mesh_io");
}
