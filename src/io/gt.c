/* gt.c - reader and writer of GEOGT1 ground-truth distance files (exact
 * distances from a list of sources to every vertex; doc/file-formats.md). */
#include "../core/internal.h"
#include "atomic_file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const unsigned char gt_magic[8] = {'G', 'E', 'O', 'G', 'T', '1', 0, 0};

static uint32_t get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double get_f64(const unsigned char *p)
{
    uint64_t u = 0;
    for (int i = 7; i >= 0; --i) u = u << 8 | p[i];
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; ++i) p[i] = (unsigned char)(v >> (8 * i));
}

static void put_f64(unsigned char *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    for (int i = 0; i < 8; ++i) p[i] = (unsigned char)(u >> (8 * i));
}

void gs_gt_free(gs_gt *gt)
{
    if (!gt) return;
    free(gt->sources);
    free(gt->dist);
    free(gt);
}

int gs_gt_read(const char *path, gs_gt **out, gs_error *err)
{
    if (!out || !path) return gs__fail(err, GS_EARG, "gs_gt_read: NULL argument");
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) return gs__fail(err, GS_EIO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) { /* a folder "opens" and has size LONG_MAX */
        fclose(f);
        return gs__fail(err, GS_EIO, "%s: not a regular file", path);
    }
    int rc = GS_OK;
    gs_gt *gt = NULL;
    unsigned char head[16], *rec = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0) size = ftell(f);
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        rc = gs__fail(err, GS_EIO, "%s: cannot determine the file size", path);
        goto done;
    }
    if (size < 16 || fread(head, 1, 16, f) != 16) {
        rc = gs__fail(err, GS_EPARSE, "%s: too short for a GEOGT1 header (%ld bytes)", path, size);
        goto done;
    }
    if (memcmp(head, gt_magic, 8) != 0) {
        rc = gs__fail(err, GS_EPARSE, "%s: bad magic (not a GEOGT1 file)", path);
        goto done;
    }
    uint32_t n = get_u32(head + 8), k = get_u32(head + 12);
    uint64_t rec_size = 4 + 8 * (uint64_t)n;
    if (n == 0 || (uint64_t)size != 16 + (uint64_t)k * rec_size) {
        rc = gs__fail(err, GS_EPARSE,
                      "%s: header says %u vertices and %u sources, which needs %llu bytes, but the "
                      "file has %ld",
                      path, n, k, (unsigned long long)(16 + (uint64_t)k * rec_size), size);
        goto done;
    }
    gt = gs__calloc(1, sizeof *gt);
    rec = gs__malloc(rec_size, 1);
    if (!gt || !rec) {
        rc = gs__fail(err, GS_ENOMEM, "%s: out of memory", path);
        goto done;
    }
    gt->n_vertices = n;
    gt->n_sources = k;
    gt->sources = gs__malloc(k, sizeof *gt->sources);
    gt->dist = gs__malloc((size_t)k * n, sizeof *gt->dist);
    if (!gt->sources || !gt->dist) {
        rc = gs__fail(err, GS_ENOMEM, "%s: out of memory for %u x %u distances", path, k, n);
        goto done;
    }
    for (uint32_t j = 0; j < k; ++j) {
        if (fread(rec, 1, rec_size, f) != rec_size) {
            rc = gs__fail(err, GS_EIO, "%s: read error in record %u", path, j);
            goto done;
        }
        gt->sources[j] = get_u32(rec);
        if (gt->sources[j] >= n) {
            rc = gs__fail(err, GS_EPARSE, "%s: record %u: source vertex %u out of range (%u vertices)",
                          path, j, gt->sources[j], n);
            goto done;
        }
        double *row = gt->dist + (size_t)j * n;
        for (uint32_t i = 0; i < n; ++i) row[i] = get_f64(rec + 4 + 8 * (size_t)i);
    }
done:
    fclose(f);
    free(rec);
    if (rc) {
        gs_gt_free(gt);
        return rc;
    }
    *out = gt;
    return GS_OK;
}

int gs_gt_write(const char *path, uint32_t n, uint32_t k, const uint32_t *sources,
                const double *dist, gs_error *err)
{
    if (!path || (k && (!sources || !dist)))
        return gs__fail(err, GS_EARG, "gs_gt_write: NULL argument");
    if (n == 0) return gs__fail(err, GS_EARG, "gs_gt_write: no vertices");
    for (uint32_t j = 0; j < k; ++j)
        if (sources[j] >= n)
            return gs__fail(err, GS_EARG, "gs_gt_write: source %u is vertex %u, out of range (%u)",
                            j, sources[j], n);
    gs__atomic_file af;
    int rc = gs__atomic_open(&af, path, err);
    if (rc) return rc;
    unsigned char head[16], *rec = gs__malloc(4 + 8 * (size_t)n, 1);
    if (!rec) {
        gs__atomic_abort(&af);
        return gs__fail(err, GS_ENOMEM, "%s: out of memory", path);
    }
    memcpy(head, gt_magic, 8);
    put_u32(head + 8, n);
    put_u32(head + 12, k);
    int ok = fwrite(head, 1, 16, af.fp) == 16;
    for (uint32_t j = 0; ok && j < k; ++j) {
        put_u32(rec, sources[j]);
        for (uint32_t i = 0; i < n; ++i) put_f64(rec + 4 + 8 * (size_t)i, dist[(size_t)j * n + i]);
        ok = fwrite(rec, 1, 4 + 8 * (size_t)n, af.fp) == 4 + 8 * (size_t)n;
    }
    free(rec);
    if (!ok) {
        gs__atomic_abort(&af);
        return gs__fail(err, GS_EIO, "%s: write error: %s", path, strerror(errno));
    }
    return gs__atomic_commit(&af, err);
}
