/* make_seeds.c - the fuzz targets' seed corpora, from generated meshes:
 * make_seeds DIR writes DIR/<target>/<name> for every target of fuzz/:
 * each mesh (valid ones and flawed soups) in every variant of its format
 * (OBJ with polygons and v/vt/vn indices, OFF, PLY ascii and binary of
 * both byte orders, STL ascii and binary), encoded soups for fuzz_repair,
 * small databases (connected, two components, leaf tables, sampled
 * functions) and query text for the CLI parsers. Run by tools/fuzz.sh. */
#include "geosep.h"

#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *g_dir;

static void die(const char *what, const char *detail)
{
    fprintf(stderr, "make_seeds: %s: %s\n", what, detail);
    exit(1);
}

static FILE *open_seed(const char *target, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", g_dir, target);
    if (mkdir(path, 0777) && errno != EEXIST) die(path, strerror(errno));
    snprintf(path, sizeof path, "%s/%s/%s", g_dir, target, name);
    FILE *f = fopen(path, "wb");
    if (!f) die(path, strerror(errno));
    return f;
}

static void close_seed(FILE *f)
{
    if (fclose(f)) die("write", strerror(errno));
}

static void text_seed(const char *target, const char *name, const char *text)
{
    FILE *f = open_seed(target, name);
    fputs(text, f);
    close_seed(f);
}

/* ---- meshes ------------------------------------------------------------------ */

typedef struct soup {
    const char *name;
    uint32_t nv, nf;
    const double *xyz;
    const uint32_t *tri;
} soup;

static void put_u32(FILE *f, uint32_t v, int be)
{
    unsigned char b[4];
    for (int i = 0; i < 4; ++i) b[be ? 3 - i : i] = (unsigned char)(v >> (8 * i));
    fwrite(b, 1, 4, f);
}

static void put_f32(FILE *f, float x, int be)
{
    uint32_t v;
    memcpy(&v, &x, 4);
    put_u32(f, v, be);
}

static void put_f64(FILE *f, double x, int be)
{
    uint64_t v;
    memcpy(&v, &x, 8);
    put_u32(f, (uint32_t)(be ? v >> 32 : v), be);
    put_u32(f, (uint32_t)(be ? v : v >> 32), be);
}

static void write_obj(const soup *s, int variant)
{
    char name[128];
    snprintf(name, sizeof name, "%s-%d.obj", s->name, variant);
    FILE *f = open_seed("fuzz_obj", name);
    fprintf(f, "# %s\no %s\n", s->name, s->name);
    for (uint32_t v = 0; v < s->nv; ++v)
        fprintf(f, "v %.17g %.17g %.17g\n", s->xyz[3 * v], s->xyz[3 * v + 1], s->xyz[3 * v + 2]);
    if (variant == 1) fputs("vt 0 0\nvn 0 0 1\n", f);
    for (uint32_t t = 0; t < s->nf; ++t) {
        const uint32_t *c = s->tri + 3 * t;
        if (variant == 0)
            fprintf(f, "f %u %u %u\n", c[0] + 1, c[1] + 1, c[2] + 1);
        else if (variant == 1)
            fprintf(f, "f %u/1/1 %u//1 %u/1\n", c[0] + 1, c[1] + 1, c[2] + 1);
        else /* negative (relative) indices */
            fprintf(f, "f %d %d %d\n", (int)c[0] - (int)s->nv, (int)c[1] - (int)s->nv, (int)c[2] - (int)s->nv);
    }
    if (variant == 0) fputs("f 1 2 3 4\n", f); /* a polygon (fanned) */
    close_seed(f);
}

static void write_off(const soup *s)
{
    char name[128];
    snprintf(name, sizeof name, "%s.off", s->name);
    FILE *f = open_seed("fuzz_off", name);
    fprintf(f, "OFF\n# %s\n%u %u 0\n", s->name, s->nv, s->nf);
    for (uint32_t v = 0; v < s->nv; ++v)
        fprintf(f, "%.17g %.17g %.17g\n", s->xyz[3 * v], s->xyz[3 * v + 1], s->xyz[3 * v + 2]);
    for (uint32_t t = 0; t < s->nf; ++t)
        fprintf(f, "3 %u %u %u\n", s->tri[3 * t], s->tri[3 * t + 1], s->tri[3 * t + 2]);
    close_seed(f);
}

static void write_ply(const soup *s, int fmt) /* 0 ascii, 1 little, 2 big endian */
{
    static const char *const fmts[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    char name[128];
    snprintf(name, sizeof name, "%s-%s.ply", s->name, fmts[fmt]);
    FILE *f = open_seed("fuzz_ply", name);
    fprintf(f, "ply\nformat %s 1.0\ncomment %s\nelement vertex %u\n", fmts[fmt], s->name, s->nv);
    fprintf(f, "property %s x\nproperty %s y\nproperty %s z\n", fmt == 2 ? "double" : "float",
            fmt == 2 ? "double" : "float", fmt == 2 ? "double" : "float");
    fprintf(f, "element face %u\nproperty list uchar %s vertex_indices\nend_header\n", s->nf,
            fmt == 1 ? "uint" : "int");
    int be = fmt == 2;
    for (uint32_t v = 0; v < s->nv; ++v)
        for (int k = 0; k < 3; ++k) {
            double x = s->xyz[3 * v + k];
            if (fmt == 0) fprintf(f, "%.9g%c", x, k == 2 ? '\n' : ' ');
            else if (fmt == 1) put_f32(f, (float)x, 0);
            else put_f64(f, x, be);
        }
    for (uint32_t t = 0; t < s->nf; ++t) {
        if (fmt == 0) {
            fprintf(f, "3 %u %u %u\n", s->tri[3 * t], s->tri[3 * t + 1], s->tri[3 * t + 2]);
            continue;
        }
        fputc(3, f);
        for (int k = 0; k < 3; ++k) put_u32(f, s->tri[3 * t + k], be);
    }
    close_seed(f);
}

static void write_stl(const soup *s, int binary)
{
    char name[128];
    snprintf(name, sizeof name, "%s-%s.stl", s->name, binary ? "binary" : "ascii");
    FILE *f = open_seed("fuzz_stl", name);
    if (binary) {
        char header[80] = "geosep fuzz seed";
        fwrite(header, 1, 80, f);
        put_u32(f, s->nf, 0);
    } else
        fprintf(f, "solid %s\n", s->name);
    for (uint32_t t = 0; t < s->nf; ++t) {
        if (binary) {
            for (int k = 0; k < 3; ++k) put_f32(f, 0.0f, 0);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) put_f32(f, (float)s->xyz[3 * s->tri[3 * t + c] + k], 0);
            fputc(0, f), fputc(0, f);
            continue;
        }
        fputs("  facet normal 0 0 1\n    outer loop\n", f);
        for (int c = 0; c < 3; ++c) {
            const double *p = s->xyz + 3 * s->tri[3 * t + c];
            fprintf(f, "      vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
        }
        fputs("    endloop\n  endfacet\n", f);
    }
    if (!binary) fprintf(f, "endsolid %s\n", s->name);
    close_seed(f);
}

/* fuzz_repair's encoding: table coordinates where they are in the table,
 * else raw doubles. */
static void write_repair(const soup *s)
{
    static const double table[16] = {0.0, 1.0, 2.0, 0.5, -1.0, 3.0, 1e-7, 1.0 + 1e-12,
                                     0.25, 4.0, -0.5, 1e-3, 10.0, 0.75, 1.5, 2.5};
    if (s->nv < 3 || s->nv > 63) return;
    int raw = 0;
    for (uint32_t i = 0; i < 3 * s->nv && !raw; ++i) {
        int found = 0;
        for (int k = 0; k < 16; ++k) found |= table[k] == s->xyz[i];
        raw = !found;
    }
    char name[128];
    snprintf(name, sizeof name, "%s.soup", s->name);
    FILE *f = open_seed("fuzz_repair", name);
    fputc((int)(s->nv - 3), f);
    fputc(raw, f);
    for (uint32_t i = 0; i < 3 * s->nv; ++i) {
        if (raw) {
            fwrite(&s->xyz[i], 8, 1, f); /* the target reads host order */
            continue;
        }
        for (int k = 0; k < 16; ++k)
            if (table[k] == s->xyz[i]) {
                fputc(k, f);
                break;
            }
    }
    for (uint32_t t = 0; t < s->nf && t < 400; ++t)
        for (int k = 0; k < 3; ++k) fputc((int)s->tri[3 * t + k], f);
    close_seed(f);
}

static void write_all(const soup *s)
{
    for (int v = 0; v < 3; ++v) write_obj(s, v);
    write_off(s);
    for (int fmt = 0; fmt < 3; ++fmt) write_ply(s, fmt);
    write_stl(s, 0);
    write_stl(s, 1);
    write_repair(s);
}

static void generated(const char *spec, const char *name)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    if (gs_mesh_generate(spec, &m, &err)) die(spec, err.message);
    soup s = {name, gs_mesh_num_vertices(m), gs_mesh_num_faces(m), gs_mesh_positions(m), gs_mesh_faces(m)};
    write_all(&s);
    gs_mesh_free(m);
}

/* Soups with the flaws repair handles, on a 3 x 3 grid of unit squares. */
static const double grid_xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 0, 2, 0, 1, 2, 0, 2, 2, 0,
                                  /* 9, 10: copies of 4 and 5 (an unwelded seam), 11 above 4 */
                                  1, 1, 0, 2, 1, 0, 1, 1, 1};
static const uint32_t bowtie[] = {0, 1, 4, 4, 5, 8};                      /* pinched vertex 4 */
static const uint32_t dup_face[] = {0, 1, 4, 0, 4, 3, 0, 1, 4, 4, 1, 0};  /* duplicates */
static const uint32_t fin[] = {0, 1, 4, 0, 4, 3, 0, 4, 11};               /* 3 faces on edge 0-4 */
static const uint32_t flipped[] = {0, 1, 4, 0, 3, 4, 1, 2, 5, 1, 5, 4};   /* one face reversed */
static const uint32_t zero_area[] = {0, 1, 2, 0, 2, 4, 3, 4, 7, 3, 7, 6}; /* 0 1 2 collinear */
static const uint32_t seam[] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 9, 7, 3, 7, 6, 9, 10, 8, 9, 8, 7};
static const uint32_t repeat[] = {0, 0, 1, 0, 1, 4, 1, 1, 1};             /* repeated corners */

static void soups(void)
{
    const soup s[] = {
        {"bowtie", 12, 2, grid_xyz, bowtie},       {"duplicate", 12, 4, grid_xyz, dup_face},
        {"fin", 12, 3, grid_xyz, fin},             {"flipped", 12, 4, grid_xyz, flipped},
        {"zero-area", 12, 4, grid_xyz, zero_area}, {"seam", 12, 8, grid_xyz, seam},
        {"repeat", 12, 3, grid_xyz, repeat},
    };
    for (size_t i = 0; i < sizeof s / sizeof *s; ++i) write_all(&s[i]);
}

/* ---- databases ---------------------------------------------------------------- */

static void database(const char *spec, const char *name, int leaf_exact, int sampled)
{
    gs_mesh *m = NULL;
    gs_db *db = NULL;
    gs_error err = {0};
    if (gs_mesh_generate(spec, &m, &err)) die(spec, err.message);
    gs_build_options o;
    gs_build_options_default(&o);
    o.threads = 1;
    o.vmax = 8;
    o.leaf_exact = leaf_exact;
    o.sampled = sampled;
    if (gs_db_build(m, &o, &db, NULL, &err)) die(spec, err.message);
    char path[1024];
    snprintf(path, sizeof path, "%s/fuzz_db", g_dir);
    if (mkdir(path, 0777) && errno != EEXIST) die(path, strerror(errno));
    snprintf(path, sizeof path, "%s/fuzz_db/%s.db", g_dir, name);
    if (gs_db_save(db, path, &err)) die(path, err.message);
    gs_db_free(db);
    gs_mesh_free(m);
}

/* A flawed soup repaired, its database storing the input ids (the alias
 * section) and leaf tables. */
static void repaired_database(const soup *s)
{
    gs_mesh *m = NULL;
    gs_repair *r = NULL;
    gs_db *db = NULL;
    gs_error err = {0};
    if (gs_mesh_repair(s->xyz, s->nv, s->tri, s->nf, &m, &r, &err)) die(s->name, err.message);
    gs_build_options o;
    gs_build_options_default(&o);
    o.threads = 1;
    o.vmax = 8;
    o.repair = r;
    if (gs_db_build(m, &o, &db, NULL, &err)) die(s->name, err.message);
    char path[1024];
    snprintf(path, sizeof path, "%s/fuzz_db/%s-repaired.db", g_dir, s->name);
    if (gs_db_save(db, path, &err)) die(path, err.message);
    gs_db_free(db);
    gs_repair_free(r);
    gs_mesh_free(m);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fputs("usage: make_seeds DIR\n", stderr);
        return 2;
    }
    g_dir = argv[1];
    if (mkdir(g_dir, 0777) && errno != EEXIST) die(g_dir, strerror(errno));
    generated("grid:3,3", "grid");
    generated("sphere:0", "icosahedron");
    generated("cube:1", "cube");
    generated("two:2", "two");
    generated("torus:4,3", "torus");
    soups();
    /* a few malformed-but-close texts the grammar-less mutations rarely find */
    text_seed("fuzz_obj", "polygon-texture.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1\n");
    text_seed("fuzz_off", "header-comments.off", "OFF # c\n\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    text_seed("fuzz_ply", "extra-props.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nelement face 1\nproperty list uchar int vertex_index\nproperty int flags\n"
              "element edge 0\nproperty int a\nend_header\n0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 2 7\n");

    database("grid:5,5", "grid", 0, 0);
    database("two:4", "two-components", 0, 0);
    database("sphere:1", "sphere-leaf-exact", 1, 0);
    database("grid:6,4", "grid-sampled", 0, 1);
    repaired_database(&(soup){"bowtie", 12, 2, grid_xyz, bowtie});
    repaired_database(&(soup){"seam", 12, 8, grid_xyz, seam});
    database("knot:40,8", "knot-near-pairs", 1, 0); /* 42 near pairs: section 'near_pairs' with entries */

    /* mode byte (see fuzz_cli_input.c), then the text */
    FILE *f = open_seed("fuzz_cli_input", "pairs");
    fputc(0, f);
    fputs("0 1\n2 15\n\n  3\t4  \n15 15\n", f);
    close_seed(f);
    f = open_seed("fuzz_cli_input", "points");
    fputc(1, f);
    fputs("0 1 5 0.5 0.25 0.25  15 14 10 1 0 0\n3 3 3 1 0 0 4 5 6 0.2 0.3 0.5\n", f);
    close_seed(f);
    f = open_seed("fuzz_cli_input", "points-mesh");
    fputc(2, f);
    fputs("0 0.2 0.3 0.5  17 1 0 0\n4 1e-3 0.999 0\t3 0.25 0.25 0.5\n", f);
    close_seed(f);
    f = open_seed("fuzz_cli_input", "field-point");
    fputc(3, f);
    fputs("0,1,5:0.5,0.25,0.25", f);
    close_seed(f);
    f = open_seed("fuzz_cli_input", "field-source-point");
    fputc(4, f);
    fputs("7:0.2,0.3,0.5", f);
    close_seed(f);
    f = open_seed("fuzz_cli_input", "solve-source-point");
    fputc(5, f);
    fputs("3:1,0,0", f);
    close_seed(f);
    return 0;
}
