/* write_obj.c - gs_mesh_save_obj: "%.17g" positions (bit-exact round trip)
 * and 1-based faces, written to a temporary file in the target folder and
 * renamed over the target, so a failure never leaves a partial file. */
#include "io_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* mkstemp creates the file 0600; give it the mode of the file it replaces,
 * or 0644 for a new file (the umask cannot be read without changing it). */
static void set_mode(int fd, const char *path)
{
    struct stat st;
    mode_t mode = 0644;
    if (stat(path, &st) == 0) mode = st.st_mode & 07777;
    (void)fchmod(fd, mode);
}

static int save_fail(gs_error *err, const char *path, const char *what, int e)
{
    char buf[128];
    if (strerror_r(e, buf, sizeof buf) != 0) snprintf(buf, sizeof buf, "error %d", e);
    return gs__fail(err, GS_EIO, "%s: %s: %s", path, what, buf);
}

int gs_mesh_save_obj(const gs_mesh *mesh, const char *path, gs_error *err)
{
    if (!mesh || !path) return gs__fail(err, GS_EARG, "gs_mesh_save_obj: NULL argument");
    size_t n = strlen(path);
    char *tmp = gs__malloc(n + 16, 1);
    if (!tmp) return gs__fail(err, GS_ENOMEM, "%s: out of memory", path);
    memcpy(tmp, path, n);
    memcpy(tmp + n, ".tmp.XXXXXX", 12);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        int rc = save_fail(err, path, "cannot create a temporary file", errno);
        free(tmp);
        return rc;
    }
    set_mode(fd, path);
    FILE *f = fdopen(fd, "w");
    int rc = GS_OK;
    if (!f) {
        rc = save_fail(err, path, "cannot open the temporary file", errno);
        close(fd);
    } else {
        errno = 0;
        int bad = write_body(f, mesh) != 0 || ferror(f);
        int e = errno;
        if (fclose(f) != 0 && !bad) {
            bad = 1;
            e = errno;
        }
        if (bad) rc = save_fail(err, path, "cannot write", e ? e : EIO);
    }
    if (rc == GS_OK && rename(tmp, path) != 0)
        rc = save_fail(err, path, "cannot rename the temporary file into place", errno);
    if (rc) unlink(tmp);
    free(tmp);
    return rc;
}
