/* png.c - PNG output through libpng, written under a temporary name and
 * renamed into place (src/io/atomic_file.h): never a partial file. */
#include "render_internal.h"
#include "../io/atomic_file.h"

#include <png.h>
#include <setjmp.h>
#include <string.h>

typedef struct png_err {
    char message[256];
} png_err;

static void on_error(png_structp png, png_const_charp msg)
{
    png_err *e = png_get_error_ptr(png);
    if (e) {
        strncpy(e->message, msg ? msg : "unknown error", sizeof e->message - 1);
        e->message[sizeof e->message - 1] = 0;
    }
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

int gs__png_write(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, gs_error *err)
{
    gs__atomic_file af;
    int rc = gs__atomic_open(&af, path, err);
    if (rc) return rc;
    png_err perr = {{0}};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &perr, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        gs__atomic_abort(&af);
        return gs__fail(err, GS_ENOMEM, "%s: out of memory for the PNG encoder", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        gs__atomic_abort(&af);
        return gs__fail(err, GS_EIO, "%s: PNG encoding failed: %s", path, perr.message);
    }
    png_init_io(png, af.fp);
    png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 9);
    png_write_info(png, info);
    for (uint32_t y = 0; y < h; ++y) png_write_row(png, rgb + (size_t)y * w * 3);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return gs__atomic_commit(&af, err);
}
