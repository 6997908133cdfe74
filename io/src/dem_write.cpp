/* dem_write.cpp - tp_dem_write_geotiff: a DEM read in memory (a heightmap image placed with
 * --spacing/--zscale/--origin) written as a georeferenced Float32 GeoTIFF, so that the commands
 * that read the ground through a store can build one from it with GDAL like any DEM. */
#include "atomic_write.hpp"
#include "gdal_util.hpp"
#include "tp_io.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

using tpio::fail;

extern "C" tp_status tp_dem_write_geotiff(const tp_dem* d, const char* path, tp_error* err)
{
    if (!d || !d->heights || !path || !*path || d->width < 1 || d->height < 1)
        return fail(err, TP_ERR_INVALID_ARG, "DEM GeoTIFF: bad arguments");
    try {
        tpio::register_drivers();
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = d->crs_wkt && *d->crs_wkt;
        if (has_crs && srs.importFromWkt(d->crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "%s: the DEM's CRS cannot be read back", path);
        srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        tpio::Dataset mem = tpio::mem_dataset(d->heights, d->width, d->height, d->geotransform,
                                              has_crs ? &srs : nullptr);
        GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
        if (!mem || !gtiff)
            return fail(err, TP_ERR_BACKEND, "%s: %s", path, tpio::gdal_message().c_str());
        mem->GetRasterBand(1)->SetUnitType("metre"); /* heights are in metres by now */
        /* a new temporary name beside path, renamed when complete: a reader never sees half */
        const std::string tmp = tpio::temp_name(path);
        const char* const options[] = {"COMPRESS=DEFLATE", "PREDICTOR=3", "TILED=YES", nullptr};
        tpio::Dataset out(gtiff->CreateCopy(tmp.c_str(), mem.get(), FALSE,
                                            const_cast<char**>(options), nullptr, nullptr));
        bool ok = out != nullptr;
        if (ok) {
            out->FlushCache();
            out.reset(); /* closes the file */
            ok = CPLGetLastErrorType() < CE_Failure;
        }
        if (!ok) {
            std::string why = tpio::gdal_message();
            std::remove(tmp.c_str());
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path, why.c_str());
        }
        if (std::rename(tmp.c_str(), path) != 0) {
            int e = errno;
            std::remove(tmp.c_str());
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path, std::strerror(e));
        }
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
