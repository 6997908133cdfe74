/*
 * byte_raster.cpp - a one-band Byte raster written on a georeference in the format its path's
 * extension names (tp_io.h "Byte rasters"): the viewshed's and the light map's outputs. GDAL's
 * driver (output_format.cpp) encodes it into a folder of /vsimem/, sidecars included, and the
 * folder's files are written all or none (file_set.cpp): tpio::raster_write, which writes the
 * gdaldem products too (gdaldem.cpp).
 */
#include "byte_raster.hpp"
#include "gdal_util.hpp"
#include "output_format.hpp"
#include "tp_io.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

using tpio::fail;

namespace {

/* The sidecars GDAL reads with the file name (in a folder): its .aux.xml and world files
 * (stem.wld, stem.XZw for name.XYZ, stem.XYZw, either case). */
std::vector<std::string> sidecars(const std::string& name)
{
    std::vector<std::string> out = {name + ".aux.xml", name + ".AUX.XML"};
    const size_t dot = name.rfind('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 >= name.size())
        return out;
    const std::string stem = name.substr(0, dot), ext = name.substr(dot + 1);
    for (bool upper : {false, true}) {
        std::string e = ext;
        for (char& c : e)
            c = (char)(upper ? std::toupper((unsigned char)c) : std::tolower((unsigned char)c));
        const std::string w = upper ? "W" : "w";
        out.push_back(stem + "." + e.substr(0, 1) + e.substr(e.size() - 1) + w);
        out.push_back(stem + "." + e + w);
        out.push_back(stem + (upper ? ".WLD" : ".wld"));
    }
    return out;
}

/* Removes a /vsimem/ folder and what is in it, whatever happens. */
struct MemDir {
    std::string name;
    ~MemDir()
    {
        if (!name.empty())
            VSIRmdirRecursive(name.c_str());
    }
};

} // namespace

namespace tpio {

tp_status raster_write(const char* path, tp_output_kind kind, GDALDataset* mem, tp_error* err)
{
    static std::atomic<unsigned> counter{0};
    tp_file_set* set = nullptr;
    try {
        GDALDriver* drv;
        const char* const* options;
        tp_status s = tpio::output_driver(path, kind, &drv, &options, err);
        if (s != TP_OK)
            return s;
        const std::string p = path;
        const size_t slash = p.rfind('/');
        const std::string name = slash == std::string::npos ? p : p.substr(slash + 1);
        if (name.empty())
            return fail(err, TP_ERR_INVALID_ARG, "%s: a file name is needed, not a folder", path);
        const std::string dir = slash == std::string::npos ? std::string() : p.substr(0, slash + 1);
        tpio::QuietGdal quiet;
        char folder[96];
        std::snprintf(folder, sizeof folder, "/vsimem/tp_raster_%p_%u", (const void*)mem,
                      counter++);
        MemDir md;
        md.name = folder;
        VSIMkdir(folder, 0700);
        const std::string encoded = md.name + "/" + name;
        {
            tpio::Dataset out(drv->CreateCopy(encoded.c_str(), mem, FALSE,
                                              const_cast<char**>(options), nullptr, nullptr));
            if (!out)
                return fail(err, TP_ERR_BACKEND, "%s: GDAL's %s driver cannot write it: %s", path,
                            drv->GetDescription(), tpio::gdal_message().c_str());
            CPLErrorReset();
        } /* closed: the file and its sidecars are complete in memory */
        if (CPLGetLastErrorType() == CE_Failure)
            return fail(err, TP_ERR_BACKEND, "%s: GDAL's %s driver cannot finish it: %s", path,
                        drv->GetDescription(), tpio::gdal_message().c_str());

        CPLStringList files(VSIReadDir(folder));
        std::vector<std::string> written;
        for (int i = 0; i < files.size(); ++i)
            if (std::strcmp(files[i], ".") && std::strcmp(files[i], ".."))
                written.push_back(files[i]);
        if (std::find(written.begin(), written.end(), name) == written.end())
            return fail(err, TP_ERR_BACKEND, "%s: GDAL's %s driver wrote no file", path,
                        drv->GetDescription());
        s = tp_file_set_begin(&set, err);
        for (size_t i = 0; s == TP_OK && i < written.size(); ++i) {
            vsi_l_offset size = 0;
            GByte* bytes = VSIGetMemFileBuffer((md.name + "/" + written[i]).c_str(), &size, FALSE);
            s = bytes ? tp_file_set_add(set, (dir + written[i]).c_str(), bytes, (size_t)size, err)
                      : fail(err, TP_ERR_BACKEND, "%s: GDAL kept no %s", path, written[i].c_str());
        }
        for (const std::string& old : sidecars(name))
            if (s == TP_OK && std::find(written.begin(), written.end(), old) == written.end())
                s = tp_file_set_remove(set, (dir + old).c_str(), err);
        if (s != TP_OK) {
            tp_file_set_abort(set);
            return s;
        }
        tp_file_set* committing = set;
        set = nullptr;
        return tp_file_set_commit(committing, err);
    } catch (...) {
        tp_file_set_abort(set);
        return tpio::caught(err, path);
    }
}

} // namespace tpio

/* One band of values (GDT_Byte or GDT_Float32) on a georeference written as kind, as
 * tp_byte_raster_write writes; nodata (NaN: none) tagged on the band. */
static tp_status band_write(const char* path, tp_output_kind kind, GDALDataType type,
                            const void* values, int width, int height,
                            const double geotransform[6], const char* crs_wkt,
                            const char* description, double nodata, tp_error* err)
{
    try {
        GDALDriver* drv;
        const char* const* options;
        tp_status s = tpio::output_driver(path, kind, &drv, &options, err);
        if (s != TP_OK)
            return s;
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = crs_wkt && *crs_wkt;
        if (has_crs && srs.SetFromUserInput(crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "%s: GDAL cannot read the CRS: %s", path,
                        tpio::gdal_message().c_str());
        GDALDriver* mem_drv = GetGDALDriverManager()->GetDriverByName("MEM");
        if (!mem_drv)
            return fail(err, TP_ERR_BACKEND, "%s: GDAL has no MEM driver", path);
        tpio::Dataset mem(mem_drv->Create("", width, height, 1, type, nullptr));
        if (!mem)
            return fail(err, TP_ERR_BACKEND, "%s: GDAL cannot hold the raster in memory: %s", path,
                        tpio::gdal_message().c_str());
        mem->SetGeoTransform(const_cast<double*>(geotransform));
        if (has_crs)
            mem->SetSpatialRef(&srs);
        GDALRasterBand* b = mem->GetRasterBand(1);
        if (description && *description)
            b->SetDescription(description);
        if (nodata == nodata)
            b->SetNoDataValue(nodata);
        if (b->RasterIO(GF_Write, 0, 0, width, height, const_cast<void*>(values), width, height,
                        type, 0, 0, nullptr) != CE_None)
            return fail(err, TP_ERR_BACKEND, "%s: GDAL cannot hold the raster in memory: %s", path,
                        tpio::gdal_message().c_str());

        return tpio::raster_write(path, kind, mem.get(), err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}

/* What both writers refuse before any work: no path, values or georeference, a size that is
 * not width * height. */
static bool arguments_ok(const char* path, const void* values, size_t value_count, int width,
                         int height, const double geotransform[6])
{
    return path && *path && values && geotransform && width >= 1 && height >= 1 &&
           value_count == (size_t)width * (size_t)height;
}

extern "C" tp_status tp_byte_raster_write(const char* path, const uint8_t* values,
                                          size_t value_count, int width, int height,
                                          const double geotransform[6], const char* crs_wkt,
                                          const char* description, tp_error* err)
{
    if (!arguments_ok(path, values, value_count, width, height, geotransform))
        return fail(err, TP_ERR_INVALID_ARG, "%s: raster: bad arguments", path ? path : "");
    return band_write(path, TP_OUTPUT_BYTE_RASTER, GDT_Byte, values, width, height, geotransform,
                      crs_wkt, description, NAN, err);
}

extern "C" tp_status tp_float_raster_write(const char* path, const float* values,
                                           size_t value_count, int width, int height,
                                           const double geotransform[6], const char* crs_wkt,
                                           const char* description, tp_error* err)
{
    if (!arguments_ok(path, values, value_count, width, height, geotransform))
        return fail(err, TP_ERR_INVALID_ARG, "%s: raster: bad arguments", path ? path : "");
    try {
        std::vector<float> tagged(values, values + value_count);
        for (float& v : tagged)
            if (v != v)
                v = (float)TP_FLOAT_RASTER_NODATA;
        return band_write(path, TP_OUTPUT_FLOAT_RASTER, GDT_Float32, tagged.data(), width,
                          height, geotransform, crs_wkt, description, TP_FLOAT_RASTER_NODATA,
                          err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}
