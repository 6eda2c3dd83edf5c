/* pipeline.h - what the stages of gs_db_build share (paper sec. 3.1, 4.1,
 * 4.2): the builder's state, progress, and the per-node and leaf stages.
 * build.c runs the pipeline (tree -> nodes -> leaf tables -> database);
 * node.c computes one node's distance fields and fits its functions;
 * leaves.c the exact same-leaf tables. Internal. */
#ifndef GS_PIPELINE_H
#define GS_PIPELINE_H

#include "../fit/fun.h"
#include "../mesh/mesh_internal.h"
#include "../db/db_near.h"
#include "../partition/tree.h"

/* Per-vertex function slots: vertex x owns funs[fun_start[x] ..) and each
 * function's coefficients live in a per-node arena. */
typedef struct gs__builder {
    const gs_mesh *mesh;
    const double *xyz_out;  /* the positions the database stores (the      */
                            /*   caller's: mesh may be a centred copy)      */
    const gs_build_options *opt;
    const gs__tree *tree;
    uint32_t nthreads;
    uint64_t *fun_start;   /* nv+1 */
    gs__fun *funs;
    float *fun_err;        /* per function: its fit's worst error (at the  */
                           /*   samples or outside the band between them;  */
                           /*   0 for sampled): near.c widens the radius   */
                           /*   of vertices with an uncertified function   */
    float *fun_abs;        /* per function: the same error, absolute (mesh */
                           /*   units; 0 for sampled)                      */
    double **arenas;       /* one coefficient arena per node (or NULL)     */
    struct gs__node_fits *node_fits; /* per node: its fits' statistics   */
    uint32_t n_rough;      /* nodes whose curves were cut shorter (build.c) */
    /* GS_METHOD_DGG: one graph of the whole mesh (dgg_patch: the identity
     * patch), nodes solve on views of it (gs__solver_dgg_view) */
    gs_patch *dgg_patch;
    gs_solver *dgg;
    /* progress */
    double work_total, work_done;
    /* stats */
    uint64_t n_fields;
} gs__builder;

/* One node's fits (node.c fills it when it fits the node). */
typedef struct gs__node_fits {
    uint64_t n_functions, n_mixed, n_over_tol, n_uncertified;
    double max_fit_error, degree_sum, fit_err_sum;
} gs__node_fits;

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

/* The faces that a shortest path of length <= r[k] from some lv[k] may
 * cross (leaves.c: reached from the vertices' faces through shared
 * vertices, keeping faces that may meet a ball B(lv[k], r[k])) into
 * *faces (grown as needed, *cap entries); fstamp: per mesh face, the
 * stamp of the last region that took it (stamp > 0, unique per call on
 * the same fstamp). Returns the count, GS_NONE when out of memory. */
/* Near pairs (near.c): every pair x < y in different leaves with exact
 * d(x, y) < radius[x] or < radius[y] (mesh units, per vertex) whose answer
 * from db0 (the database without near pairs) is off by more than tol * d;
 * *out (malloc'ed, sorted by x then y, caller frees) and its count. */
int gs__pipe_near_pairs(gs__builder *b, const gs_db *db0, const double *radius, double tol, gs__near_pair **out,
                        uint64_t *n_out, gs_error *err);

/* Pairs off by more than this through the separators are stored (the fit
 * certificate's eps, GS_FIT_MAX_ERR). */
#define GS_PIPE_NEAR_TOL 0.02
/* The radius of vertices with an uncertified function, times near_radius:
 * their worst fit error / GS_FIT_MAX_ERR, clamped to [WIDE, WIDE_MAX]. */
#define GS_PIPE_NEAR_WIDE 2.0
#define GS_PIPE_NEAR_WIDE_MAX 3.0
/* ... and at least their worst absolute fit error / GS_PIPE_NEAR_TOL (the
 * pairs a dip of that depth can move by more than GS_PIPE_NEAR_TOL), at
 * most GS_PIPE_NEAR_ABS_MAX times near_radius. */
#define GS_PIPE_NEAR_ABS_MAX 10.0

uint32_t gs__pipe_region(const gs_mesh *m, const uint32_t *lv, uint32_t n, const double *r, uint32_t stamp,
                         uint32_t *fstamp, uint32_t **faces, size_t *cap);

/* The tree's curves shaped before the fields (curves.c): every curve of
 * more than cap samples thinned to cap; each curve passing next to a sharp
 * saddle given a detour through it (*cut: new, one byte per sample, 1 where
 * a piece must end; the caller frees it); curves (of the nodes i with
 * only[i] != 0; only NULL: all) split into pieces of at most piece0
 * intervals and at the cuts (cut may be NULL). GS_ENOMEM leaves the tree
 * as it was. */
void gs__pipe_thin_samples(gs__tree *t, uint32_t cap);
int gs__pipe_insert_pivots(gs__tree *t, const gs_mesh *m, uint8_t **cut, gs_error *err);
int gs__pipe_split_curves(gs__tree *t, uint32_t piece0, const uint8_t *only, const uint8_t *cut, gs_error *err);

#endif
