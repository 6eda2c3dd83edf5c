/* fuzz_repair.c - gs_mesh_repair on arbitrary triangle soups. Input bytes:
 *   [0]   number of vertices - 3 (mod 61: 3..63)
 *   [1]   flags: bit 0 raw doubles (8 bytes per coordinate, any value)
 *         instead of one byte per coordinate from a small table (so that
 *         positions coincide, faces are collinear or tiny)
 *   then the coordinates, then the faces: three bytes each (mod the
 *   vertex count; faces repeating a vertex are allowed), at most 400.
 * Checks: a repaired mesh validates (gs_mesh_create succeeds on its
 * arrays), keeps every input vertex's id and position, and its report's
 * maps are in range; a failure is GS_EMESH with a message; a soup with a
 * non-finite coordinate fails. */
#include "geosep.h"
#include "fuzz_check.h"

#include <math.h>
#include <string.h>

static const double table[16] = {0.0, 1.0, 2.0, 0.5, -1.0, 3.0, 1e-7, 1.0 + 1e-12,
                                 0.25, 4.0, -0.5, 1e-3, 10.0, 0.75, 1.5, 2.5};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2) return 0;
    uint32_t nv = 3 + data[0] % 61;
    int raw = data[1] & 1;
    size_t at = 2;
    double xyz[3 * 64];
    int finite = 1;
    for (uint32_t i = 0; i < 3 * nv; ++i) {
        if (raw) {
            if (at + 8 > size) return 0;
            memcpy(&xyz[i], data + at, 8);
            at += 8;
        } else {
            if (at >= size) return 0;
            xyz[i] = table[data[at++] & 15];
        }
        finite &= isfinite(xyz[i]) != 0;
    }
    uint32_t tri[3 * 400], nf = 0;
    for (; nf < 400 && at + 3 <= size; ++nf, at += 3)
        for (int k = 0; k < 3; ++k) tri[3 * nf + k] = data[at + k] % nv;
    if (nf == 0) return 0;

    gs_mesh *m = NULL;
    gs_repair *r = NULL;
    gs_error err = {0};
    int rc = gs_mesh_repair(xyz, nv, tri, nf, &m, &r, &err);
    if (rc) {
        FUZZ_CHECK(rc == GS_EMESH && err.message[0] && !m && !r);
        return 0;
    }
    FUZZ_CHECK(finite);
    uint32_t onv = gs_mesh_num_vertices(m), onf = gs_mesh_num_faces(m);
    const double *oxyz = gs_mesh_positions(m);
    gs_mesh *again = NULL;
    rc = gs_mesh_create(oxyz, onv, gs_mesh_faces(m), onf, &again, &err);
    if (rc) fprintf(stderr, "repaired mesh does not validate: %s\n", err.message);
    FUZZ_CHECK(rc == GS_OK);
    gs_mesh_free(again);
    FUZZ_CHECK(onv >= nv && r->n_vertices == onv && r->n_faces == onf && onf > 0);
    FUZZ_CHECK(r->n_input_vertices == nv && r->n_input_faces == nf);
    FUZZ_CHECK(memcmp(oxyz, xyz, 3 * sizeof(double) * nv) == 0);
    for (uint32_t v = 0; v < nv; ++v) {
        FUZZ_CHECK(r->vertex_map[v] < onv);
        FUZZ_CHECK(r->alias_start[v] < r->alias_start[v + 1]);
        FUZZ_CHECK(r->alias[r->alias_start[v]] == r->vertex_map[v]);
        for (uint32_t k = r->alias_start[v]; k < r->alias_start[v + 1]; ++k) FUZZ_CHECK(r->alias[k] < onv);
    }
    for (uint32_t w = 0; w < onv; ++w) {
        uint32_t o = r->vertex_origin[w];
        FUZZ_CHECK(o < nv && (w >= nv || o == w));
        FUZZ_CHECK(memcmp(oxyz + 3 * (size_t)w, xyz + 3 * (size_t)o, 3 * sizeof(double)) == 0);
    }
    for (uint32_t f = 0; f < onf; ++f) FUZZ_CHECK(r->face_origin[f] < nf && r->face_change[f] <= 2);
    char buf[128];
    FUZZ_CHECK(gs_repair_format(r, buf, sizeof buf) > 0);
    gs_mesh_free(m);
    gs_repair_free(r);
    return 0;
}
