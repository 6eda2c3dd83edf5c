/* io_internal.h - shared pieces of the mesh file readers: whole-file reading
 * with size checks, a line cursor (\n, \r\n, \r), a tokenizer, strict number
 * parsing, and the growing triangle soup every reader fills. Internal only. */
#ifndef GS_IO_INTERNAL_H
#define GS_IO_INTERNAL_H

#include "mesh_internal.h"

#include <stddef.h>
#include <stdint.h>

/* Largest mesh file geosep reads into memory (16 GiB, or less on 32-bit). */
#define GS_IO_MAX_FILE ((uint64_t)1 << 34)

/* Read a regular file into memory; *data gets size + 1 bytes, the last one
 * '\0' (so text parsers can rely on a terminator). Caller frees *data.
 * GS_EIO (missing, directory, unreadable), GS_ELIMIT (too large). */
int gs__read_file(const char *path, char **data, size_t *size, gs_error *err);

/* Line cursor over a mutable, NUL-terminated buffer [p, end). Each call
 * returns the next line with its terminator replaced by '\0'. */
typedef struct gs__lines {
    char *p, *end;
    uint32_t line; /* 1-based number of the line last returned */
} gs__lines;

void gs__lines_init(gs__lines *c, char *data, size_t size);
/* 1 and *line set: a line; 0: end of data; -1: the line holds a NUL byte. */
int gs__lines_next(gs__lines *c, char **line);

/* Next whitespace-separated token of *s (terminated in place), or NULL. */
char *gs__tok(char **s);
/* Cut the line at the first '#' (comments of OBJ and OFF). */
void gs__strip_comment(char *line);
/* 1 if the string holds only blanks. */
int gs__blank(const char *s);

/* Strict number parsing: the whole token must be consumed. 0 ok, -1 not a
 * number. gs__parse_i64 stops at `stop` (e.g. '/') if it is not '\0'. */
int gs__parse_double(const char *tok, double *out);
int gs__parse_i64(const char *tok, char stop, int64_t *out);

/* A triangle soup being read: positions, triangles and, for every triangle,
 * the line (text) or element number (binary) it came from. */
typedef struct gs__soup {
    const char *file;
    const char *unit; /* "line", "face", "triangle" */
    double *xyz;
    uint32_t *tri, *face_line;
    uint32_t nv, nf;
    size_t cap_v, cap_f;
} gs__soup;

void gs__soup_init(gs__soup *s, const char *file, const char *unit);
void gs__soup_free(gs__soup *s);
/* Make room for nv more vertices and nf more triangles (counts already
 * checked against the file size). GS_ENOMEM / GS_ELIMIT with a message. */
int gs__soup_reserve(gs__soup *s, uint64_t nv, uint64_t nf, gs_error *err);
int gs__soup_add_vertex(gs__soup *s, double x, double y, double z, gs_error *err);
int gs__soup_add_tri(gs__soup *s, uint32_t a, uint32_t b, uint32_t c, uint32_t where,
                     gs_error *err);

/* Fan-triangulates a polygon streamed one corner at a time. */
typedef struct gs__fan {
    uint32_t first, prev, n;
} gs__fan;

static inline void gs__fan_start(gs__fan *f) { f->n = 0; }
/* Add the next corner; emits a triangle from the third corner on. */
int gs__fan_add(gs__fan *f, gs__soup *s, uint32_t v, uint32_t where, gs_error *err);

/* The readers. `data` holds `size` bytes plus a '\0' and may be modified.
 * They fill `s`; the caller checks for "no faces" and builds the mesh. */
int gs__read_obj(const char *file, char *data, size_t size, gs__soup *s, gs_error *err);
int gs__read_off(const char *file, char *data, size_t size, gs__soup *s, gs_error *err);
int gs__read_ply(const char *file, char *data, size_t size, gs__soup *s, gs_error *err);
int gs__read_stl(const char *file, char *data, size_t size, gs__soup *s, gs_error *err);

/* Read a mesh file into a triangle soup without any topological check
 * (gs_mesh_load's reading: format by argument, extension, then content;
 * the readers' parse-level checks hold: indices in range, finite
 * coordinates). A file without faces is an error as for gs_mesh_load. On
 * failure *s is left empty; on success the caller frees it. */
int gs__load_soup(const char *path, gs_mesh_format format, gs__soup *s, gs_error *err);

/* The same from size bytes in memory (copied; `name` stands for the file
 * in messages and picks the format by its extension under GS_FORMAT_AUTO). */
int gs__load_soup_memory(const char *name, const void *data, size_t size, gs_mesh_format format,
                         gs__soup *s, gs_error *err);

/* gs_mesh_load from size bytes in memory (the fuzz targets' entry). */
int gs__mesh_load_memory(const char *name, const void *data, size_t size, gs_mesh_format format,
                         gs_mesh **out, gs_error *err);

/* gs_mesh_repair_file from size bytes in memory (the fuzz targets' entry). */
int gs__mesh_repair_memory(const char *name, const void *data, size_t size, gs_mesh_format format,
                           gs_mesh **out, gs_repair **info, gs_error *err);

/* 1 if (size, data) has the exact size of a binary STL (84 + 50 n bytes). */
int gs__stl_is_binary(const char *data, size_t size);

#endif
