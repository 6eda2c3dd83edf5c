/* tree.h - the nested bisection tree of a mesh (paper sec. 3.1 and 4.1):
 * patches P(N) (face sets with ghost triangles), separators S(N) made of
 * smooth sampled curves, and the leaf of every vertex. Internal. */
#ifndef GS_TREE_H
#define GS_TREE_H

#include "../mesh/mesh_internal.h"

/* A separator sample: a point of mesh face `face` with barycentric coords. */
typedef struct gs_sep_sample {
    uint32_t face;  /* mesh face id                                       */
    double bary[3]; /* >= 0, sum 1                                        */
    double s;       /* arc length from the curve's start (0 for the first) */
} gs_sep_sample;

/* A crossing of a separator curve with a mesh edge. The samples of a curve
 * lie on the piecewise-linear curve through its crossings: it enters mesh
 * face `face` through the edge (v[0], v[1]) at (1-t)*v[0] + t*v[1] and runs
 * straight inside `face` to the next crossing. v[0] lies on child 0's side,
 * v[1] on child 1's side; face is GS_NONE after the last crossing of a path
 * (both ends of a path are on patch-boundary edges). Every mesh edge of
 * P(N) joining the two sides is crossed exactly once by S(N). */
typedef struct gs_sep_cross {
    uint32_t face;
    uint32_t v[2];
    double t;       /* in (0,1): never through a vertex                      */
} gs_sep_cross;

/* A separator curve: an ordered run of samples at (nearly) regular arc
 * length. A path ends on the patch boundary at both ends; a loop is closed
 * (its last sample connects back to the first; `length` includes that
 * closing segment, so samples are spaced length/n_samples apart). */
typedef struct gs_sep_curve {
    uint32_t node;         /* tree node whose separator holds the curve    */
    uint32_t closed;       /* 1 = loop, 0 = path                           */
    uint32_t sample_start; /* into gs_tree.samples                         */
    uint32_t n_samples;    /* >= 2                                          */
    double length;         /* arc length                                    */
    uint32_t cross_start;  /* into gs_tree.cross: the edge crossings of the */
    uint32_t n_cross;      /*   piecewise-linear curve the samples lie on   */
} gs_sep_curve;

typedef struct gs_tree_node {
    uint32_t parent;      /* GS_NONE for the root (node 0)                  */
    uint32_t child[2];    /* GS_NONE for leaves                             */
    uint32_t depth;       /* root 0                                         */
    uint32_t face_start;  /* into gs_tree.faces: mesh faces of P(N), with   */
    uint32_t n_faces;     /*   the ghost triangles its separator crossed    */
    uint32_t vert_start;  /* into gs_tree.verts: the mesh vertices owned by */
    uint32_t n_verts;     /*   the subtree of N (contiguous: DFS order)     */
    uint32_t curve_start; /* into gs_tree.curves: the curves of S(N)        */
    uint32_t n_curves;    /*   (0 for leaves, and for a split by components)*/
    uint32_t curve_prefix;/* number of curves of all proper ancestors of N  */
} gs_tree_node;

typedef struct gs_tree {
    uint32_t n_nodes, n_curves, n_samples;
    gs_tree_node *nodes;     /* node 0 is the root; parents before children */
    gs_sep_curve *curves;    /* grouped by node, in node order              */
    gs_sep_sample *samples;
    gs_sep_cross *cross;     /* grouped by curve (gs_sep_curve.cross_start) */
    uint32_t n_cross;
    uint32_t *faces;         /* concatenated face lists of all nodes        */
    size_t n_face_refs;
    uint32_t *verts;         /* a permutation of the referenced vertices in */
    uint32_t n_verts;        /*   DFS leaf order (node ranges nest)         */
    uint32_t *leaf_of_vertex;/* nv entries; GS_NONE for unreferenced ones   */
    /* statistics */
    double avg_leaf_depth;   /* over vertices (as the paper's av h)         */
    uint32_t max_depth;
    double avg_curves_per_separator, avg_samples_per_curve;
    uint32_t n_leaves;
} gs_tree;

typedef struct gs_tree_options {
    uint32_t vmax;          /* stop splitting at <= vmax vertices (30)       */
    double sample_spacing;  /* target sample spacing / mean edge length (1) */
    uint32_t smooth_iters;  /* strip curves: filter-and-project-onto-cut-   */
                            /*   edge iterations (level_iters = 0 only)     */
    uint32_t filter_iters;  /* filter the samples and project them onto the */
                            /*   surface (paper 4.1), after resampling (0:  */
                            /*   else they leave the separator)             */
    uint32_t min_samples;   /* at least this many samples per curve (3):   */
                            /*   short curves sampled densely enough for    */
                            /*   fits of the degree the builder allows      */
    uint32_t seed;          /* METIS seed (deterministic builds)            */
    uint32_t level_iters;   /* diffusion rounds of the level-set separator  */
                            /*   (0: curves pulled taut in the METIS strip) */
    uint32_t cut_seeds;     /* METIS seeds seed, seed+1, ... tried per node  */
                            /*   (4); the candidate cut whose separator is  */
                            /*   shortest wins (paper 4.1: short, smooth)   */
    uint32_t bisector;      /* also try each cut as a power bisector (1;    */
                            /*   level-set curves only: level_iters > 0)    */
    double level_bias;      /* diffusion level-set candidates count this    */
                            /*   much longer (1.25): bisectors are straight */
    double long_curve;      /* length scale of the candidates' score, in    */
                            /*   mean edges x sqrt(vertices) (2; 0: plain   */
                            /*   total length; see tree.c choose_cut)       */
    uint32_t threads;       /* threads over a node's candidate cuts (0: the */
                            /*   OpenMP default); the tree is the same for  */
                            /*   any count                                   */
    void (*progress)(void *user, double fraction); /* after each split node */
    void *progress_user;    /*   (fraction of the estimated work), or NULL  */
} gs_tree_options;

void gs_tree_options_default(gs_tree_options *o);

/* Build the tree. Every referenced vertex belongs to exactly one leaf; a
 * vertex owned by node N lies on a face of P(N); for every internal node N
 * and vertices x, y owned by different children, every path inside P(N)
 * from x to y crosses a curve of S(N) (or none exists: different
 * components, empty separator). *out receives a new tree (gs_tree_free). */
int gs_tree_build(const gs_mesh *mesh, const gs_tree_options *opt, gs_tree **out,
                  gs_error *err);
void gs_tree_free(gs_tree *tree);

#endif
