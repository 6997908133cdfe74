/*
 * tp_io/texture.h - images draped on the render grid.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_TEXTURE_H
#define TP_IO_TEXTURE_H

#include "tp_core.h"
#include "tp_io/render_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Textures draped on the render grid (io/src/texture.cpp)
 *
 * A georeferenced image (an orthophoto GeoTIFF, any CRS) is warped by GDAL onto the render
 * grid's CRS and extent, so that texel (i, j) of the result covers the grid's pixel area: the
 * sample (x, y) sits at texture coordinates ((x + 0.5) / grid width, (y + 0.5) / grid height).
 * An image without georeference (a PNG, read through OpenImageIO) is taken to cover the same
 * extent. The result is RGBA8, top row first, at most max_size texels per side (aspect kept
 * by scaling both sides alike); texels outside the image are transparent (alpha 0).
 * Colour comes from the bands GDAL labels red, green and blue, wherever they are, else from the
 * first three bands (an RGB + near-infrared orthophoto shows as RGB), else from one grey band;
 * a palette band is expanded through its colour table. Alpha comes only from a band GDAL labels
 * alpha (so a 4th band is not taken for alpha unless it says so). A raster without bands is
 * TP_ERR_BAD_DATA.
 */
typedef struct tp_texture {
    int width, height;
    uint8_t* rgba;     /* width * height * 4; owned */
    int georeferenced; /* 1 if warped from the image's own georeference */
} tp_texture;

/* Errors name the file: TP_ERR_INVALID_ARG for max_size < 1, TP_ERR_IO for a file that cannot
 * be opened or read (and, before opening, a path that is not a regular file: a FIFO would
 * block), TP_ERR_BAD_DATA for a PNG cut short, failing a CRC or claiming more pixels than its
 * data holds, TP_ERR_OUT_OF_MEMORY for an image whose pixels would not fit in memory (from its
 * header, before decoding), TP_ERR_BACKEND when GDAL or OpenImageIO fails. The codecs' own
 * stderr lines are kept off stderr; their text is in err. */
tp_status tp_texture_build(const char* path, const tp_render_grid* grid, int max_size,
                           tp_texture** out, tp_error* err);
void tp_texture_destroy(tp_texture* tex); /* accepts NULL */

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_TEXTURE_H */
