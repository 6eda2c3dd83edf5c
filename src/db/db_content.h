/* db_content.h - what the builder hands to the database writer: the tree's
 * shape, the curves, every vertex's separator distance functions (paper sec.
 * 3.1: leaf index, curves J_x, function parameters), positions for same-leaf
 * queries and the build parameters. The writer packs it into the on-disk
 * layout (doc/database-format.md), which is also the in-memory layout that
 * queries read. Internal. */
#ifndef GS_DB_CONTENT_H
#define GS_DB_CONTENT_H

#include "../fit/fun.h"
#include "db_near.h"
#include "format.h"

typedef struct gs__db_curve {
    uint32_t node;
    uint32_t closed;
    uint32_t n_samples;
    double length;
} gs__db_curve;

typedef struct gs__db_content {
    uint32_t nv;
    const double *xyz;          /* 3*nv                                      */
    uint32_t n_nodes;
    const gs__db_node *nodes;
    uint32_t n_curves;
    const gs__db_curve *curves;
    const uint32_t *leaf;       /* nv: leaf node of each vertex, GS_NONE if  */
                                /*   unreferenced                            */
    /* Vertex x has nodes[leaf[x]].curve_prefix functions, one per curve of
     * its leaf's proper ancestors, root's curves first (so the function of
     * curve j of ancestor A is number nodes[A].curve_prefix + j - A's first
     * curve... i.e. index nodes[A].curve_prefix + (j - nodes[A].curve_start)).
     * funs[fun_start[x] + i]; fun.coef arrays are owned by the builder. */
    const uint64_t *fun_start;  /* nv+1                                      */
    const gs__fun *funs;
    /* Optional exact distances inside each leaf (leaf_exact option), else
     * NULL: leaf_verts lists each leaf's vertices (ranges leaf_vstart[l]..)
     * and leaf_dist the row-major table of each leaf, at leaf_dstart[l]. */
    const uint32_t *leaf_vstart;  /* n_nodes+1 (empty for internal nodes)    */
    const uint32_t *leaf_verts;
    const uint64_t *leaf_dstart;  /* n_nodes+1                               */
    const double *leaf_dist;
    /* Optional input-id aliases (a repaired mesh), else n_input = 0: input
     * vertex v became the vertices alias[alias_start[v] .. alias_start[v+1])
     * (gs_repair's CSR: each list non-empty, every alias < nv). The writer
     * stores the lists that are not exactly {v}. */
    uint32_t n_input;             /* <= nv                                   */
    const uint32_t *alias_start;  /* n_input + 1                             */
    const uint32_t *alias;
    /* Optional exact distances of near pairs (section 'near_pairs'):
     * near_radius > 0 writes the section with near_pairs[0..n_near),
     * sorted by x then y (db_near.h); 0: no section. */
    double near_radius;
    const gs__near_pair *near_pairs;
    uint64_t n_near;
    /* build parameters, recorded in the file */
    uint32_t method;              /* gs_method                               */
    uint32_t vmax, mmax;
    double tol;
    uint32_t vertex_sources, sampled;
    double sample_spacing;        /* / mean edge length                      */
    uint32_t seed;                /* partitioning seed                       */
    uint32_t max_samples;         /* cap on samples per curve (0: none)      */
    double heat_time, fmm_exact_start; /* gs_solver_options                  */
    double dgg_eps;               /* gs_solver_options; 0 unless method dgg  */
    uint32_t heat_refine;         /* gs_solver_options, 0..3                 */
    double avg_depth;
    uint32_t max_depth, n_leaves;
} gs__db_content;

#endif
