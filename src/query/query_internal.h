/* query_internal.h - a query source: one vertex x whose separator distance
 * functions are decoded and tabulated on their curves' grids once, then
 * kept for many targets (fields, neighbourhoods, the nearest among
 * candidates, radius matrices: src/query/field.c, within.c). Its answers
 * equal gs_db_distance(db, x, y) bit for bit: the same candidates in the
 * same order, the same pair minimiser on the same values (query.c).
 * Internal. */
#ifndef GS_QUERY_INTERNAL_H
#define GS_QUERY_INTERNAL_H

#include "../db/db_internal.h"

#include <stdint.h>

typedef struct gs__qsrc gs__qsrc;

/* A source for x < n_vertices (any leaf, GS_NONE too); NULL when out of
 * memory (about 1 KB per separator function of x). Free with
 * gs__qsrc_free. One thread at a time per source (its cache fills as
 * targets are answered); the database is only read. */
gs__qsrc *gs__qsrc_create(const gs_db *db, uint32_t x);
void gs__qsrc_free(gs__qsrc *s);

/* gs_db_distance(db, x, y), bit for bit (NaN for y >= n_vertices). */
double gs__qsrc_distance(gs__qsrc *s, uint32_t y);

/* The same for y in leaf ly != x's leaf (neither GS_NONE), y != x, when
 * the caller knows top, the lowest common ancestor of the two leaves. */
double gs__qsrc_cross(gs__qsrc *s, uint32_t y, uint32_t ly, uint32_t top);

/* gs__qsrc_cross, but the candidate curves whose quick-reject bound (the
 * sum of the two stored minima) exceeds cut are not visited: the answer is
 * exact whenever it is at most every such bound, else some value above the
 * smallest answer those curves could give. For a neighbourhood of radius
 * r, a cut above which every curve's answer exceeds r keeps every answer
 * <= r exact and every other one > r. */
double gs__qsrc_cross_cut(gs__qsrc *s, uint32_t y, uint32_t ly, uint32_t top, double cut);

/* x's leaf (GS_NONE: used by no face). */
uint32_t gs__qsrc_leaf(const gs__qsrc *s);

/* x's stored minima, one per function (curve_prefix(x's leaf) floats,
 * borrowed from the database); NULL when x's leaf is GS_NONE. */
const float *gs__qsrc_minima(const gs__qsrc *s);

/* The lowest common ancestor of x's leaf and `node` (x's leaf not
 * GS_NONE). */
uint32_t gs__qsrc_ancestor(const gs__qsrc *s, uint32_t node);

/* One row of a radius matrix (within.c, for radius.c): the vertices within
 * r of x (r >= 0 checked by the caller) by increasing id, and their
 * distances. *ids, *dist: new arrays (caller frees; NULL when *n = 0). */
int gs__db_within_row(const gs_db *db, uint32_t x, double r, uint32_t **ids, double **dist, size_t *n,
                      gs_error *err);

#endif
