/* pipeline.h - what the stages of gs_db_build share (paper sec. 3.1, 4.1,
 * 4.2): the builder's state, progress, and the per-node and leaf stages.
 * build.c runs the pipeline (tree -> nodes -> leaf tables -> database);
 * node.c computes one node's distance fields and fits its functions;
 * leaves.c the exact same-leaf tables. Internal. */
#ifndef GS_PIPELINE_H
#define GS_PIPELINE_H

#include "../fit/fun.h"
#include "../mesh/mesh_internal.h"
#include "../partition/tree.h"

/* Per-vertex function slots: vertex x owns funs[fun_start[x] ..) and each
 * function's coefficients live in a per-node arena. */
typedef struct gs__builder {
    const gs_mesh *mesh;
    const double *xyz_out;  /* the positions the database stores (the      */
                            /*   caller's: mesh may be a centred copy)      */
    const gs_build_options *opt;
    const gs_tree *tree;
    uint32_t nthreads;
    uint64_t *fun_start;   /* nv+1 */
    gs_fun *funs;
    double **arenas;       /* one coefficient arena per node (or NULL)     */
    /* progress */
    double work_total, work_done;
    /* stats */
    uint64_t n_fields, n_functions, n_mixed, n_over_tol, n_uncertified;
    double max_fit_error;
    double degree_sum, fit_err_sum;
} gs__builder;

/* Report progress of a stage (no-op without a callback). */
void gs__pipe_progress(gs__builder *b, const char *stage, double frac);

/* Nodes with fewer owned vertices are processed in parallel, one thread
 * each; larger ones one at a time with all threads. */
enum { GS_PIPE_SMALL_NODE = 4096 };

/* Fields, fits and compaction of tree node i with nthreads threads; adds
 * the seconds spent to *t_fields and *t_fits (node.c). */
int gs__pipe_process_node(gs__builder *b, uint32_t i, uint32_t nthreads, double *t_fields, double *t_fits,
                          gs_error *err);

/* Exact distances between the vertices of each leaf (leaves.c). */
typedef struct gs__leaf_tables {
    uint32_t *vstart;  /* n_nodes+1 */
    uint32_t *verts;
    uint64_t *dstart;  /* n_nodes+1 */
    double *dist;
} gs__leaf_tables;

void gs__pipe_leaf_tables_free(gs__leaf_tables *lt);
int gs__pipe_leaf_tables(gs__builder *b, gs__leaf_tables *lt, gs_error *err);

#endif
