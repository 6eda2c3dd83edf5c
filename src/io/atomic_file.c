/* atomic_file.c - temporary-file-then-rename writing (see atomic_file.h). */
#include "atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int gs__atomic_open(gs__atomic_file *af, const char *path, gs_error *err)
{
    memset(af, 0, sizeof *af);
    /* the rename would replace whatever the path names: a device, a pipe or
     * a folder is refused, never swapped for a regular file (a symbolic
     * link is followed for this check; the rename replaces the link) */
    struct stat old;
    if (stat(path, &old) == 0 && !S_ISREG(old.st_mode))
        return gs__fail(err, GS_EIO, "%s: exists and is not a regular file (not replaced)", path);
    size_t n = strlen(path);
    af->final_path = gs__malloc(n + 1, 1);
    af->tmp_path = gs__malloc(n + 12, 1);
    if (!af->final_path || !af->tmp_path) {
        gs__atomic_abort(af);
        return gs__fail(err, GS_ENOMEM, "%s: out of memory", path);
    }
    memcpy(af->final_path, path, n + 1);
    memcpy(af->tmp_path, path, n);
    memcpy(af->tmp_path + n, ".tmp.XXXXXX", 12);
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL;
        gs__atomic_abort(af);
        return gs__fail(err, GS_EIO, "%s: cannot create a temporary file: %s", path, strerror(e));
    }
    /* mkstemp creates the file 0600: give it the mode of the file it
     * replaces, or 0644 for a new one (reading the umask would change it). */
    struct stat st;
    (void)fchmod(fd, stat(path, &st) == 0 ? (st.st_mode & 07777) : 0644);
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        close(fd);
        gs__atomic_abort(af);
        return gs__fail(err, GS_EIO, "%s: cannot open for writing", path);
    }
    return GS_OK;
}

void gs__atomic_abort(gs__atomic_file *af)
{
    if (af->fp) fclose(af->fp);
    if (af->tmp_path) remove(af->tmp_path);
    free(af->tmp_path);
    free(af->final_path);
    memset(af, 0, sizeof *af);
}

int gs__atomic_commit(gs__atomic_file *af, gs_error *err)
{
    int bad = fflush(af->fp) != 0 || ferror(af->fp);
    bad |= fclose(af->fp) != 0;
    af->fp = NULL;
    if (bad || rename(af->tmp_path, af->final_path) != 0) {
        int e = errno;
        int rc = gs__fail(err, GS_EIO, "%s: cannot write: %s", af->final_path, strerror(e));
        gs__atomic_abort(af);
        return rc;
    }
    free(af->tmp_path);
    free(af->final_path);
    memset(af, 0, sizeof *af);
    return GS_OK;
}
