/* mesh_internal.h - the internal layout of meshes and patches: flat arrays of
 * positions and faces plus a corner/half-edge connectivity (gs__topo) that all
 * distance solvers run on. Not part of the public API. */
#ifndef GS_MESH_INTERNAL_H
#define GS_MESH_INTERNAL_H

#include "../core/internal.h"

/* Half-edge h = 3*f + i of face f runs from tri[h] to tri[gs__next(h)]; it is
 * also "corner h", the corner of face f at vertex tri[h]. */
static inline uint32_t gs__next(uint32_t h) { return (h % 3 == 2) ? h - 2 : h + 1; }
static inline uint32_t gs__prev(uint32_t h) { return (h % 3 == 0) ? h + 2 : h - 1; }

enum {
    GS_V_BOUNDARY = 1,    /* on a boundary edge (or a bow-tie vertex)       */
    GS_V_SADDLE = 2,      /* interior, total angle > 2*pi                   */
    GS_V_UNUSED = 4,      /* used by no face                                */
    GS_V_NONMANIFOLD = 8  /* several fans of faces meet (patches only)      */
};

/* Connectivity and intrinsic geometry of a triangle mesh or patch. */
typedef struct gs__topo {
    uint32_t nv, nf;
    const double *xyz;   /* 3*nv positions (borrowed)                        */
    const uint32_t *tri; /* 3*nf corner vertices (borrowed)                  */
    uint32_t *opp;       /* 3*nf: twin half-edge across the edge, or GS_NONE */
    double *len;         /* 3*nf: length of half-edge h                      */
    double *angle;       /* 3*nf: interior angle at corner h (radians)       */
    uint32_t *vc_start;  /* nv+1: CSR offsets into vc                        */
    uint32_t *vc;        /* corners at each vertex (h with tri[h] == v)      */
    double *vangle;      /* nv: total angle at each vertex                   */
    uint8_t *vflag;      /* nv: GS_V_* flags                                 */
    uint32_t n_edges;
} gs__topo;

/* The point of face f with barycentric weights w (of its corners in
 * order): p = w0 x(c0) + w1 x(c1) + w2 x(c2). */
static inline void gs__face_point(const gs__topo *t, uint32_t f, const double w[3], double p[3])
{
    const uint32_t *c = t->tri + 3 * (size_t)f;
    for (int k = 0; k < 3; ++k)
        p[k] = w[0] * t->xyz[3 * (size_t)c[0] + k] + w[1] * t->xyz[3 * (size_t)c[1] + k] +
               w[2] * t->xyz[3 * (size_t)c[2] + k];
}

/* Where the faces came from, for error messages: the file name and, for
 * every face, the line (text files) or element number (binary files) that
 * defined it. Both pointers may be NULL. */
typedef struct gs__origin {
    const char *file;
    const uint32_t *face_line; /* nf entries, or NULL                      */
    const char *unit;          /* "line" or "face"; NULL means "face"       */
} gs__origin;

enum { GS_TOPO_ALLOW_NONMANIFOLD_VERTICES = 1 };

/* Validate and build connectivity. On failure *t is left empty (freed). */
int gs__topo_build(gs__topo *t, uint32_t nv, const double *xyz, uint32_t nf,
                  const uint32_t *tri, unsigned flags, const gs__origin *origin,
                  gs_error *err);
void gs__topo_free(gs__topo *t);
/* The connectivity of a patch of whole's mesh, without validation (its
 * faces are the mesh's, already checked): face f of the patch is face
 * fmap[f] of the mesh, with the same corner order (tri: the patch's
 * corners in its own vertex ids); opp (3 nf, malloc'ed, taken over also on
 * failure): the twins, a mesh twin's local half-edge where its face is in
 * the patch, else GS_NONE. Lengths and angles are copied from whole: the
 * same connectivity, bit for bit, as gs__topo_build of those faces with
 * GS_TOPO_ALLOW_NONMANIFOLD_VERTICES, in O(patch). */
int gs__topo_build_sub(gs__topo *t, const gs__topo *whole, const uint32_t *fmap, uint32_t *opp, uint32_t nv,
                       const double *xyz, uint32_t nf, const uint32_t *tri, gs_error *err);

/* The validation's zero-area test of triangle (p, q, r): 0 if it has area,
 * 2 if its corners are at one point, 1 if they are collinear (its height is
 * below ~1e-12 of its longest edge). */
int gs__tri_zero_area(const double *p, const double *q, const double *r);

/* 1-to-4 midpoint subdivision of t (subdivide.c): the vertices of t keep
 * their ids, then one midpoint per edge; face f becomes faces 4f .. 4f+3:
 * (c0, m0, m2), (m0, c1, m1), (m2, m1, c2), (m0, m1, m2), c the corners of
 * f and m_i the midpoint of its half-edge 3f+i. *xyz_out (3 * *nv_out) and
 * *tri_out (3 * *nf_out) are malloc'ed, the caller frees them. */
int gs__subdivide_arrays(const gs__topo *t, uint32_t *nv_out, double **xyz_out, uint32_t *nf_out,
                         uint32_t **tri_out, gs_error *err);

struct gs_mesh {
    uint32_t nv, nf;
    double *xyz;
    uint32_t *tri;
    gs__topo topo;
    gs_mesh_report report;
};

/* Take ownership of xyz/tri (malloc'ed) and build a mesh; on failure both
 * arrays are freed. origin may be NULL. */
int gs__mesh_adopt(double *xyz, uint32_t nv, uint32_t *tri, uint32_t nf,
                  const gs__origin *origin, gs_mesh **out, gs_error *err);

struct gs_patch {
    const gs_mesh *mesh;
    uint32_t nv, nf;
    int identity;       /* 1: the whole mesh, local ids == mesh ids         */
    double *xyz;        /* owned local copies (NULL if identity)            */
    uint32_t *tri;
    uint32_t *vmap;     /* local -> mesh vertex, increasing (NULL if identity) */
    uint32_t *fmap;     /* local -> mesh face (NULL if identity)            */
    gs__topo topo_own;   /* owned connectivity (unused if identity)          */
    const gs__topo *topo;/* the connectivity solvers use                     */
};

#endif
