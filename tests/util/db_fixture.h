/* db_fixture.h - a hand-made database (tree, curves, quadratic distance
 * functions, leaf tables) packed through the writer, shared by test_db.c and
 * test_query.c. */
#ifndef GEOSEP_TESTS_DB_FIXTURE_H
#define GEOSEP_TESTS_DB_FIXTURE_H

#include "db/db_internal.h"

/* ---- fixture ---------------------------------------------------------------
 * Tree: node 0 (root; curve 0, a path) -> node 1 (leaf: vertices 0,1) and
 * node 2 (curves 1 = loop, 2 = path) -> leaves 3 (vertices 2,3) and 4
 * (vertices 4,5). Vertex 6 is used by no face. Every function is a
 * quadratic a + b (t - t0)^2 in Chebyshev form (so its minimum is a), one is
 * fitted to d^2, and vertex 5 cannot reach curves 0 and 2. */
#define FX_NV 7
#define FX_NF 64

typedef struct fixture {
    double xyz[3 * FX_NV];
    gs__db_node nodes[5];
    gs__db_curve curves[3];
    uint32_t leaf[FX_NV];
    uint64_t fun_start[FX_NV + 1];
    gs__fun funs[FX_NF];
    double coef[FX_NF][3];
    double qa[FX_NF], qb[FX_NF], qt[FX_NF]; /* the quadratics, for references */
    uint32_t leaf_vstart[6], leaf_verts[6];
    uint64_t leaf_dstart[6];
    double leaf_dist[12];
    uint32_t alias_start[6], alias[7];
    gs__db_content c;
} fixture;

/* Fill *f (leaf tables when leaf_exact). */
void make_fixture(fixture *f, int leaf_exact);
/* Input-id aliases as a repair would make them: 5 input vertices; 0 and 3
 * are themselves, 1 became {1, 5} and 2 {2, 6} (split), 4 was welded into
 * 2. */
void fixture_add_aliases(fixture *f);
/* make_fixture with leaf tables and aliases, packed (every section). */
gs_db *fixture_db_full(fixture *f);
/* make_fixture, then pack it: a new database (caller frees), NULL on failure
 * (a failed CHECK). */
gs_db *fixture_db(fixture *f, int leaf_exact);

#endif
