/* test_render.c - the renderer (gs_render, gs_render_png) on generated
 * meshes, by known answers: the pixels a face-on square covers, exact
 * background, one colour for a constant field, K isolines crossed by a
 * scanline, no holes in a closed sphere's silhouette, grey for
 * unreachable vertices, the view's orientation, dots hidden behind the
 * surface, paths (a white line in a dark border) where they run and
 * hidden behind the surface, separator curves between the root's two subtrees, the PNG read
 * back with libpng equal to the buffer, every bad argument, and no file
 * (nor a partial one) after a failed write. */
#include "check.h"
#include "geosep.h"

#include <dirent.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static gs_mesh *gen(const char *spec)
{
    gs_mesh *m = NULL;
    gs_error err = {0};
    int rc = gs_mesh_generate(spec, &m, &err);
    CHECK_MSG(rc == GS_OK, "%s: %s", spec, err.message);
    return m;
}

typedef struct image {
    uint32_t w, h;
    uint8_t *p;
} image;

static image render(const gs_mesh *m, const gs_render_options *o)
{
    image im = {o->width, o->height, malloc((size_t)o->width * o->height * 3)};
    gs_error err = {0};
    int rc = gs_render(m, o, im.p, &err);
    CHECK_MSG(rc == GS_OK, "gs_render: %s", err.message);
    return im;
}

static const uint8_t *px(const image *im, uint32_t x, uint32_t y) { return im->p + 3 * ((size_t)y * im->w + x); }
static int is_bg(const uint8_t *p) { return p[0] == 255 && p[1] == 255 && p[2] == 255; }
static int is_grey(const uint8_t *p) { return p[0] == p[1] && p[1] == p[2]; }

static gs_render_options opts(uint32_t w, uint32_t h, double az, double el)
{
    gs_render_options o;
    gs_render_options_default(&o);
    o.width = w, o.height = h, o.azimuth_deg = az, o.elevation_deg = el;
    return o;
}

/* A unit square seen face-on: 0.9 of the smaller side, centred, every
 * pixel of it covered, every other pixel exactly the background; also at a
 * size drawn in many bands. */
static void test_square_area(void)
{
    gs_mesh *m = gen("grid:2,2");
    uint32_t sizes[][2] = {{300, 200}, {200, 300}, {1000, 1000}, {16, 16}};
    for (size_t t = 0; t < sizeof sizes / sizeof *sizes; ++t) {
        gs_render_options o = opts(sizes[t][0], sizes[t][1], 0, 0);
        image im = render(m, &o);
        double side = 0.9 * (o.width < o.height ? o.width : o.height);
        double x0 = 0.5 * (o.width - side), y0 = 0.5 * (o.height - side);
        uint64_t inside_bad = 0, outside_bad = 0, n = 0;
        for (uint32_t y = 0; y < o.height; ++y)
            for (uint32_t x = 0; x < o.width; ++x) {
                int in = x >= x0 && x + 1 <= x0 + side && y >= y0 && y + 1 <= y0 + side;
                int edge = !in && x + 1 > x0 && x < x0 + side && y + 1 > y0 && y < y0 + side;
                const uint8_t *p = px(&im, x, y);
                n += !is_bg(p);
                if (in && is_bg(p)) inside_bad++;
                if (!in && !edge && !is_bg(p)) outside_bad++;
            }
        CHECK_MSG(inside_bad == 0 && outside_bad == 0, "%ux%u: %llu inside pixels empty, %llu outside drawn", o.width,
                  o.height, (unsigned long long)inside_bad, (unsigned long long)outside_bad);
        /* sides land on whole pixels here, so the area is exact */
        if (side == floor(side) && x0 == floor(x0) && y0 == floor(y0))
            CHECK_MSG(n == (uint64_t)(side * side), "%ux%u: %llu pixels drawn, expected %.0f", o.width, o.height,
                      (unsigned long long)n, side * side);
        free(im.p);
    }
    gs_mesh_free(m);
}

/* A constant field: every drawn pixel of a face-on grid is the same colour,
 * the colour map's low end (violet: blue > red > green), no isolines. */
static void test_constant_field(void)
{
    gs_mesh *m = gen("grid:11,11");
    uint32_t nv = gs_mesh_num_vertices(m);
    double *f = malloc(nv * sizeof *f);
    for (uint32_t v = 0; v < nv; ++v) f[v] = 5.0;
    gs_render_options o = opts(200, 200, 0, 0);
    o.field = f;
    o.isolines = 10;
    image im = render(m, &o);
    const uint8_t *c = px(&im, 100, 100);
    uint64_t other = 0, drawn = 0;
    for (uint32_t y = 10; y < 190; ++y)
        for (uint32_t x = 10; x < 190; ++x) {
            const uint8_t *p = px(&im, x, y);
            drawn++;
            other += memcmp(p, c, 3) != 0;
        }
    CHECK_MSG(other == 0, "%llu of %llu pixels differ from the centre's colour", (unsigned long long)other,
              (unsigned long long)drawn);
    CHECK_MSG(c[2] > c[0] && c[0] > c[1], "colour %u,%u,%u: expected viridis' violet", c[0], c[1], c[2]);
    /* two-sided: the back, seen from behind (mirrored), is lit as the front */
    o.azimuth_deg = 180;
    image back = render(m, &o);
    const uint8_t *cb = px(&back, 100, 100);
    CHECK_MSG(memcmp(cb, c, 3) == 0, "back %u,%u,%u, front %u,%u,%u", cb[0], cb[1], cb[2], c[0], c[1], c[2]);
    free(back.p);
    free(im.p);
    free(f);
    gs_mesh_free(m);
}

/* Isolines of a linear field: K dark bands along a scanline. */
static void test_isolines(void)
{
    gs_mesh *m = gen("grid:41,41");
    uint32_t nv = gs_mesh_num_vertices(m);
    const double *xyz = gs_mesh_positions(m);
    double *f = malloc(nv * sizeof *f);
    for (uint32_t v = 0; v < nv; ++v) f[v] = 3.0 * xyz[3 * v] + 1.0;
    uint32_t ks[] = {1, 3, 7, 20};
    for (size_t t = 0; t < sizeof ks / sizeof *ks; ++t) {
        gs_render_options o = opts(400, 400, 0, 0);
        o.field = f;
        o.isolines = 0;
        image plain = render(m, &o);
        o.isolines = ks[t];
        image iso = render(m, &o);
        for (uint32_t y = 100; y <= 300; y += 100) {
            int runs = 0, in = 0;
            uint32_t width = 0, maxw = 0;
            for (uint32_t x = 0; x < o.width; ++x) {
                const uint8_t *a = px(&plain, x, y), *b = px(&iso, x, y);
                int dark = b[0] + b[1] + b[2] < 0.6 * (a[0] + a[1] + a[2]);
                if (dark && !in) runs++, width = 0;
                if (dark) width++, maxw = width > maxw ? width : maxw;
                in = dark;
            }
            CHECK_MSG(runs == (int)ks[t], "K %u, row %u: %d dark bands", ks[t], y, runs);
            CHECK_MSG(maxw >= 1 && maxw <= 3, "K %u: isoline %u pixels wide (expected 1-3)", ks[t], maxw);
        }
        /* the field grows to the right: the map's low (violet) end left */
        const uint8_t *l = px(&plain, 25, 200), *r = px(&plain, 375, 200);
        CHECK(l[2] > l[1] && r[0] > r[2] && r[1] > r[2]);
        free(plain.p);
        free(iso.p);
    }
    /* isolines keep their width in pixels when the mesh is zoomed */
    gs_render_options o = opts(800, 800, 0, 0);
    o.field = f;
    o.isolines = 0;
    image bigplain = render(m, &o);
    o.isolines = 3;
    image big = render(m, &o);
    uint32_t maxw = 0, w = 0;
    for (uint32_t x = 0; x < o.width; ++x) {
        const uint8_t *b = px(&big, x, 400), *a = px(&bigplain, x, 400);
        int dark = b[0] + b[1] + b[2] < 0.6 * (a[0] + a[1] + a[2]);
        w = dark ? w + 1 : 0;
        if (w > maxw) maxw = w;
    }
    CHECK_MSG(maxw >= 1 && maxw <= 3, "zoomed: isoline %u pixels wide", maxw);
    free(big.p);
    free(bigplain.p);
    free(f);
    gs_mesh_free(m);
}

/* A closed sphere: no background inside its silhouette, about the area of
 * a disc of radius 0.45 x the image, antialiased at its rim. */
static void test_sphere(void)
{
    gs_mesh *m = gen("sphere:3");
    double views[][2] = {{30, 20}, {0, 90}, {-123, -45}};
    for (size_t t = 0; t < 3; ++t) {
        gs_render_options o = opts(200, 200, views[t][0], views[t][1]);
        image im = render(m, &o);
        uint64_t holes = 0, area = 0, partial = 0;
        for (uint32_t y = 0; y < o.height; ++y) {
            int first = -1, last = -1;
            for (uint32_t x = 0; x < o.width; ++x)
                if (!is_bg(px(&im, x, y))) last = (int)x, first = first < 0 ? (int)x : first;
            for (int x = first; first >= 0 && x <= last; ++x) {
                const uint8_t *p = px(&im, (uint32_t)x, y);
                holes += is_bg(p);
                area++;
            }
            if (first >= 0) partial += px(&im, (uint32_t)first, y)[0] > 235;
        }
        CHECK_MSG(holes == 0, "view %g,%g: %llu background pixels inside the silhouette", views[t][0], views[t][1],
                  (unsigned long long)holes);
        double r = 0.45 * 200, want = 3.14159265358979 * r * r;
        CHECK_MSG(fabs((double)area - want) < 0.04 * want, "view %g,%g: area %llu, a disc of radius %g: %.0f",
                  views[t][0], views[t][1], (unsigned long long)area, r, want);
        CHECK_MSG(partial > 10, "no antialiased rim pixels (%llu)", (unsigned long long)partial);
        free(im.p);
    }
    gs_mesh_free(m);
}

/* Faces with an inf or NaN corner are neutral grey; the others coloured. */
static void test_unreachable(void)
{
    gs_mesh *m = gen("grid:11,11");
    uint32_t nv = gs_mesh_num_vertices(m);
    const double *xyz = gs_mesh_positions(m);
    double *f = malloc(nv * sizeof *f);
    for (uint32_t v = 0; v < nv; ++v) f[v] = xyz[3 * v] < 0.45 ? INFINITY : xyz[3 * v] + xyz[3 * v + 1];
    f[nv - 1] = NAN; /* corner (1, 1): top right */
    gs_render_options o = opts(200, 200, 0, 0);
    o.field = f;
    image im = render(m, &o);
    uint64_t grey = 0, bad = 0;
    for (uint32_t y = 12; y < 188; ++y)
        for (uint32_t x = 12; x < 80; ++x) { /* x < 0.38: faces with an inf corner */
            grey++;
            bad += !is_grey(px(&im, x, y));
        }
    CHECK_MSG(bad == 0 && grey > 0, "%llu of %llu pixels left of x = 0.4 are not grey", (unsigned long long)bad,
              (unsigned long long)grey);
    CHECK(is_grey(px(&im, 185, 15)) && !is_bg(px(&im, 185, 15))); /* the NaN corner's face */
    CHECK(!is_grey(px(&im, 150, 100)));
    CHECK(!is_grey(px(&im, 185, 185)));
    free(im.p);
    free(f);
    gs_mesh_free(m);
}

/* Orientation: y up, (0, 0) looks from +z with x right; (90, 0) from +x
 * (so +z is on the left); (0, 90) from +y (so -z is at the top). */
static void test_orientation(void)
{
    gs_mesh *m = gen("cube:4");
    uint32_t nv = gs_mesh_num_vertices(m);
    const double *xyz = gs_mesh_positions(m);
    double *f = malloc(nv * sizeof *f);
    struct {
        double az, el;
        int axis;
        int high_at; /* 0: right, 1: left, 2: top, 3: bottom */
    } cases[] = {{0, 0, 0, 0}, {0, 0, 1, 2}, {90, 0, 2, 1}, {0, 90, 2, 3}, {180, 0, 0, 1}, {0, 90, 0, 0}};
    for (size_t t = 0; t < sizeof cases / sizeof *cases; ++t) {
        for (uint32_t v = 0; v < nv; ++v) f[v] = xyz[3 * v + cases[t].axis];
        gs_render_options o = opts(200, 200, cases[t].az, cases[t].el);
        o.field = f;
        o.isolines = 0;
        image im = render(m, &o);
        const uint8_t *lo, *hi;
        uint32_t a = 40, b = 160, c = 100;
        switch (cases[t].high_at) {
        case 0: lo = px(&im, a, c), hi = px(&im, b, c); break;
        case 1: lo = px(&im, b, c), hi = px(&im, a, c); break;
        case 2: lo = px(&im, c, b), hi = px(&im, c, a); break;
        default: lo = px(&im, c, a), hi = px(&im, c, b); break;
        }
        /* viridis: yellow (high) has far more green than violet (low) */
        CHECK_MSG(hi[1] > lo[1] + 60, "view %g,%g, axis %d: low %u,%u,%u high %u,%u,%u", cases[t].az, cases[t].el,
                  cases[t].axis, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        free(im.p);
    }
    free(f);
    gs_mesh_free(m);
}

/* Dots: white inside a dark ring where visible; hidden behind the surface. */
static void test_points(void)
{
    gs_mesh *m = gen("sphere:3");
    double pts[6] = {0, 0, 1, 0, 0, -1}; /* front and back, seen from +z */
    gs_render_options o = opts(200, 200, 0, 0);
    o.points = pts;
    o.n_points = 1;
    image front = render(m, &o);
    /* where the point lands: the view is fitted to the vertices' extent */
    const double *xyz = gs_mesh_positions(m);
    double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
    for (uint32_t v = 0; v < gs_mesh_num_vertices(m); ++v)
        for (int k = 0; k < 2; ++k) lo[k] = fmin(lo[k], xyz[3 * v + k]), hi[k] = fmax(hi[k], xyz[3 * v + k]);
    double s = 180 / fmax(hi[0] - lo[0], hi[1] - lo[1]);
    double cx = 100 - s * 0.5 * (lo[0] + hi[0]), cy = 100 + s * 0.5 * (lo[1] + hi[1]);
    const uint8_t *c = px(&front, (uint32_t)cx, (uint32_t)cy);
    CHECK_MSG(c[0] == 255 && c[1] == 255 && c[2] == 255, "centre %u,%u,%u: expected the dot's white", c[0], c[1], c[2]);
    const uint8_t *ring = px(&front, (uint32_t)(cx + 3.75), (uint32_t)cy);
    CHECK_MSG(ring[0] < 60 && ring[1] < 60 && ring[2] < 60, "ring %u,%u,%u: expected dark", ring[0], ring[1], ring[2]);
    o.points = pts + 3;
    image back = render(m, &o);
    o.n_points = 0;
    image none = render(m, &o);
    CHECK(memcmp(back.p, none.p, (size_t)o.width * o.height * 3) == 0);
    free(front.p);
    free(back.p);
    free(none.p);
    gs_mesh_free(m);
}

/* Paths: a white line in a dark border along the polyline, hidden behind
 * the surface; the pixels of a face-on grid's middle line. */
static void test_paths(void)
{
    gs_mesh *m = gen("grid:11,11");
    /* the line y = 0.5 from x = 0.1 to 0.9 in three pieces, and a second
     * path: the vertical x = 0.25 from y = 0.6 to 0.9 */

    double pts2[18] = {0.1, 0.5, 0, 0.4, 0.5, 0, 0.6, 0.5, 0, 0.9, 0.5, 0, 0.25, 0.6, 0, 0.25, 0.9, 0};
    uint32_t starts[3] = {0, 4, 6};
    gs_render_options o = opts(200, 200, 0, 0);
    o.paths = pts2;
    o.path_starts = starts;
    o.n_paths = 2;

    image im = render(m, &o);
    o.n_paths = 0;
    image none = render(m, &o);
    /* the unit square spans 180 pixels: x = 10 + 180 u, y = 190 - 180 v */
    for (uint32_t x = 30; x <= 170; x += 20) {
        const uint8_t *c = px(&im, x, 100), *d = px(&im, x, 102), *e = px(&im, x, 104), *n = px(&none, x, 104);
        CHECK_MSG(c[0] == 255 && c[1] == 255 && c[2] == 255, "x %u: centre %u,%u,%u, expected white", x, c[0], c[1], c[2]);
        CHECK_MSG(d[0] < 40 && d[1] < 40 && d[2] < 40, "x %u: border %u,%u,%u, expected dark", x, d[0], d[1], d[2]);
        CHECK_MSG(!memcmp(e, n, 3), "x %u: beside the path %u,%u,%u, expected the surface", x, e[0], e[1], e[2]);
    }
    const uint8_t *v = px(&im, 55, 46), *beyond = px(&im, 55, 20), *nb = px(&none, 55, 20); /* (0.25, 0.8); (0.25, 0.95) */
    CHECK_MSG(v[0] == 255 && v[1] == 255 && v[2] == 255, "second path: %u,%u,%u, expected white", v[0], v[1], v[2]);
    CHECK(!memcmp(beyond, nb, 3));
    /* nothing else changes: the rows far from both paths are the same */
    for (uint32_t y = 130; y < 200; ++y) CHECK(!memcmp(px(&im, 0, y), px(&none, 0, y), 3 * 200));
    free(im.p);
    free(none.p);
    gs_mesh_free(m);
    /* behind a sphere: not drawn */
    m = gen("sphere:3");
    double back[6] = {-0.1, 0, -1, 0.1, 0, -1};
    uint32_t s2[2] = {0, 2};
    o = opts(120, 120, 0, 0);
    image a = render(m, &o);
    o.paths = back, o.path_starts = s2, o.n_paths = 1;
    image b = render(m, &o);
    CHECK(memcmp(a.p, b.p, (size_t)120 * 120 * 3) == 0);
    free(a.p);
    free(b.p);
    gs_mesh_free(m);
}

/* Separators: the tree accessors, and the root's (red) curve drawn
 * between the vertices of its two subtrees. */
static void test_separators(void)
{
    gs_mesh *m = gen("grid:24,24");
    gs_build_options bo;
    gs_build_options_default(&bo);
    bo.method = GS_METHOD_GRAPH;
    bo.threads = 1;
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs_db_build(m, &bo, &db, NULL, &err);
    CHECK_MSG(rc == GS_OK, "build: %s", err.message);
    if (rc) return gs_mesh_free(m);
    gs_db_info info;
    gs_db_get_info(db, &info, NULL);
    uint32_t nv = gs_mesh_num_vertices(m), parent = 0, depth = 7;
    CHECK(gs_db_tree_node(db, 0, &parent, &depth, NULL) == GS_OK && parent == GS_NONE && depth == 0);
    CHECK(gs_db_tree_node(db, info.n_nodes, &parent, &depth, &err) == GS_EARG && strstr(err.message, "out of range"));
    CHECK(gs_db_tree_node(NULL, 0, NULL, NULL, NULL) == GS_EARG);
    CHECK(gs_db_vertex_leaf(db, nv) == GS_NONE && gs_db_vertex_leaf(NULL, 0) == GS_NONE);
    /* each vertex's side of the root: its ancestor at depth 1 */
    int *side = malloc(nv * sizeof *side);
    uint32_t leaves_max_depth = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t n = gs_db_vertex_leaf(db, v), p, d, steps = 0, child = n;
        CHECK(n < info.n_nodes);
        gs_db_tree_node(db, n, &p, &d, NULL);
        if (d > leaves_max_depth) leaves_max_depth = d;
        while (p != GS_NONE && steps++ <= info.max_depth) child = n, n = p, gs_db_tree_node(db, n, &p, &d, NULL);
        CHECK(n == 0);
        side[v] = (int)child;
    }
    CHECK(leaves_max_depth == info.max_depth);
    gs_render_options o = opts(300, 300, 0, 0);
    o.separators = db;
    image im = render(m, &o);
    const double *xyz = gs_mesh_positions(m);
    uint64_t red = 0, stray = 0;
    for (uint32_t y = 0; y < o.height; ++y)
        for (uint32_t x = 0; x < o.width; ++x) {
            const uint8_t *p = px(&im, x, y);
            if (!(p[0] > 180 && p[1] < 40 && p[2] < 40)) continue;
            red++;
            /* pixel -> mesh: [0,1]^2 onto [15, 285] */
            double mx = (x + 0.5 - 15) / 270, my = (285 - (y + 0.5)) / 270, r = 2.0 / 23;
            int near[2] = {0, 0};
            for (uint32_t v = 0; v < nv; ++v) {
                double dx = xyz[3 * v] - mx, dy = xyz[3 * v + 1] - my;
                if (dx * dx + dy * dy < r * r) near[side[v] == side[0]] = 1;
            }
            stray += !(near[0] && near[1]);
        }
    CHECK_MSG(red > 100, "%llu red pixels (the root's separator)", (unsigned long long)red);
    CHECK_MSG(stray == 0, "%llu red pixels away from the root's split", (unsigned long long)stray);
    /* no separators: no red */
    o.separators = NULL;
    image plain = render(m, &o);
    uint64_t red0 = 0;
    for (size_t k = 0; k < (size_t)o.width * o.height; ++k)
        red0 += plain.p[3 * k] > 180 && plain.p[3 * k + 1] < 40 && plain.p[3 * k + 2] < 40;
    CHECK(red0 == 0);
    /* a database of another mesh */
    gs_mesh *other = gen("grid:24,24,2,1"), *small = gen("grid:5,5");
    uint8_t *buf = malloc(300 * 300 * 3);
    o.separators = db;
    memset(buf, 7, 300 * 300 * 3);
    CHECK(gs_render(other, &o, buf, &err) == GS_EARG && strstr(err.message, "separators") &&
          strstr(err.message, "vertex"));
    CHECK(gs_render(small, &o, buf, &err) == GS_EARG && strstr(err.message, "25"));
    CHECK(buf[0] == 7 && buf[300 * 300 * 3 - 1] == 7); /* untouched */
    free(buf);
    gs_mesh_free(other);
    gs_mesh_free(small);
    free(side);
    free(im.p);
    free(plain.p);
    gs_db_free(db);
    gs_mesh_free(m);
}

/* Extreme fields and mesh scales: drawn, never a crash or a NaN (the
 * sanitizer build checks the conversions). */
static void test_extremes(void)
{
    gs_mesh *g = gen("grid:9,9");
    uint32_t nv = gs_mesh_num_vertices(g), nf = gs_mesh_num_faces(g);
    double *f = malloc(nv * sizeof *f), *xyz = malloc(3 * nv * sizeof *xyz);
    for (uint32_t v = 0; v < nv; ++v) f[v] = v % 2 ? 1.7e308 : -1.7e308;
    gs_render_options o = opts(64, 64, 10, 10);
    o.field = f;
    image im = render(g, &o);
    CHECK(!is_bg(px(&im, 32, 32)));
    free(im.p);
    for (uint32_t v = 0; v < nv; ++v) f[v] = v == 3 ? 1e-300 : 0;
    im = render(g, &o);
    CHECK(!is_bg(px(&im, 32, 32)));
    free(im.p);
    double scales[] = {1e-45, 1e45};
    for (int t = 0; t < 2; ++t) {
        for (uint32_t i = 0; i < 3 * nv; ++i) xyz[i] = gs_mesh_positions(g)[i] * scales[t] + (i % 3 == 0 ? 1e3 * scales[t] : 0);
        gs_mesh *m = NULL;
        gs_error err = {0};
        CHECK_MSG(gs_mesh_create(xyz, nv, gs_mesh_faces(g), nf, &m, &err) == GS_OK, "%s", err.message);
        if (!m) continue;
        gs_render_options q = opts(100, 100, 0, 0);
        image a = render(m, &q);
        uint64_t n = 0;
        for (size_t k = 0; k < 100 * 100; ++k) n += !is_bg(a.p + 3 * k);
        CHECK_MSG(n == 90 * 90, "scale %g: %llu pixels drawn, expected 8100", scales[t], (unsigned long long)n);
        free(a.p);
        gs_mesh_free(m);
    }
    free(f);
    free(xyz);
    gs_mesh_free(g);
}

/* ---- PNG ------------------------------------------------------------------- */

static uint8_t *read_png(const char *path, uint32_t *w, uint32_t *h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path)) return NULL;
    img.format = PNG_FORMAT_RGB;
    uint8_t *buf = malloc(PNG_IMAGE_SIZE(img));
    if (!buf || !png_image_finish_read(&img, NULL, buf, 0, NULL)) {
        free(buf);
        png_image_free(&img);
        return NULL;
    }
    *w = img.width, *h = img.height;
    return buf;
}

static int n_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d) closedir(d);
    return n;
}

static void test_png(void)
{
    gs_mesh *m = gen("torus:32,16");
    uint32_t nv = gs_mesh_num_vertices(m);
    double *f = malloc(nv * sizeof *f);
    for (uint32_t v = 0; v < nv; ++v) f[v] = v % 7 == 0 ? INFINITY : sin(0.1 * v);
    gs_render_options o = opts(123, 77, 10, 40);
    o.field = f;
    image im = render(m, &o);
    char dir[] = "/tmp/geosep-render.XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256], bad[300];
    snprintf(path, sizeof path, "%s/t.png", dir);
    gs_error err = {0};
    int rc = gs_render_png(m, &o, path, &err);
    CHECK_MSG(rc == GS_OK, "png: %s", err.message);
    uint32_t w = 0, h = 0;
    uint8_t *back = read_png(path, &w, &h);
    CHECK(back && w == o.width && h == o.height);
    if (back) CHECK(memcmp(back, im.p, (size_t)w * h * 3) == 0);
    free(back);
    CHECK(n_entries(dir) == 1);
    /* overwrite: the new picture replaces the old one */
    o.width = 50;
    CHECK(gs_render_png(m, &o, path, &err) == GS_OK);
    back = read_png(path, &w, &h);
    CHECK(back && w == 50);
    free(back);
    CHECK(n_entries(dir) == 1);
    /* failures leave nothing: a missing folder, a folder as the path, a
     * bad option (the old file kept as it was) */
    snprintf(bad, sizeof bad, "%s/missing/t.png", dir);
    CHECK(gs_render_png(m, &o, bad, &err) == GS_EIO && strstr(err.message, "missing/t.png"));
    CHECK(gs_render_png(m, &o, dir, &err) == GS_EIO && strstr(err.message, "not a regular file"));
    o.width = 5;
    CHECK(gs_render_png(m, &o, path, &err) == GS_EARG);
    back = read_png(path, &w, &h);
    CHECK(back && w == 50);
    free(back);
    CHECK(n_entries(dir) == 1);
    o.width = 50;
    CHECK(gs_render_png(m, &o, NULL, &err) == GS_EARG);
    CHECK(gs_render_png(m, &o, "", &err) == GS_EARG);
    unlink(path);
    rmdir(dir);
    free(im.p);
    free(f);
    gs_mesh_free(m);
}

/* ---- bad arguments ---------------------------------------------------------- */

static void expect_earg(const gs_mesh *m, const gs_render_options *o, uint8_t *buf, const char *what)
{
    gs_error err = {0};
    memset(buf, 7, 64 * 64 * 3);
    int rc = gs_render(m, o, buf, &err);
    CHECK_MSG(rc == GS_EARG && strstr(err.message, what), "%s: rc %d, '%s'", what, rc, err.message);
    CHECK(buf[0] == 7);
}

static void test_bad_args(void)
{
    gs_mesh *m = gen("grid:3,3");
    uint8_t *buf = malloc(64 * 64 * 3);
    gs_render_options o = opts(64, 64, 0, 0);
    gs_error err = {0};
    CHECK(gs_render(m, &o, buf, &err) == GS_OK);
    CHECK(gs_render(m, &o, NULL, &err) == GS_EARG && strstr(err.message, "rgb"));
    expect_earg(NULL, &o, buf, "mesh");
    expect_earg(m, NULL, buf, "options");
    uint32_t sizes[][2] = {{15, 64}, {64, 15}, {0, 64}, {8193, 64}, {64, 8193}, {UINT32_MAX, 64}};
    for (size_t t = 0; t < 6; ++t) {
        gs_render_options b = o;
        b.width = sizes[t][0], b.height = sizes[t][1];
        expect_earg(m, &b, buf, "size");
    }
    double bad_angles[] = {NAN, INFINITY, -INFINITY};
    for (int t = 0; t < 3; ++t) {
        gs_render_options b = o;
        b.azimuth_deg = bad_angles[t];
        expect_earg(m, &b, buf, "azimuth");
        b = o;
        b.elevation_deg = bad_angles[t];
        expect_earg(m, &b, buf, "elevation");
    }
    gs_render_options b = o;
    b.isolines = GS_RENDER_MAX_ISOLINES + 1;
    expect_earg(m, &b, buf, "isolines");
    b = o;
    b.n_points = 2;
    expect_earg(m, &b, buf, "points is NULL");
    double pts[6] = {0, 0, 0, 1, NAN, 0};
    b.points = pts;
    expect_earg(m, &b, buf, "point 1");
    pts[4] = INFINITY;
    expect_earg(m, &b, buf, "point 1");
    b.n_points = 1;
    CHECK(gs_render(m, &b, buf, &err) == GS_OK);
    {
        gs_render_options c = o;
        double pp[6] = {0, 0, 0, 1, 1, 0};
        uint32_t st[2] = {0, 2}, bad_st[2] = {1, 2}, down[3] = {0, 2, 1};
        c.n_paths = 1;
        expect_earg(m, &c, buf, "paths or path_starts is NULL");
        c.paths = pp, c.path_starts = bad_st;
        expect_earg(m, &c, buf, "path_starts[0] is 1");
        c.path_starts = down, c.n_paths = 2;
        expect_earg(m, &c, buf, "path_starts[1] is 2, path_starts[2] 1");
        c.path_starts = st, c.n_paths = 1;
        CHECK(gs_render(m, &c, buf, &err) == GS_OK);
        pp[4] = NAN;
        expect_earg(m, &c, buf, "path point 1");
    }
    double far[6] = {-1e300, 1e300, 1e300, 1e300, -1e300, -1e300}; /* far off: not drawn, no crash */
    b.points = far;
    b.n_points = 2;
    CHECK(gs_render(m, &b, buf, &err) == GS_OK);
    /* the largest size works (1x1 supersampling) and angles far out too */
    b = opts(GS_RENDER_MAX_SIZE, GS_RENDER_MIN_SIZE, 1e6, -1e6);
    uint8_t *wide = malloc((size_t)b.width * b.height * 3);
    CHECK(gs_render(m, &b, wide, &err) == GS_OK);
    free(wide);
    gs_render_options_default(NULL); /* no crash */
    gs_render_options d;
    gs_render_options_default(&d);
    CHECK(d.width == 640 && d.height == 480 && d.field == NULL && d.separators == NULL && d.n_points == 0);
    free(buf);
    gs_mesh_free(m);
}

int main(void)
{
    test_square_area();
    test_constant_field();
    test_isolines();
    test_sphere();
    test_unreachable();
    test_orientation();
    test_points();
    test_paths();
    test_separators();
    test_extremes();
    test_png();
    test_bad_args();
    return gs__test_finish("test_render");
}
