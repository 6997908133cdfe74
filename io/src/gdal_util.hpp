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

} // namespace tpio
