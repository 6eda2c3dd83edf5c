/* render_internal.h - the renderer's pieces (src/render): the separator
 * segments taken from a database's tree, and the PNG writer. Internal. */
#ifndef GS_RENDER_INTERNAL_H
#define GS_RENDER_INTERNAL_H

#include "../core/internal.h"

/* A straight piece of a separator curve inside one face, in mesh
 * coordinates, and the depth of the tree node whose separator it is. */
typedef struct gs__rseg {
    double p[2][3];
    uint64_t key[2]; /* what each end is: an edge's midpoint or a face's centroid */
    uint32_t node, depth;
    uint32_t order; /* position in the face order (ties of the sort) */
} gs__rseg;

/* The separator segments of db over mesh (db validated as the mesh's by the
 * caller): for every face whose corners lie in different leaves, where the
 * separator of each node that splits them crosses it, chained into curves
 * and smoothed (the midpoints zigzag along the mesh's edges). Sorted deepest
 * first (so that shallower curves are drawn over deeper ones). *out is
 * malloc'ed (caller frees; NULL when *n is 0). */
int gs__render_separators(const gs_mesh *mesh, const gs_db *db, gs__rseg **out, size_t *n, gs_error *err);

/* Write w x h RGB pixels (rows top to bottom) as a PNG file, atomically. */
int gs__png_write(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, gs_error *err);

#endif
