/* render.c - a small software renderer for pictures of meshes, distance
 * fields and separator curves (geosep.h, "Pictures"): an orthographic
 * camera fitted to the mesh, a z-buffered triangle rasterizer with
 * supersampling, Lambert + ambient shading, a colour map with isolines of
 * constant width in pixels, and lines and dots drawn over the surface with
 * a depth test. The image is drawn in horizontal bands so that the
 * supersampled buffers stay small at any image size. No global state. */
#include "render_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MARGIN 0.05          /* of the image, on every side             */
#define BAND_SAMPLES (1u << 20) /* samples per band (bounds the memory) */
#define AMBIENT 0.35
#define DIFFUSE 0.65
#define ISO_HALF_WIDTH 0.75  /* pixels: isolines are 1.5 pixels wide    */
#define ISO_DARK 0.18        /* an isoline's colour: the map's x this   */
#define DOT_RADIUS 4.5       /* pixels: a point's dot ...               */
#define DOT_INNER 3.0        /*   ... white inside this, a dark ring    */

#define PATH_WIDTH 2.5          /* pixels: a path's white core ...       */
#define PATH_BORDER 6.0         /*   ... in a dark border                 */

static const float BACKGROUND[3] = {1.0f, 1.0f, 1.0f};
static const float PATH_RGB[3] = {1.0f, 1.0f, 1.0f};
static const float PATH_DARK[3] = {0.08f, 0.08f, 0.08f};
static const float PLAIN[3] = {0.86f, 0.83f, 0.75f};   /* no field       */
static const float UNREACHED[3] = {0.55f, 0.55f, 0.55f}; /* inf/NaN: grey */

/* The viridis colour map (matplotlib's default, by Stefan van der Walt and
 * Nathaniel Smith, public domain / CC0), at 10 evenly spaced points: the
 * values R's viridisLite::viridis(10) prints (#440154 ... #FDE725);
 * linear in between. */
static const unsigned char VIRIDIS[10][3] = {
    {0x44, 0x01, 0x54}, {0x48, 0x28, 0x78}, {0x3E, 0x4A, 0x89}, {0x31, 0x68, 0x8E}, {0x26, 0x82, 0x8E},
    {0x1F, 0x9E, 0x89}, {0x35, 0xB7, 0x79}, {0x6D, 0xCD, 0x59}, {0xB4, 0xDE, 0x2C}, {0xFD, 0xE7, 0x25}};

static void colormap(double t, float *c)
{
    if (!(t > 0)) t = 0;
    if (t > 1) t = 1;
    double x = t * 9.0;
    int i = (int)x;
    if (i > 8) i = 8;
    double a = x - i;
    for (int k = 0; k < 3; ++k) c[k] = (float)(((1 - a) * VIRIDIS[i][k] + a * VIRIDIS[i + 1][k]) / 255.0);
}

/* Separator colours and widths (pixels) by depth: the root's curve red and
 * widest; deeper ones thinner, in turn orange, blue, green, purple, ... */
static const float SEP_RGB[6][3] = {{0.85f, 0.05f, 0.05f}, {1.00f, 0.55f, 0.00f}, {0.10f, 0.35f, 0.95f},
                                    {0.00f, 0.62f, 0.30f}, {0.62f, 0.20f, 0.78f}, {0.20f, 0.20f, 0.20f}};

static double sep_width(uint32_t depth)
{
    static const double w[5] = {4.0, 3.0, 2.4, 1.9, 1.5};
    return depth < 5 ? w[depth] : 1.2;
}

void gs_render_options_default(gs_render_options *opt)
{
    if (!opt) return;
    memset(opt, 0, sizeof *opt);
    opt->width = 640;
    opt->height = 480;
    opt->azimuth_deg = 30;
    opt->elevation_deg = 20;
    opt->isolines = 10;
}

/* ---- camera --------------------------------------------------------------- */

typedef struct camera {
    double right[3], up[3], dir[3]; /* dir points towards the viewer       */
    double scale, ox, oy;           /* pixel x = ox + scale p.right,       */
                                    /* pixel y = oy - scale p.up           */
    double dmid, dinv;              /* depth = (p.dir - dmid) * dinv       */
} camera;

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static int normalize3(double *a)
{
    double n = sqrt(dot3(a, a));
    if (!(n > 0) || !isfinite(n)) return 0;
    a[0] /= n, a[1] /= n, a[2] /= n;
    return 1;
}

/* Fit the view to the vertices used by faces (used[v] != 0). */
static void camera_fit(camera *c, const gs_render_options *o, const double *xyz, uint32_t nv, const uint8_t *used)
{
    double az = o->azimuth_deg * (M_PI / 180.0), el = o->elevation_deg * (M_PI / 180.0);
    c->dir[0] = cos(el) * sin(az), c->dir[1] = sin(el), c->dir[2] = cos(el) * cos(az);
    c->right[0] = cos(az), c->right[1] = 0, c->right[2] = -sin(az);
    cross3(c->dir, c->right, c->up);
    normalize3(c->up);
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (uint32_t v = 0; v < nv; ++v) {
        if (!used[v]) continue;
        const double *p = xyz + 3 * (size_t)v;
        double q[3] = {dot3(p, c->right), dot3(p, c->up), dot3(p, c->dir)};
        for (int k = 0; k < 3; ++k) {
            if (q[k] < lo[k]) lo[k] = q[k];
            if (q[k] > hi[k]) hi[k] = q[k];
        }
    }
    double w = o->width * (1 - 2 * MARGIN), h = o->height * (1 - 2 * MARGIN);
    double ex = hi[0] - lo[0], ey = hi[1] - lo[1], ez = hi[2] - lo[2];
    double sx = ex > 0 ? w / ex : INFINITY, sy = ey > 0 ? h / ey : INFINITY;
    c->scale = sx < sy ? sx : sy;
    if (!isfinite(c->scale)) c->scale = 1; /* cannot happen: faces have area */
    c->ox = 0.5 * o->width - c->scale * 0.5 * (lo[0] + hi[0]);
    c->oy = 0.5 * o->height + c->scale * 0.5 * (lo[1] + hi[1]);
    c->dmid = 0.5 * (lo[2] + hi[2]);
    c->dinv = ez > 0 ? 1.0 / ez : 1.0;
}

static void project(const camera *c, const double *p, double *x, double *y, double *z)
{
    *x = c->ox + c->scale * dot3(p, c->right);
    *y = c->oy - c->scale * dot3(p, c->up);
    *z = (dot3(p, c->dir) - c->dmid) * c->dinv;
}

/* ---- validation -------------------------------------------------------------- */

static int check_options(const gs_mesh *mesh, const gs_render_options *o, gs_error *err)
{
    if (!mesh) return gs__fail(err, GS_EARG, "render: mesh is NULL");
    if (!o) return gs__fail(err, GS_EARG, "render: options are NULL");
    if (o->width < GS_RENDER_MIN_SIZE || o->width > GS_RENDER_MAX_SIZE || o->height < GS_RENDER_MIN_SIZE ||
        o->height > GS_RENDER_MAX_SIZE)
        return gs__fail(err, GS_EARG, "render: image size %ux%u: width and height must be %u to %u pixels", o->width,
                        o->height, GS_RENDER_MIN_SIZE, GS_RENDER_MAX_SIZE);
    if (!isfinite(o->azimuth_deg)) return gs__fail(err, GS_EARG, "render: azimuth %g is not finite", o->azimuth_deg);
    if (!isfinite(o->elevation_deg))
        return gs__fail(err, GS_EARG, "render: elevation %g is not finite", o->elevation_deg);
    if (o->isolines > GS_RENDER_MAX_ISOLINES)
        return gs__fail(err, GS_EARG, "render: %u isolines (at most %u)", o->isolines, GS_RENDER_MAX_ISOLINES);
    if (o->n_points && !o->points)
        return gs__fail(err, GS_EARG, "render: n_points is %u but points is NULL", o->n_points);
    for (uint32_t i = 0; i < o->n_points; ++i)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(o->points[3 * (size_t)i + k]))
                return gs__fail(err, GS_EARG, "render: point %u has a non-finite coordinate (%g)", i,
                                o->points[3 * (size_t)i + k]);
    if (o->n_paths && (!o->paths || !o->path_starts))
        return gs__fail(err, GS_EARG, "render: n_paths is %u but paths or path_starts is NULL", o->n_paths);
    for (uint32_t i = 0; i < o->n_paths; ++i)
        if (o->path_starts[i + 1] < o->path_starts[i] || (i == 0 && o->path_starts[0] != 0))
            return gs__fail(err, GS_EARG, "render: path_starts[%u] is %u, path_starts[%u] %u (offsets from 0, increasing)",
                            i, o->path_starts[i], i + 1, o->path_starts[i + 1]);
    for (size_t i = 0; o->n_paths && i < 3 * (size_t)o->path_starts[o->n_paths]; ++i)
        if (!isfinite(o->paths[i]))
            return gs__fail(err, GS_EARG, "render: path point %zu has a coordinate %g (must be finite)", i / 3,
                            o->paths[i]);
    if (o->separators) {
        gs_db_info info;
        int rc = gs_db_get_info(o->separators, &info, err);
        if (rc) return rc;
        uint32_t nv = gs_mesh_num_vertices(mesh);
        if (info.n_vertices != nv)
            return gs__fail(err, GS_EARG,
                            "render: separators: the database has %u vertices, the mesh %u (not the database of this mesh)",
                            info.n_vertices, nv);
        const double *a = gs_mesh_positions(mesh), *b = gs_db_positions(o->separators);
        for (size_t i = 0; i < 3 * (size_t)nv; ++i)
            if (a[i] != b[i])
                return gs__fail(err, GS_EARG,
                                "render: separators: vertex %zu is not where the database has it (not the database of this mesh)",
                                i / 3);
    }
    return GS_OK;
}

/* ---- the scene: projected vertices, normals, per-face data --------------------- */

typedef struct overlay { /* a line (a capsule of radius r) or a dot, in pixels */
    double x0, y0, z0, x1, y1, z1;
    double r;
    float rgb[3];
    int dot;
} overlay;

typedef struct scene {
    const gs_render_options *o;
    const gs_mesh *mesh;
    uint32_t nv, nf, S; /* S: samples per pixel along each axis */
    const double *xyz;
    const uint32_t *tri;
    const double *field;
    double *sx, *sy, *sz;   /* nv: pixel coordinates and depth             */
    double *vn;             /* 3 nv: vertex normals (zero: none)           */
    double *grad;           /* nf: |grad field| in field units per pixel   */
    double fmin, fmax, light[3], dir[3];
    double tol;             /* depth tolerance of overlays (depth units)   */
    overlay *ov;
    size_t nov;
} scene;

static void scene_free(scene *s)
{
    free(s->sx);
    free(s->sy);
    free(s->sz);
    free(s->vn);
    free(s->grad);
    free(s->ov);
}

static void field_range(scene *s, const uint8_t *used)
{
    s->fmin = INFINITY, s->fmax = -INFINITY;
    if (!s->field) return;
    for (uint32_t v = 0; v < s->nv; ++v) {
        double f = s->field[v];
        if (!used[v] || !isfinite(f)) continue;
        if (f < s->fmin) s->fmin = f;
        if (f > s->fmax) s->fmax = f;
    }
}

static int face_finite(const scene *s, uint32_t f)
{
    const uint32_t *c = s->tri + 3 * (size_t)f;
    return isfinite(s->field[c[0]]) && isfinite(s->field[c[1]]) && isfinite(s->field[c[2]]);
}

/* The field's gradient in screen space, per face (affine in x, y). */
static void face_gradients(scene *s)
{
    for (uint32_t f = 0; f < s->nf; ++f) {
        const uint32_t *c = s->tri + 3 * (size_t)f;
        s->grad[f] = 0;
        if (!face_finite(s, f)) continue;
        double ax = s->sx[c[1]] - s->sx[c[0]], ay = s->sy[c[1]] - s->sy[c[0]];
        double bx = s->sx[c[2]] - s->sx[c[0]], by = s->sy[c[2]] - s->sy[c[0]];
        double fa = s->field[c[1]] - s->field[c[0]], fb = s->field[c[2]] - s->field[c[0]];
        double det = ax * by - ay * bx;
        if (!(fabs(det) > 1e-12)) continue; /* edge-on: not drawn */
        double gx = (fa * by - fb * ay) / det, gy = (ax * fb - bx * fa) / det;
        s->grad[f] = sqrt(gx * gx + gy * gy);
    }
}

static void vertex_normals(scene *s)
{
    for (uint32_t f = 0; f < s->nf; ++f) {
        const uint32_t *c = s->tri + 3 * (size_t)f;
        const double *p0 = s->xyz + 3 * (size_t)c[0], *p1 = s->xyz + 3 * (size_t)c[1], *p2 = s->xyz + 3 * (size_t)c[2];
        double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        double b[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]}, n[3];
        cross3(a, b, n);
        if (!normalize3(n)) continue;
        /* weighted by the corner angle: smooth on uneven triangulations */
        for (int i = 0; i < 3; ++i) {
            const double *q = s->xyz + 3 * (size_t)c[i], *q1 = s->xyz + 3 * (size_t)c[(i + 1) % 3],
                         *q2 = s->xyz + 3 * (size_t)c[(i + 2) % 3];
            double u[3] = {q1[0] - q[0], q1[1] - q[1], q1[2] - q[2]}, w[3] = {q2[0] - q[0], q2[1] - q[1], q2[2] - q[2]};
            double ang = (normalize3(u) && normalize3(w)) ? acos(fmax(-1.0, fmin(1.0, dot3(u, w)))) : 0;
            for (int k = 0; k < 3; ++k) s->vn[3 * (size_t)c[i] + k] += ang * n[k];
        }
    }
    for (uint32_t v = 0; v < s->nv; ++v)
        if (!normalize3(s->vn + 3 * (size_t)v)) s->vn[3 * (size_t)v] = s->vn[3 * (size_t)v + 1] = s->vn[3 * (size_t)v + 2] = 0;
}

static void ov_line(overlay *v, const camera *cam, const double *a, const double *b, double width, const float *rgb)
{
    project(cam, a, &v->x0, &v->y0, &v->z0);
    project(cam, b, &v->x1, &v->y1, &v->z1);
    v->r = 0.5 * width;
    memcpy(v->rgb, rgb, sizeof v->rgb);
    v->dot = 0;
}

/* Separator segments (deepest first, so that the root's curves end on top),
 * then the points' dots. */
static int add_overlays(scene *s, const camera *cam, gs_error *err)
{
    const gs_render_options *o = s->o;
    gs__rseg *seg = NULL;
    size_t nseg = 0;
    if (o->separators) {
        int rc = gs__render_separators(s->mesh, o->separators, &seg, &nseg, err);
        if (rc) return rc;
    }
    size_t npp = o->n_paths ? o->path_starts[o->n_paths] : 0;
    s->ov = gs__malloc(nseg + 2 * npp + o->n_points + 1, sizeof *s->ov);
    if (!s->ov) {
        free(seg);
        return gs__fail(err, GS_ENOMEM, "render: out of memory for %zu lines", nseg + 2 * npp);
    }
    for (size_t i = 0; i < nseg; ++i) {
        uint32_t d = seg[i].depth;
        ov_line(&s->ov[s->nov++], cam, seg[i].p[0], seg[i].p[1], sep_width(d), SEP_RGB[d < 5 ? d : 5]);
    }
    free(seg);
    /* paths: every segment's dark border, then every white core over them */
    for (int pass = 0; pass < 2; ++pass)
        for (uint32_t i = 0; i < o->n_paths; ++i)
            for (uint32_t k = o->path_starts[i]; k + 1 < o->path_starts[i + 1]; ++k)
                ov_line(&s->ov[s->nov++], cam, o->paths + 3 * (size_t)k, o->paths + 3 * (size_t)k + 3,
                        pass ? PATH_WIDTH : PATH_BORDER, pass ? PATH_RGB : PATH_DARK);
    for (uint32_t i = 0; i < o->n_points; ++i) {
        const double *p = o->points + 3 * (size_t)i;
        static const float black[3] = {0, 0, 0};
        overlay *v = &s->ov[s->nov++];
        ov_line(v, cam, p, p, 2 * DOT_RADIUS, black);
        v->dot = 1;
    }
    return GS_OK;
}

static int scene_make(scene *s, const gs_mesh *mesh, const gs_render_options *o, gs_error *err)
{
    memset(s, 0, sizeof *s);
    s->o = o;
    s->mesh = mesh;
    s->nv = gs_mesh_num_vertices(mesh);
    s->nf = gs_mesh_num_faces(mesh);
    s->xyz = gs_mesh_positions(mesh);
    s->tri = gs_mesh_faces(mesh);
    s->field = o->field;
    uint64_t px = (uint64_t)o->width * o->height;
    s->S = px <= (4u << 20) ? 3 : px <= (16u << 20) ? 2 : 1;
    size_t nv1 = (size_t)s->nv + 1;
    uint8_t *used = gs__calloc(nv1, 1);
    s->sx = gs__malloc(nv1, sizeof *s->sx);
    s->sy = gs__malloc(nv1, sizeof *s->sy);
    s->sz = gs__malloc(nv1, sizeof *s->sz);
    s->vn = gs__calloc(3 * nv1, sizeof *s->vn);
    s->grad = gs__malloc((size_t)s->nf + 1, sizeof *s->grad);
    if (!used || !s->sx || !s->sy || !s->sz || !s->vn || !s->grad) {
        free(used);
        return gs__fail(err, GS_ENOMEM, "render: out of memory for a mesh of %u vertices", s->nv);
    }
    for (size_t i = 0; i < 3 * (size_t)s->nf; ++i) used[s->tri[i]] = 1;
    camera cam;
    camera_fit(&cam, o, s->xyz, s->nv, used);
    for (uint32_t v = 0; v < s->nv; ++v) project(&cam, s->xyz + 3 * (size_t)v, &s->sx[v], &s->sy[v], &s->sz[v]);
    field_range(s, used);
    free(used);
    memcpy(s->dir, cam.dir, sizeof s->dir);
    /* the light: from the viewer's upper left */
    for (int k = 0; k < 3; ++k) s->light[k] = cam.dir[k] + 0.55 * cam.up[k] - 0.35 * cam.right[k];
    normalize3(s->light);
    /* overlays on the surface may dip below it by the surface's slope times
     * their width: accept them up to (8 px) in depth */
    s->tol = 8.0 / cam.scale * cam.dinv;
    vertex_normals(s);
    if (s->field) face_gradients(s);
    return add_overlays(s, &cam, err);
}

/* ---- one band of rows: rasterize, shade, overlay, resolve ------------------------- */

typedef struct band {
    uint32_t y0, rows;  /* output rows [y0, y0 + rows)                     */
    uint32_t w, h;      /* in samples                                      */
    float *depth;       /* w h: larger is nearer; -inf: background         */
    uint32_t *face;     /* w h: GS_NONE: background                        */
    float *b1, *b2;     /* w h: barycentric weights of corners 1 and 2     */
    float *rgb;         /* 3 w h                                           */
} band;

/* The samples (centres at i + 0.5) in [lo, hi], clipped to 0..n-1 (in
 * doubles first: lo and hi may be far outside). */
static void sample_range(double lo, double hi, uint32_t n, long *i0, long *i1)
{
    lo = ceil(fmax(lo, -1.0) - 0.5);
    hi = floor(fmin(hi, (double)n + 1) - 0.5);
    *i0 = lo < 0 ? 0 : (long)lo;
    *i1 = hi > (double)n - 1 ? (long)n - 1 : (long)hi;
}

static void raster_face(const scene *s, band *b, uint32_t f)
{
    const uint32_t *c = s->tri + 3 * (size_t)f;
    double S = s->S, x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        x[i] = s->sx[c[i]] * S;
        y[i] = (s->sy[c[i]] - b->y0) * S;
        z[i] = s->sz[c[i]];
    }
    double ymin = fmin(y[0], fmin(y[1], y[2])), ymax = fmax(y[0], fmax(y[1], y[2]));
    if (ymax < 0 || ymin > b->h) return;
    double xmin = fmin(x[0], fmin(x[1], x[2])), xmax = fmax(x[0], fmax(x[1], x[2]));
    if (xmax < 0 || xmin > b->w) return;
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (!(fabs(area) > 1e-12)) return;
    /* samples at (i + 0.5, j + 0.5) inside the triangle */
    long i0, i1, j0, j1;
    sample_range(xmin, xmax, b->w, &i0, &i1);
    sample_range(ymin, ymax, b->h, &j0, &j1);
    double inv = 1.0 / area;
    for (long j = j0; j <= j1; ++j) {
        double py = j + 0.5;
        for (long i = i0; i <= i1; ++i) {
            double px = i + 0.5;
            double w1 = ((px - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (py - y[0])) * inv;
            double w2 = ((x[1] - x[0]) * (py - y[0]) - (px - x[0]) * (y[1] - y[0])) * inv;
            double w0 = 1 - w1 - w2;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            double zz = w0 * z[0] + w1 * z[1] + w2 * z[2];
            size_t k = (size_t)j * b->w + (size_t)i;
            if (zz > b->depth[k]) {
                b->depth[k] = (float)zz;
                b->face[k] = f;
                b->b1[k] = (float)w1;
                b->b2[k] = (float)w2;
            }
        }
    }
}

static void shade_sample(const scene *s, const band *b, size_t k, float *out)
{
    uint32_t f = b->face[k];
    if (f == GS_NONE) {
        memcpy(out, BACKGROUND, sizeof BACKGROUND);
        return;
    }
    const uint32_t *c = s->tri + 3 * (size_t)f;
    double w1 = b->b1[k], w2 = b->b2[k], w0 = 1 - w1 - w2;
    float col[3];
    if (!s->field) {
        memcpy(col, PLAIN, sizeof col);
    } else if (!face_finite(s, f)) {
        memcpy(col, UNREACHED, sizeof col);
    } else {
        double v = w0 * s->field[c[0]] + w1 * s->field[c[1]] + w2 * s->field[c[2]];
        double range = s->fmax - s->fmin;
        colormap(range > 0 ? (v - s->fmin) / range : 0, col);
        uint32_t K = s->o->isolines;
        if (K && range > 0 && s->grad[f] > 0) {
            double step = range / (K + 1), u = (v - s->fmin) / step, lev = floor(u + 0.5);
            if (lev < 1) lev = 1;
            if (lev > K) lev = K;
            if (fabs(u - lev) * step / s->grad[f] < ISO_HALF_WIDTH)
                for (int i = 0; i < 3; ++i) col[i] *= (float)ISO_DARK;
        }
    }
    /* Lambert, two-sided: normals turned towards the viewer */
    const double *p0 = s->xyz + 3 * (size_t)c[0], *p1 = s->xyz + 3 * (size_t)c[1], *p2 = s->xyz + 3 * (size_t)c[2];
    double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    double fn[3], n[3];
    cross3(e1, e2, fn);
    normalize3(fn);
    const double *n0 = s->vn + 3 * (size_t)c[0], *n1 = s->vn + 3 * (size_t)c[1], *n2 = s->vn + 3 * (size_t)c[2];
    for (int i = 0; i < 3; ++i) n[i] = w0 * n0[i] + w1 * n1[i] + w2 * n2[i];
    if (!normalize3(n) || dot3(n, fn) < 0.2) memcpy(n, fn, sizeof n); /* no smooth normal there */
    if (dot3(fn, s->dir) < 0) n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    double lit = AMBIENT + DIFFUSE * fmax(0.0, dot3(n, s->light));
    for (int i = 0; i < 3; ++i) out[i] = (float)(col[i] * lit);
}

static void draw_overlay(const scene *s, band *b, const overlay *v)
{
    double S = s->S, x0 = v->x0 * S, y0 = (v->y0 - b->y0) * S, x1 = v->x1 * S, y1 = (v->y1 - b->y0) * S;
    double r = v->r * S, rin = DOT_INNER * S;
    double xmin = fmin(x0, x1) - r, xmax = fmax(x0, x1) + r, ymin = fmin(y0, y1) - r, ymax = fmax(y0, y1) + r;
    if (ymax < 0 || ymin > b->h || xmax < 0 || xmin > b->w) return;
    long i0, i1, j0, j1;
    sample_range(xmin, xmax, b->w, &i0, &i1);
    sample_range(ymin, ymax, b->h, &j0, &j1);
    double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i) {
            double px = i + 0.5 - x0, py = j + 0.5 - y0;
            double t = len2 > 0 ? (px * dx + py * dy) / len2 : 0;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            double ex = px - t * dx, ey = py - t * dy, d2 = ex * ex + ey * ey;
            if (d2 > r * r) continue;
            size_t k = (size_t)j * b->w + (size_t)i;
            double z = v->z0 + t * (v->z1 - v->z0);
            if (z + s->tol < b->depth[k]) continue; /* behind the surface */
            float *o = b->rgb + 3 * k;
            if (v->dot && d2 < rin * rin) o[0] = o[1] = o[2] = 1.0f;
            else memcpy(o, v->rgb, sizeof v->rgb);
        }
}

static void render_band(const scene *s, band *b, uint8_t *rgb)
{
    size_t n = (size_t)b->w * b->h;
    for (size_t k = 0; k < n; ++k) {
        b->depth[k] = -INFINITY;
        b->face[k] = GS_NONE;
    }
    double top = b->y0, bottom = (double)b->y0 + b->rows;
    for (uint32_t f = 0; f < s->nf; ++f) {
        const uint32_t *c = s->tri + 3 * (size_t)f;
        double y0 = s->sy[c[0]], y1 = s->sy[c[1]], y2 = s->sy[c[2]];
        if (fmax(y0, fmax(y1, y2)) < top || fmin(y0, fmin(y1, y2)) > bottom) continue;
        raster_face(s, b, f);
    }
    for (size_t k = 0; k < n; ++k) shade_sample(s, b, k, b->rgb + 3 * k);
    for (size_t i = 0; i < s->nov; ++i) draw_overlay(s, b, &s->ov[i]);
    uint32_t S = s->S, W = s->o->width;
    float inv = 1.0f / (float)(S * S);
    for (uint32_t y = 0; y < b->rows; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            float acc[3] = {0, 0, 0};
            for (uint32_t j = 0; j < S; ++j)
                for (uint32_t i = 0; i < S; ++i) {
                    const float *p = b->rgb + 3 * ((size_t)(y * S + j) * b->w + x * S + i);
                    acc[0] += p[0], acc[1] += p[1], acc[2] += p[2];
                }
            uint8_t *o = rgb + 3 * ((size_t)(b->y0 + y) * W + x);
            for (int k = 0; k < 3; ++k) {
                float v = acc[k] * inv * 255.0f + 0.5f;
                o[k] = (uint8_t)(!(v >= 0) ? 0 : v > 255 ? 255 : v);
            }
        }
}

int gs_render(const gs_mesh *mesh, const gs_render_options *opt, uint8_t *rgb, gs_error *err)
{
    int rc = check_options(mesh, opt, err);
    if (rc) return rc;
    if (!rgb) return gs__fail(err, GS_EARG, "render: rgb is NULL");
    scene s;
    if ((rc = scene_make(&s, mesh, opt, err))) {
        scene_free(&s);
        return rc;
    }
    uint32_t S = s.S, W = opt->width, H = opt->height;
    uint32_t rows = BAND_SAMPLES / (W * S * S);
    if (rows < 1) rows = 1;
    if (rows > H) rows = H;
    band b = {0};
    b.w = W * S;
    size_t n = (size_t)b.w * rows * S;
    b.depth = gs__malloc(n, sizeof *b.depth);
    b.face = gs__malloc(n, sizeof *b.face);
    b.b1 = gs__malloc(n, sizeof *b.b1);
    b.b2 = gs__malloc(n, sizeof *b.b2);
    b.rgb = gs__malloc(3 * n, sizeof *b.rgb);
    /* nothing fails once the buffers are there: rgb is untouched on failure */
    if (!b.depth || !b.face || !b.b1 || !b.b2 || !b.rgb) {
        rc = gs__fail(err, GS_ENOMEM, "render: out of memory for a %ux%u image", W, H);
    } else {
        for (uint32_t y0 = 0; y0 < H; y0 += rows) {
            b.y0 = y0;
            b.rows = H - y0 < rows ? H - y0 : rows;
            b.h = b.rows * S;
            render_band(&s, &b, rgb);
        }
    }
    free(b.depth);
    free(b.face);
    free(b.b1);
    free(b.b2);
    free(b.rgb);
    scene_free(&s);
    return rc;
}

int gs_render_png(const gs_mesh *mesh, const gs_render_options *opt, const char *path, gs_error *err)
{
    int rc = check_options(mesh, opt, err);
    if (rc) return rc;
    if (!path || !*path) return gs__fail(err, GS_EARG, "render: no output path");
    uint8_t *img = gs__malloc((size_t)opt->width * opt->height, 3);
    if (!img) return gs__fail(err, GS_ENOMEM, "render: out of memory for a %ux%u image", opt->width, opt->height);
    rc = gs_render(mesh, opt, img, err);
    if (!rc) rc = gs__png_write(path, img, opt->width, opt->height, err);
    free(img);
    return rc;
}
