/* gdal_util.hpp - small C++ helpers shared by the io/ files that call GDAL. Private to io/. */
#pragma once

#include "io_util.hpp"

#include <cpl_error.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>

namespace tpio {

/* Silences GDAL's printing for a scope; CPLGetLastErrorMsg still records the message. */
struct QuietGdal {
    QuietGdal()
    {
        CPLPushErrorHandler(CPLQuietErrorHandler);
        CPLErrorReset();
    }
    ~QuietGdal() { CPLPopErrorHandler(); }
    QuietGdal(const QuietGdal&) = delete;
    QuietGdal& operator=(const QuietGdal&) = delete;
};

inline std::string gdal_message()
{
    const char* m = CPLGetLastErrorMsg();
    return (m && *m) ? std::string(m) : std::string("GDAL gave no detail");
}

inline void register_drivers()
{
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
}

struct DatasetCloser {
    void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

/* A Float32 in-memory dataset over a copy of heights (NaN = nodata). */
inline Dataset mem_dataset(const float* heights, int w, int h, const double gt[6],
                           const OGRSpatialReference* srs)
{
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    if (!mem)
        return nullptr;
    Dataset ds(mem->Create("", w, h, 1, GDT_Float32, nullptr));
    if (!ds)
        return nullptr;
    ds->SetGeoTransform(const_cast<double*>(gt));
    if (srs)
        ds->SetSpatialRef(srs);
    GDALRasterBand* b = ds->GetRasterBand(1);
    b->SetNoDataValue(std::nan(""));
    if (b->RasterIO(GF_Write, 0, 0, w, h, const_cast<float*>(heights), w, h, GDT_Float32, 0, 0,
                    nullptr) != CE_None)
        return nullptr;
    return ds;
}

/* The unit of a DEM's heights (io/src/vertical_datum.cpp), converted to metres by the readers
 * (tp_dem_read, tp_mosaic). */
struct ZUnit {
    double to_m = 1.0;   /* metres per unit of the heights as stored */
    std::string name;    /* "metre", "international foot", "US survey foot"; "" when unknown
                            (taken as metres) */
    std::string from;    /* how it is known: "band unit 'ft'", "vertical CRS 'NAVD88 height
                            (ftUS)'", "--z-unit us-ft"; "" when unknown */
    std::string warning; /* a unit named but not known, taken as metres; "" otherwise */
};

/* The unit of band 1 of ds: z_unit ("m", "ft", "us-ft": --z-unit) when given, else band 1's
 * unit type (GDALRasterBand::GetUnitType), else the unit of the vertical part of its CRS. An
 * unknown name is a warning naming it (heights taken as metres). TP_ERR_INVALID_ARG for an
 * unknown z_unit. */
tp_status z_unit_of(GDALDataset* ds, const char* z_unit, ZUnit* out, tp_error* err);

/* The datum of a DEM's heights as its CRS states it (the vertical CRS's name), "" when it
 * states none. */
std::string vertical_datum_of(GDALDataset* ds);

} // namespace tpio
