/* partition_internal.h - what the pieces of the nested bisection (paper sec.
 * 3.1, 4.1) share: the local view of one node being split (owned vertices
 * first, then ghost vertices), the growable output arrays, and the steps. */
#ifndef GS_PARTITION_INTERNAL_H
#define GS_PARTITION_INTERNAL_H

#include "tree.h"

/* One node N being split. Local vertex ids: 0..no-1 are the vertices V(N)
 * owned by N, no..nl-1 the ghost vertices (corners of faces of P(N) that N
 * does not own). vloc/floc are mesh-sized maps that hold local ids for the
 * vertices and faces of this node only (GS_NONE elsewhere), so every step
 * costs time proportional to the node's size. */
typedef struct gs__part_node {
    const gs_mesh *mesh;
    uint32_t id;            /* tree node id                                   */
    uint32_t no, nl, nf;    /* owned vertices, local vertices, faces of P(N)  */
    const uint32_t *lv;     /* nl: local -> mesh vertex                       */
    const uint32_t *faces;  /* nf: local -> mesh face                         */
    const uint32_t *vloc;   /* mesh vertex -> local id or GS_NONE             */
    const uint32_t *floc;   /* mesh face -> local face id or GS_NONE          */
    uint8_t *side;          /* nl: 0 or 1 (child) for owned and ghost ones    */
    double *phi;            /* nl: the smoothed side function minus its cut  */
                            /*   level (side = phi > 0), or NULL              */
    int phi_valid;          /* phi holds that function for the current sides */
} gs__part_node;

/* Growable output arrays of the curve builder. */
typedef struct gs__part_out {
    gs__sep_curve *curves;
    size_t n_curves, cap_curves;
    gs__sep_sample *samples;
    size_t n_samples, cap_samples;
    gs__sep_cross *cross;
    size_t n_cross, cap_cross;
} gs__part_out;

/* Sides of the owned vertices (side[0..no)): the connected components of the
 * graph induced by V(N) grouped into two balanced halves when that is
 * possible, otherwise a METIS bisection. Both sides are non-empty (no >= 2).
 * Then every ghost vertex takes the side of the majority of its owned
 * neighbours. (split.c, the only file that includes metis.h) */
int gs__part_sides(gs__part_node *nd, uint32_t seed, double mean_edge, gs_error *err);

/* Smooth separator (paper 4.1's aim, by a level set): diffuse the +-1 side
 * indicator of the METIS cut over the graph of P(N) for `iters` rounds of
 * edge-length-weighted averaging, cut at the median over the owned vertices
 * (exact balance), and set every local vertex's side from it. nd->phi then
 * holds the function minus the cut level, whose zero set (linear on each
 * face) is the separator. Keeps the METIS sides if the cut would empty a
 * side. (split.c) */
int gs__part_level_set(gs__part_node *nd, uint32_t iters, gs_error *err);

/* Cut nd->phi at the level keeping the current share of side-1 owned
 * vertices (exact balance): phi minus that level, sides, phi_valid. Keeps
 * the sides if ties make that impossible. GS_ENOMEM only. (split.c) */
int gs__part_cut_median(gs__part_node *nd);

/* Smooth separator as a level set of d_A^2 - d_B^2 (exact geodesic
 * distances from the owned vertices A, B nearest to the centroids of the two
 * sides): linear in flat regions, so its level sets are straight there.
 * Repeated `iters` times with the new sides' centres. (split.c) */
int gs__part_bisector(gs__part_node *nd, uint32_t iters, gs_error *err);

/* The separator curves of a node whose sides are set: the faces of P(N)
 * with corners on both sides are chained into paths and loops; each one is
 * placed on the zero level of nd->phi (or, without it, pulled taut between
 * anchors inside its strip and smoothed) and resampled (curve.c). */
int gs__part_curves(const gs__part_node *nd, const gs__tree_options *opt,
                    double mean_edge, gs__part_out *out, gs_error *err);

#endif
