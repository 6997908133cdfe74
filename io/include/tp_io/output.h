/*
 * tp_io/output.h - the format an output path is written in (by its extension), and one-band byte
 * rasters written in it.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_OUTPUT_H
#define TP_IO_OUTPUT_H

#include "tp_core.h"
#include "tp_io/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Output formats (io/src/output_format.cpp): the one place that decides, from an output path's
 * extension (case ignored), the format it is written in, for every writer below that follows
 * the extension (tp_byte_raster_write, tp_gdaldem_write in gdaldem.h, tp_contours_write in
 * tp_vector.h, tp_image_write_rgba) and for the commands, which check their outputs with it
 * before any work.
 */
typedef enum tp_output_kind {
    TP_OUTPUT_NONE = 0,
    TP_OUTPUT_BYTE_RASTER, /* one band of bytes on a georeference (viewshed, light): GeoTIFF
                              (.tif, .tiff), PNG (.png; a .wld world file and an .aux.xml with
                              the CRS beside), GeoPackage (.gpkg), lossless JPEG 2000 (.jp2,
                              .j2k), Erdas Imagine (.img), Arc/Info ASCII Grid (.asc; a .prj
                              beside), BMP (.bmp; .wld, .aux.xml): those this GDAL has */
    /* one band of Float32 on a georeference (terrain's slope and aspect): those of the byte
     * rasters' formats that hold Float32, GeoTIFF, GeoPackage, Erdas Imagine, Arc/Info ASCII
     * Grid */
    TP_OUTPUT_FLOAT_RASTER,
    TP_OUTPUT_VECTOR,      /* lines with fields (contours): any OGR format that creates vector
                              files, by its extension (.gpkg, .shp, .geojson, .kml, ...) */
    TP_OUTPUT_STORE,       /* a terrain store (build): .tpt */
    TP_OUTPUT_PLOT,        /* a plot gnuplot draws (los --profile, profile --png): .png */
    TP_OUTPUT_IMAGERY,     /* an imagery pyramid (imagery -o): .tpi */
    TP_OUTPUT_LIGHT_MAP,   /* a day's light map (light --day -o): .tpl */
    TP_OUTPUT_MESH,        /* a triangle mesh (export -o), through VTK's writers: VTK XML
                              PolyData (.vtp), legacy VTK (.vtk), VTK XML multiblock (.vtm) */
    TP_OUTPUT_SCREENSHOT,  /* an RGBA picture (view --screenshot), through OpenImageIO's writer
                              for the extension, encoded in memory (tp_image_write_rgba): PNG
                              (.png), TIFF (.tif, .tiff), JPEG (.jpg, .jpeg), BMP (.bmp), Targa
                              (.tga), WebP (.webp), OpenEXR (.exr) */
} tp_output_kind;

typedef struct tp_output_format {
    char driver[32]; /* the writer: the GDAL driver's short name ("GTiff", "PNG", "GPKG"),
                        OpenImageIO's format name for a screenshot ("png", "tiff"); "" for a
                        store, a plot or a mesh */
    char name[64];   /* the format as the lists name it ("GeoTIFF", "PNG", "terrapatch store") */
    tp_mesh_format mesh; /* TP_OUTPUT_MESH: the VTK file written; TP_MESH_VTP otherwise */
} tp_output_format;

/* The format path is written in as an output of kind. TP_ERR_INVALID_ARG with a message
 * "PATH: why" when there is none: no extension, an unknown one, a raster format that is lossy
 * ("JPEG is lossy: ...") or that is not among those above; *out written only on success. */
tp_status tp_output_format_for(const char* path, tp_output_kind kind, tp_output_format* out,
                               tp_error* err);

/* What kind is written in, for messages: "GeoTIFF (.tif, .tiff), PNG (.png), ..." into buf (at
 * most cap bytes with the NUL; cut short when cap is too small; buf may be NULL with cap 0).
 * Returns the length of the whole list, as snprintf. */
size_t tp_output_formats(tp_output_kind kind, char* buf, size_t cap);

/* ---------------------------------------------------------------------------------------------
 * Byte rasters (io/src/byte_raster.cpp): the viewshed's and the light map's outputs
 */

/* Writes values (width * height bytes = value_count, row 0 first) as a one-band Byte raster in
 * the format path's extension names (tp_output_format_for, TP_OUTPUT_BYTE_RASTER) with
 * geotransform and crs_wkt ("" or NULL: none), e.g. a render grid's, and the band description
 * description (NULL or "": none). GDAL's driver encodes it in memory (CreateCopy from a MEM
 * dataset; a GeoTIFF DEFLATE-compressed and tiled), with the sidecars the driver writes (a PNG's
 * .wld world file, GDAL's .aux.xml holding the CRS and description where the format cannot),
 * and the files are written all or none (tp_file_set_*): an older file and its sidecars stay as
 * they were on failure; older sidecars GDAL would read with the new file (PATH.aux.xml, world
 * files PATH's stem .wld, .XXw for .XYZ) that the new one lacks are removed with it. No nodata
 * tag. TP_ERR_INVALID_ARG for NULL values or path, a size mismatch, a path whose format is not
 * written (tp_output_format_for's message), a bad path (as tp_file_begin); TP_ERR_BAD_DATA for a
 * crs_wkt GDAL cannot read; TP_ERR_IO when writing fails; TP_ERR_BACKEND when GDAL does. */
tp_status tp_byte_raster_write(const char* path, const uint8_t* values, size_t value_count,
                               int width, int height, const double geotransform[6],
                               const char* crs_wkt, const char* description, tp_error* err);

/* The nodata value of the float rasters (gdaldem's). */
#define TP_FLOAT_RASTER_NODATA (-9999.0)

/* Writes values (width * height floats, row 0 first, NaN where there is none) as a one-band
 * Float32 raster in the format path's extension names for TP_OUTPUT_FLOAT_RASTER, as
 * tp_byte_raster_write writes (all or none, sidecars), NaN written as TP_FLOAT_RASTER_NODATA
 * and tagged as the band's nodata. Errors as tp_byte_raster_write's. */
tp_status tp_float_raster_write(const char* path, const float* values, size_t value_count,
                                int width, int height, const double geotransform[6],
                                const char* crs_wkt, const char* description, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_OUTPUT_H */
