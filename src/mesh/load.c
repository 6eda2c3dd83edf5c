/* load.c - gs_mesh_load: read the file, pick the reader (explicit format,
 * else extension, else content sniffing), then validate and build the mesh
 * with every triangle's line or element number for error messages. */
#include "io_internal.h"

#include <stdlib.h>
#include <string.h>

static int lower(int ch) { return (ch >= 'A' && ch <= 'Z') ? ch - 'A' + 'a' : ch; }

static int ends_with_ci(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    if (k > n) return 0;
    for (size_t i = 0; i < k; ++i)
        if (lower((unsigned char)s[n - k + i]) != suffix[i]) return 0;
    return 1;
}

static gs_mesh_format by_extension(const char *path)
{
    if (ends_with_ci(path, ".obj")) return GS_FORMAT_OBJ;
    if (ends_with_ci(path, ".off")) return GS_FORMAT_OFF;
    if (ends_with_ci(path, ".ply")) return GS_FORMAT_PLY;
    if (ends_with_ci(path, ".stl")) return GS_FORMAT_STL;
    return GS_FORMAT_AUTO;
}

/* 1 if data starts with word (after blanks) followed by a blank or end. */
static int starts_with_word(const char *data, size_t size, const char *word, int ci)
{
    size_t i = 0, k = strlen(word);
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\n' ||
                        data[i] == '\r'))
        ++i;
    if (size - i < k) return 0;
    for (size_t j = 0; j < k; ++j) {
        int a = (unsigned char)data[i + j];
        if ((ci ? lower(a) : a) != word[j]) return 0;
    }
    return i + k == size || (data[i + k] && strchr(" \t\r\n", data[i + k]) != NULL);
}

static int sniff_off(const char *data, size_t size)
{
    static const char *const heads[] = {"OFF", "COFF", "NOFF", "CNOFF", "STOFF",
                                        "STCOFF", "STNOFF", "STCNOFF"};
    for (size_t i = 0; i < sizeof heads / sizeof *heads; ++i)
        if (starts_with_word(data, size, heads[i], 0)) return 1;
    return 0;
}

/* OBJ: the first statement (after comments/blank lines) is a known keyword. */
static int sniff_obj(const char *data, size_t size)
{
    static const char *const kws[] = {"v", "vt", "vn", "vp", "f", "o", "g", "s",
                                      "usemtl", "mtllib", "l", "p"};
    size_t i = 0;
    for (;;) {
        while (i < size && data[i] && strchr(" \t\r\n", data[i])) ++i;
        if (i < size && data[i] == '#') {
            while (i < size && data[i] != '\n' && data[i] != '\r') ++i;
            continue;
        }
        break;
    }
    for (size_t k = 0; k < sizeof kws / sizeof *kws; ++k)
        if (starts_with_word(data + i, size - i, kws[k], 0)) return 1;
    return 0;
}

static gs_mesh_format sniff(const char *data, size_t size)
{
    if (size >= 4 && memcmp(data, "ply", 3) == 0 && (data[3] == '\n' || data[3] == '\r'))
        return GS_FORMAT_PLY;
    if (sniff_off(data, size)) return GS_FORMAT_OFF;
    if (gs__stl_is_binary(data, size) || starts_with_word(data, size, "solid", 1))
        return GS_FORMAT_STL;
    if (sniff_obj(data, size)) return GS_FORMAT_OBJ;
    return GS_FORMAT_AUTO;
}

static int run_reader(gs_mesh_format f, const char *path, char *data, size_t size,
                      gs__soup *s, gs_error *err)
{
    switch (f) {
    case GS_FORMAT_OBJ: return gs__read_obj(path, data, size, s, err);
    case GS_FORMAT_OFF: return gs__read_off(path, data, size, s, err);
    case GS_FORMAT_PLY: return gs__read_ply(path, data, size, s, err);
    case GS_FORMAT_STL: return gs__read_stl(path, data, size, s, err);
    default: break;
    }
    return gs__fail(err, GS_EFORMAT,
                    "%s: unknown mesh format (extension not .obj/.off/.ply/.stl and the "
                    "content is not recognised)", path);
}

static int build(gs__soup *s, gs_mesh **out, gs_error *err)
{
    uint32_t *lines = s->face_line;
    s->face_line = NULL;
    gs__origin origin = {s->file, lines, s->unit};
    int rc = gs__mesh_adopt(s->xyz, s->nv, s->tri, s->nf, &origin, out, err);
    s->xyz = NULL; /* adopted (or freed) by gs__mesh_adopt */
    s->tri = NULL;
    free(lines);
    return rc;
}

/* The reading after the bytes are in memory: data holds size bytes and a
 * '\0' after them (the readers may modify it); frees data. */
static int load_soup_data(const char *path, gs_mesh_format format, char *data, size_t size,
                          gs__soup *s, gs_error *err)
{
    if (size == 0) {
        free(data);
        return gs__fail(err, GS_EPARSE, "%s: empty file", path);
    }
    if (format == GS_FORMAT_AUTO) format = by_extension(path);
    if (format == GS_FORMAT_AUTO) format = sniff(data, size);
    int rc = run_reader(format, path, data, size, s, err);
    free(data);
    if (rc == GS_OK && s->nf == 0 && s->nv == 0)
        rc = gs__fail(err, GS_EPARSE, "%s: no vertices and no faces in the file", path);
    else if (rc == GS_OK && s->nf == 0)
        rc = gs__fail(err, GS_EMESH, "%s: no faces (the file has %u vertices)", path, s->nv);
    if (rc) gs__soup_free(s);
    return rc;
}

int gs__load_soup(const char *path, gs_mesh_format format, gs__soup *s, gs_error *err)
{
    gs__soup_init(s, path, NULL);
    if ((int)format < GS_FORMAT_AUTO || format > GS_FORMAT_STL)
        return gs__fail(err, GS_EARG, "unknown mesh format %d", (int)format);
    char *data;
    size_t size;
    int rc = gs__read_file(path, &data, &size, err);
    if (rc) return rc;
    return load_soup_data(path, format, data, size, s, err);
}

int gs__load_soup_memory(const char *name, const void *bytes, size_t size, gs_mesh_format format,
                         gs__soup *s, gs_error *err)
{
    gs__soup_init(s, name, NULL);
    if ((int)format < GS_FORMAT_AUTO || format > GS_FORMAT_STL)
        return gs__fail(err, GS_EARG, "unknown mesh format %d", (int)format);
    if (size > GS_IO_MAX_FILE || size > SIZE_MAX - 1)
        return gs__fail(err, GS_ELIMIT, "%s: too large (%zu bytes)", name, size);
    char *data = gs__malloc(size + 1, 1);
    if (!data) return gs__fail(err, GS_ENOMEM, "%s: out of memory reading %zu bytes", name, size);
    if (size) memcpy(data, bytes, size);
    data[size] = '\0';
    return load_soup_data(name, format, data, size, s, err);
}

int gs__mesh_load_memory(const char *name, const void *data, size_t size, gs_mesh_format format,
                         gs_mesh **out, gs_error *err)
{
    *out = NULL;
    gs__soup s;
    int rc = gs__load_soup_memory(name, data, size, format, &s, err);
    if (rc == GS_OK) rc = build(&s, out, err);
    gs__soup_free(&s);
    return rc;
}

int gs_mesh_load(const char *path, gs_mesh_format format, gs_mesh **out, gs_error *err)
{
    if (!out) return gs__fail(err, GS_EARG, "gs_mesh_load: out is NULL");
    *out = NULL;
    if (!path) return gs__fail(err, GS_EARG, "gs_mesh_load: path is NULL");
    if ((int)format < GS_FORMAT_AUTO || format > GS_FORMAT_STL)
        return gs__fail(err, GS_EARG, "gs_mesh_load: unknown format %d", (int)format);
    gs__soup s;
    int rc = gs__load_soup(path, format, &s, err);
    if (rc == GS_OK) rc = build(&s, out, err);
    gs__soup_free(&s);
    return rc;
}
