/* write_obj.c - gs_mesh_save_obj: "%.17g" positions (bit-exact round trip)
 * and 1-based faces, written to a temporary file in the target folder and
 * renamed over the target, so a failure never leaves a partial file. */
#include "io_internal.h"
#include "../io/atomic_file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int write_body(FILE *f, const gs_mesh *m)
{
    if (fprintf(f, "# geosep %s: %u vertices, %u faces\n", gs_version_string(), m->nv,
                m->nf) < 0)
        return -1;
    for (uint32_t v = 0; v < m->nv; ++v) {
        const double *p = m->xyz + 3 * (size_t)v;
        if (fprintf(f, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]) < 0) return -1;
    }
    for (uint32_t t = 0; t < m->nf; ++t) {
        const uint32_t *c = m->tri + 3 * (size_t)t;
        if (fprintf(f, "f %lu %lu %lu\n", (unsigned long)c[0] + 1, (unsigned long)c[1] + 1,
                    (unsigned long)c[2] + 1) < 0)
            return -1;
    }
    return 0;
}

int gs_mesh_save_obj(const gs_mesh *mesh, const char *path, gs_error *err)
{
    if (!mesh || !path) return gs__fail(err, GS_EARG, "gs_mesh_save_obj: NULL argument");
    gs__atomic_file af;
    int rc = gs__atomic_open(&af, path, err);
    if (rc) return rc;
    if (write_body(af.fp, mesh) != 0) {
        int e = errno;
        gs__atomic_abort(&af);
        return gs__fail(err, GS_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    return gs__atomic_commit(&af, err);
}
