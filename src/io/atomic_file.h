/* atomic_file.h - write a file under a temporary name in the same folder and
 * rename it into place on commit, so that readers never see a partial file
 * and a failure leaves nothing behind. */
#ifndef GS_ATOMIC_FILE_H
#define GS_ATOMIC_FILE_H

#include "../core/internal.h"
#include <stdio.h>

typedef struct gs__atomic_file {
    FILE *fp;
    char *final_path;
    char *tmp_path;
} gs__atomic_file;

/* Create "<path>.tmp.XXXXXX" and open it for writing. GS_EIO when path
 * exists and is not a regular file (device, pipe, folder: never replaced). */
int gs__atomic_open(gs__atomic_file *af, const char *path, gs_error *err);
/* Flush, close and rename to the final path (on failure: remove the temp). */
int gs__atomic_commit(gs__atomic_file *af, gs_error *err);
/* Close and remove the temporary file. */
void gs__atomic_abort(gs__atomic_file *af);

#endif
