/*
 * vertical_datum.cpp - what a DEM says about the datum of its heights (tp_dem_vertical_info):
 * the vertical part of its CRS, through GDAL's OGRSpatialReference. Only what the file states;
 * nothing is assumed here (the caller says what it assumes, and that it assumes it).
 */
#include "gdal_util.hpp"
#include "tp_io.h"

#include <exception>
#include <new>

extern "C" tp_status tp_dem_vertical_info(const char* path, tp_vertical_info* out, tp_error* err)
{
    if (!path || !*path || !out) {
        tpio::set_error(err, "tp_dem_vertical_info: expected a path and an output, got NULL");
        return TP_ERR_INVALID_ARG;
    }
    if (tp_status s = tp_input_check(path, "a raster", 1, err))
        return s;
    try {
        tpio::register_drivers();
        tpio::QuietGdal quiet;
        tpio::Dataset ds(GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr,
                                           nullptr, nullptr));
        if (!ds) {
            tpio::set_error(err, "%s: not a raster GDAL can open (%s)", path,
                            tpio::gdal_message().c_str());
            return TP_ERR_BAD_DATA;
        }
        tp_vertical_info v = {};
        const char* driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "";
        std::snprintf(v.driver, sizeof v.driver, "%s", driver ? driver : "");
        const OGRSpatialReference* srs = ds->GetSpatialRef();
        if (srs && (srs->IsVertical() || srs->IsCompound())) {
            /* the VERT_CS node of a compound CRS (or the whole CRS when it is vertical) */
            const char* name = srs->GetAttrValue("VERT_CS");
            if (!name)
                name = srs->GetAttrValue("VERTCRS");
            std::snprintf(v.datum, sizeof v.datum, "%s", name ? name : "vertical CRS without a name");
        }
        if (ds->GetRasterCount() > 0) {
            const char* unit = ds->GetRasterBand(1)->GetUnitType();
            std::snprintf(v.units, sizeof v.units, "%s", unit ? unit : "");
        }
        *out = v;
        return TP_OK;
    } catch (const std::bad_alloc&) {
        tpio::set_error(err, "%s: out of memory", path);
        return TP_ERR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        tpio::set_error(err, "%s: %s", path, e.what());
        return TP_ERR_BACKEND;
    } catch (...) {
        tpio::set_error(err, "%s: unknown C++ exception", path);
        return TP_ERR_BACKEND;
    }
}
