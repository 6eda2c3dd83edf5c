/* fuzz_mesh.c - one mesh reader (FUZZ_FORMAT: GS_FORMAT_OBJ, _OFF, _PLY or
 * _STL; built once per format) on arbitrary bytes, through both of its
 * users: gs_mesh_load's path (read, validate, build) and
 * gs_mesh_repair_file's (read, repair). Never a crash; a failure is a
 * parse/mesh/limit error with a message; a loaded mesh has a report and
 * validates again from its arrays; a repaired mesh validates
 * (gs_mesh_create), keeps every input vertex's id and position, and its
 * report's maps stay in range. */
#include "geosep.h"
#include "mesh/io_internal.h"
#include "fuzz_check.h"

#include <string.h>

#ifndef FUZZ_FORMAT
#error "FUZZ_FORMAT must name the reader"
#endif

static void check_failure(int rc, const gs_error *err)
{
    if (!(rc == GS_EPARSE || rc == GS_EMESH || rc == GS_EFORMAT || rc == GS_ELIMIT || rc == GS_ENOMEM) || !err->message[0])
        fprintf(stderr, "failure %d (%s): %s\n", rc, gs_status_string(rc), err->message);
    FUZZ_CHECK(rc == GS_EPARSE || rc == GS_EMESH || rc == GS_EFORMAT || rc == GS_ELIMIT || rc == GS_ENOMEM);
    FUZZ_CHECK(err->message[0] != 0);
}

static void check_loaded(const gs_mesh *m)
{
    uint32_t nv = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    FUZZ_CHECK(nf > 0);
    gs_mesh_report rep;
    FUZZ_CHECK(gs_mesh_get_report(m, &rep, NULL) == GS_OK);
    FUZZ_CHECK(rep.n_vertices == nv && rep.n_faces == nf);
    gs_mesh *again = NULL;
    gs_error err = {0};
    FUZZ_CHECK(gs_mesh_create(gs_mesh_positions(m), nv, gs_mesh_faces(m), nf, &again, &err) == GS_OK);
    gs_mesh_free(again);
}

static void check_repaired(const gs_mesh *m, const gs_repair *r, const gs__soup *in)
{
    uint32_t nv = gs_mesh_num_vertices(m), nf = gs_mesh_num_faces(m);
    const double *xyz = gs_mesh_positions(m);
    gs_mesh *again = NULL;
    gs_error err = {0};
    int rc = gs_mesh_create(xyz, nv, gs_mesh_faces(m), nf, &again, &err);
    if (rc) fprintf(stderr, "repaired mesh does not validate: %s\n", err.message);
    FUZZ_CHECK(rc == GS_OK);
    gs_mesh_free(again);
    FUZZ_CHECK(r->n_vertices == nv && r->n_faces == nf);
    FUZZ_CHECK(r->n_input_vertices == in->nv && r->n_input_faces == in->nf);
    FUZZ_CHECK(nv >= in->nv);
    FUZZ_CHECK(memcmp(xyz, in->xyz, 3 * sizeof(double) * in->nv) == 0);
    for (uint32_t v = 0; v < in->nv; ++v) {
        FUZZ_CHECK(r->vertex_map[v] < nv);
        FUZZ_CHECK(r->alias_start[v] < r->alias_start[v + 1]);
        FUZZ_CHECK(r->alias[r->alias_start[v]] == r->vertex_map[v]);
        for (uint32_t k = r->alias_start[v]; k < r->alias_start[v + 1]; ++k) FUZZ_CHECK(r->alias[k] < nv);
    }
    for (uint32_t w = 0; w < nv; ++w) {
        uint32_t o = r->vertex_origin[w];
        FUZZ_CHECK(o < in->nv && (w >= in->nv || o == w));
        FUZZ_CHECK(memcmp(xyz + 3 * (size_t)w, in->xyz + 3 * (size_t)o, 3 * sizeof(double)) == 0);
    }
    for (uint32_t f = 0; f < nf; ++f) FUZZ_CHECK(r->face_origin[f] < in->nf && r->face_change[f] <= 2);
    char buf[256];
    size_t len = gs_repair_format(r, buf, sizeof buf);
    FUZZ_CHECK(len > 0 && strlen(buf) == (len < sizeof buf ? len : sizeof buf - 1));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gs_error err = {0};
    gs_mesh *m = NULL;
    int rc = gs__mesh_load_memory(FUZZ_NAME, data, size, FUZZ_FORMAT, &m, &err);
    if (rc == GS_OK)
        check_loaded(m);
    else {
        FUZZ_CHECK(m == NULL);
        check_failure(rc, &err);
    }
    gs_mesh_free(m);

    /* the repair path reads the same soup */
    gs__soup s;
    gs_error serr = {0};
    int src = gs__load_soup_memory(FUZZ_NAME, data, size, FUZZ_FORMAT, &s, &serr);
    if (src) check_failure(src, &serr);
    gs_repair *info = NULL;
    m = NULL;
    memset(&err, 0, sizeof err);
    rc = gs__mesh_repair_memory(FUZZ_NAME, data, size, FUZZ_FORMAT, &m, &info, &err);
    if (src) {
        FUZZ_CHECK(rc == src); /* the reader's failure */
    } else if (rc == GS_OK) {
        check_repaired(m, info, &s);
    } else {
        check_failure(rc, &err);
        FUZZ_CHECK(m == NULL && info == NULL);
    }
    gs_mesh_free(m);
    gs_repair_free(info);
    if (!src) gs__soup_free(&s);
    return 0;
}
