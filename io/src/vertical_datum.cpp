/*
 * vertical_datum.cpp - what a DEM says about the datum of its heights (tp_dem_vertical_info):
 * the vertical part of its CRS, through GDAL's OGRSpatialReference. Only what the file states;
 * nothing is assumed here (the caller says what it assumes, and that it assumes it).
 */
#include "gdal_util.hpp"
#include "tp_io.h"

#include <cctype>
#include <cmath>
#include <string>

using tpio::fail;

#include <exception>
#include <new>

namespace {

/* Lower case, without blanks at either end. */
std::string folded(const char* s)
{
    std::string r;
    for (const char* c = s ? s : ""; *c; ++c)
        r += (char)std::tolower((unsigned char)*c);
    const size_t a = r.find_first_not_of(" \t"), b = r.find_last_not_of(" \t");
    return a == std::string::npos ? std::string() : r.substr(a, b - a + 1);
}

/* Metres per unit and the unit's name for the names files and people use; false when unknown. */
bool known_unit(const std::string& u, double* to_m, const char** name)
{
    static const struct {
        const char* spelling;
        double to_m;
        const char* name;
    } units[] = {
        {"m", 1.0, "metre"},
        {"metre", 1.0, "metre"},
        {"metres", 1.0, "metre"},
        {"meter", 1.0, "metre"},
        {"meters", 1.0, "metre"},
        {"ft", 0.3048, "international foot"},
        {"foot", 0.3048, "international foot"},
        {"feet", 0.3048, "international foot"},
        {"international foot", 0.3048, "international foot"},
        {"foot (international)", 0.3048, "international foot"},
        {"us-ft", 1200.0 / 3937.0, "US survey foot"},
        {"ftus", 1200.0 / 3937.0, "US survey foot"},
        {"us_survey_foot", 1200.0 / 3937.0, "US survey foot"},
        {"us survey foot", 1200.0 / 3937.0, "US survey foot"},
        {"us survey feet", 1200.0 / 3937.0, "US survey foot"},
        {"foot_us", 1200.0 / 3937.0, "US survey foot"},
        {"foot (us survey)", 1200.0 / 3937.0, "US survey foot"},
        {"survey foot", 1200.0 / 3937.0, "US survey foot"},
    };
    for (const auto& k : units)
        if (u == k.spelling) {
            *to_m = k.to_m;
            *name = k.name;
            return true;
        }
    return false;
}

} // namespace

std::string tpio::vertical_datum_of(GDALDataset* ds)
{
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    if (!srs || !(srs->IsVertical() || srs->IsCompound()))
        return "";
    /* the VERT_CS node of a compound CRS (or the whole CRS when it is vertical) */
    const char* name = srs->GetAttrValue("VERT_CS");
    if (!name)
        name = srs->GetAttrValue("VERTCRS");
    return name ? name : "vertical CRS without a name";
}

tp_status tpio::z_unit_of(GDALDataset* ds, const char* z_unit, ZUnit* out, tp_error* err)
{
    ZUnit z;
    double to_m;
    const char* name;
    if (z_unit && *z_unit) {
        if (!known_unit(folded(z_unit), &to_m, &name))
            return fail(err, TP_ERR_INVALID_ARG, "--z-unit: expected m, ft or us-ft, got '%s'",
                        z_unit);
        z.to_m = to_m, z.name = name, z.from = std::string("--z-unit ") + z_unit;
        *out = z;
        return TP_OK;
    }
    const char* band_unit = ds->GetRasterCount() > 0 ? ds->GetRasterBand(1)->GetUnitType() : "";
    const std::string u = folded(band_unit);
    if (!u.empty()) {
        if (known_unit(u, &to_m, &name)) {
            z.to_m = to_m, z.name = name, z.from = std::string("band unit '") + band_unit + "'";
        } else {
            z.warning = std::string("band 1's unit '") + band_unit +
                        "' is not one terrapatch knows (metres, feet, US survey feet): heights "
                        "taken as metres; --z-unit m|ft|us-ft says which";
        }
        *out = z;
        return TP_OK;
    }
    /* the vertical CRS's unit: its axis unit, as PROJ names and scales it */
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    if (srs && (srs->IsVertical() || srs->IsCompound())) {
        const char* unit_name = nullptr;
        const double f = srs->GetTargetLinearUnits("VERT_CS", &unit_name);
        if (f > 0 && std::fabs(f - 1.0) > 1e-12) {
            const std::string n = folded(unit_name);
            z.to_m = f;
            z.name = known_unit(n, &to_m, &name) ? name : (unit_name ? unit_name : "");
            z.from = "vertical CRS '" + tpio::vertical_datum_of(ds) + "'";
        } else if (f > 0) {
            z.name = "metre", z.from = "vertical CRS '" + tpio::vertical_datum_of(ds) + "'";
        }
    }
    *out = z;
    return TP_OK;
}

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
        std::snprintf(v.datum, sizeof v.datum, "%s", tpio::vertical_datum_of(ds.get()).c_str());
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
