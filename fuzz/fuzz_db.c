/* fuzz_db.c - the database reader on arbitrary bytes, through the public
 * API only (the format may change; the promises do not): gs_db_open_memory,
 * and gs_db_open on the same bytes written to a file. An opened database is
 * then queried with vertex ids taken from the input (in range and out of
 * range): pairs, batches, fields, surface points, the tree. Never a crash
 * or a read outside the buffer. From the memory-opened database (checked
 * in full): a distance between vertices in range is >= 0 or +inf, never
 * NaN; ids out of range give NaN (gs_db_distance) or GS_EARG (batches,
 * fields); batches answer as single queries, bit for bit; two vertices as
 * surface points answer as gs_db_distance; queries by input id (the alias
 * section) answer >= 0 or +inf in range, NaN / GS_EARG out of it. */
#include "geosep.h"
#include "fuzz_check.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char g_path[64];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    snprintf(g_path, sizeof g_path, "/tmp/geosep-fuzz-db-%ld.db", (long)getpid());
    return 0;
}

static uint32_t id_from(const uint8_t *data, size_t size, size_t k, uint32_t n)
{
    /* a byte near the end of the input picks the id: mostly in range, one
     * value in eight just out of it */
    uint32_t b = size ? data[(size - 1 - k % size)] : 0;
    if ((b & 7) == 7) return n + (b >> 3);
    return n ? (uint32_t)(((uint64_t)b * 2654435761u + k) % n) : 0;
}

static void query(const gs_db *db, const uint8_t *data, size_t size, int strict)
{
    gs_db_info info;
    FUZZ_CHECK(gs_db_get_info(db, &info, NULL) == GS_OK);
    uint32_t n = info.n_vertices;
    FUZZ_CHECK(gs_db_positions(db) != NULL || n == 0);
    uint32_t pairs[16];
    double out[8];
    for (int k = 0; k < 8; ++k) {
        uint32_t x = id_from(data, size, 2 * (size_t)k, n), y = id_from(data, size, 2 * (size_t)k + 1, n);
        pairs[2 * k] = x, pairs[2 * k + 1] = y;
        double d = gs_db_distance(db, x, y);
        if (x >= n || y >= n)
            FUZZ_CHECK(isnan(d));
        else if (strict) {
            FUZZ_CHECK(!isnan(d) && d >= 0);
            double p = gs_db_point_distance(db, &(gs_surface_point){{x, x, x}, {1, 0, 0}},
                                            &(gs_surface_point){{y, y, y}, {1, 0, 0}});
            FUZZ_CHECK(memcmp(&p, &d, sizeof d) == 0);
        }
        (void)gs_db_vertex_leaf(db, x);
    }
    gs_error err = {0};
    int rc = gs_db_distances(db, pairs, 8, out, &err);
    int any_out = 0;
    for (int k = 0; k < 16; ++k) any_out |= pairs[k] >= n;
    if (strict) {
        FUZZ_CHECK(any_out ? rc == GS_EARG : rc == GS_OK);
        if (rc == GS_OK)
            for (int k = 0; k < 8; ++k) {
                double d = gs_db_distance(db, pairs[2 * k], pairs[2 * k + 1]);
                FUZZ_CHECK(memcmp(&d, &out[k], sizeof d) == 0);
            }
    }
    /* a point of three corners with weights from the input */
    gs_surface_point p = gs_surface_point_make(pairs[0], pairs[1], pairs[2], 0.5, 0.25, 0.25);
    gs_surface_point q = gs_surface_point_make(pairs[3], pairs[4], pairs[5], 0.2, 0.3, 0.5);
    double pq = gs_db_point_distance(db, &p, &q);
    if (strict && gs_db_point_check(db, &p, NULL) == GS_OK && gs_db_point_check(db, &q, NULL) == GS_OK)
        FUZZ_CHECK(!isnan(pq) && pq >= 0);
    if (n > 0 && n <= (1u << 16)) {
        double *f = malloc(n * sizeof *f);
        FUZZ_CHECK(f != NULL);
        uint32_t x = pairs[0];
        rc = gs_db_field(db, x, f, &err);
        if (strict) {
            FUZZ_CHECK(x >= n ? rc == GS_EARG : rc == GS_OK);
            for (uint32_t y = 0; rc == GS_OK && y < n; ++y) FUZZ_CHECK(!isnan(f[y]) && f[y] >= 0);
        }
        if (gs_db_point_check(db, &p, NULL) == GS_OK) {
            rc = gs_db_point_field(db, &p, f, &err);
            if (strict) FUZZ_CHECK(rc == GS_OK);
        }
        free(f);
    }
    /* by input id (the alias section, or the vertex ids without it) */
    uint32_t ni = gs_db_num_input_vertices(db), al[8];
    FUZZ_CHECK(ni <= n);
    for (int k = 0; k < 4; ++k) {
        uint32_t x = id_from(data, size, 16 + 2 * (size_t)k, ni), y = id_from(data, size, 17 + 2 * (size_t)k, ni);
        double d = gs_db_input_distance(db, x, y);
        uint32_t na = gs_db_input_aliases(db, x, al, 8);
        if (x >= ni || y >= ni) {
            FUZZ_CHECK(isnan(d));
        } else {
            FUZZ_CHECK(na >= 1);
            for (uint32_t i = 0; i < na && i < 8; ++i) FUZZ_CHECK(al[i] < n);
            if (strict) FUZZ_CHECK(!isnan(d) && d >= 0);
        }
        if (x >= ni) FUZZ_CHECK(na == 0);
    }
    if (ni > 0 && ni <= (1u << 16)) {
        double *f = malloc(ni * sizeof *f);
        FUZZ_CHECK(f != NULL);
        uint32_t x = id_from(data, size, 30, ni);
        rc = gs_db_input_field(db, x, f, &err);
        FUZZ_CHECK(x >= ni ? rc == GS_EARG : (rc == GS_OK || rc == GS_ENOMEM));
        for (uint32_t y = 0; strict && rc == GS_OK && y < ni; ++y) FUZZ_CHECK(!isnan(f[y]) && f[y] >= 0);
        free(f);
    }
    for (uint32_t node = 0; node < info.n_nodes && node < 4096; ++node) {
        uint32_t parent, depth;
        FUZZ_CHECK(gs_db_tree_node(db, node, &parent, &depth, NULL) == GS_OK);
        FUZZ_CHECK(node == 0 ? parent == GS_NONE : parent < node);
    }
    FUZZ_CHECK(gs_db_tree_node(db, info.n_nodes, NULL, NULL, NULL) == GS_EARG);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gs_db *db = NULL;
    gs_error err = {0};
    int rc = gs_db_open_memory(data, size, &db, &err);
    if (rc == GS_OK) {
        query(db, data, size, 1);
        gs_db_free(db);
    } else {
        FUZZ_CHECK(db == NULL && err.message[0]);
    }
    /* the file path (memory-mapped; it may check less at open) */
    FILE *f = fopen(g_path, "wb");
    if (!f) return 0;
    int ok = fwrite(data, 1, size, f) == size;
    ok &= fclose(f) == 0;
    db = NULL;
    if (ok && gs_db_open(g_path, &db, &err) == GS_OK) {
        query(db, data, size, 0);
        gs_db_free(db);
    }
    unlink(g_path);
    return 0;
}
