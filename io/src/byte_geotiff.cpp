/*
 * byte_geotiff.cpp - a one-band Byte raster written as a GeoTIFF on a georeference (tp_io.h
 * "Byte GeoTIFFs"): the viewshed's and the light map's outputs. Encoded in memory by GDAL,
 * then written whole with tp_file_write.
 */
#include "gdal_util.hpp"
#include "tp_io.h"

#include <atomic>
#include <cstdio>
#include <string>

using tpio::fail;

extern "C" tp_status tp_byte_geotiff_write(const char* path, const uint8_t* values,
                                           size_t value_count, int width, int height,
                                           const double geotransform[6], const char* crs_wkt,
                                           const char* description, tp_error* err)
{
    if (!path || !*path || !values || !geotransform || width < 1 || height < 1 ||
        value_count != (size_t)width * (size_t)height)
        return fail(err, TP_ERR_INVALID_ARG, "%s: GeoTIFF: bad arguments", path ? path : "");
    static std::atomic<unsigned> counter{0};
    std::string mem;
    try {
        tpio::register_drivers();
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = crs_wkt && *crs_wkt;
        if (has_crs && srs.SetFromUserInput(crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "%s: GeoTIFF: GDAL cannot read the CRS: %s", path,
                        tpio::gdal_message().c_str());
        char name[96];
        std::snprintf(name, sizeof name, "/vsimem/tp_byte_%p_%u.tif", (const void*)values,
                      counter++);
        mem = name;
        GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
        if (!gtiff)
            return fail(err, TP_ERR_BACKEND, "%s: GeoTIFF: GDAL has no GTiff driver", path);
        const char* co[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
        tp_status s = TP_OK;
        {
            tpio::Dataset ds(gtiff->Create(mem.c_str(), width, height, 1, GDT_Byte,
                                           const_cast<char**>(co)));
            if (!ds) {
                s = fail(err, TP_ERR_BACKEND, "%s: GeoTIFF: cannot encode a GeoTIFF: %s", path,
                         tpio::gdal_message().c_str());
                VSIUnlink(mem.c_str());
                return s;
            }
            ds->SetGeoTransform(const_cast<double*>(geotransform));
            if (has_crs)
                ds->SetSpatialRef(&srs);
            GDALRasterBand* b = ds->GetRasterBand(1);
            if (description && *description)
                b->SetDescription(description);
            if (b->RasterIO(GF_Write, 0, 0, width, height, const_cast<uint8_t*>(values), width,
                            height, GDT_Byte, 0, 0, nullptr) != CE_None)
                s = fail(err, TP_ERR_BACKEND, "%s: GeoTIFF: cannot encode a GeoTIFF: %s", path,
                         tpio::gdal_message().c_str());
            if (s == TP_OK) {
                ds->FlushCache();
                if (CPLGetLastErrorType() == CE_Failure)
                    s = fail(err, TP_ERR_BACKEND, "%s: GeoTIFF: cannot encode a GeoTIFF: %s",
                             path, tpio::gdal_message().c_str());
            }
        } /* closed: the file is complete in memory */
        if (s == TP_OK) {
            vsi_l_offset size = 0;
            GByte* bytes = VSIGetMemFileBuffer(mem.c_str(), &size, FALSE);
            s = bytes ? tp_file_write(path, bytes, (size_t)size, err)
                      : fail(err, TP_ERR_BACKEND, "%s: GeoTIFF: GDAL kept no GeoTIFF", path);
        }
        VSIUnlink(mem.c_str());
        return s;
    } catch (...) {
        if (!mem.empty())
            VSIUnlink(mem.c_str());
        return tpio::caught(err, path);
    }
}
