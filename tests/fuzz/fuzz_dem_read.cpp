/*
 * fuzz_dem_read.cpp - libFuzzer entry point for tp_dem_read (io/src/dem_read.cpp), the DEM
 * reader every command uses. The input is a file in memory: its first byte picks the file
 * name (and so the extension GDAL's drivers look at), the rest is the file, served through
 * GDAL's /vsimem/ so that no disk is touched.
 *
 * GDAL keeps only the drivers of the DEM formats we document (kDrivers): the others are
 * GDAL's own business, and some (VRT, netCDF, the network ones) would read other files.
 * Rasters above kMaxPixels are skipped: refusing what does not fit in memory is
 * tp_dem_read's tested job (tests/test_bad_input.c, "huge"), but here a large raster would
 * only be a slow input. Failures are checked too: a status with a message, *out untouched.
 */
#include "fuzz_util.h"
#include "tp_io.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include <cstring>
#include <set>
#include <string>

namespace {

/* The file names the first byte chooses from: extensions GDAL's DEM drivers know; the .hgt
 * and .dt1 names are real tile names (SRTMHGT reads the position from the name). */
const char* const kNames[] = {"dem.tif", "dem.asc", "dem.xyz",     "dem.dem", "dem.bt",  "dem.grd",
                              "dem.ter", "dem.img", "N42E001.hgt", "n42.dt1", "dem.txt", "dem"};
const char* const kDrivers[] = {"GTiff",    "COG", "AAIGrid", "GRASSASCIIGrid", "XYZ",
                                "USGSDEM",  "BT",  "GSAG",    "GSBG",           "GS7BG",
                                "Terragen", "HFA", "SRTMHGT", "DTED",           "MEM"};
constexpr long long kMaxPixels = 1 << 16; /* 256 x 256: 16 x 16 seeds, 4 MB heights were slow */

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    /* tp_dem_read registers GDAL's drivers once; let it, then drop the ones not in kDrivers
     * (registering again would bring them back, but tp_dem_read never does). */
    tp_dem* none = nullptr;
    tp_dem_read("/vsimem/not-there.tif", &none, nullptr);
    std::set<std::string> keep(std::begin(kDrivers), std::end(kDrivers));
    for (int i = GDALGetDriverCount() - 1; i >= 0; --i) {
        GDALDriverH d = GDALGetDriver(i);
        if (!keep.count(GDALGetDriverShortName(d))) {
            GDALDeregisterDriver(d);
            GDALDestroyDriver(d);
        }
    }
    CPLSetConfigOption("GDAL_PAM_ENABLED", "NO"); /* no .aux.xml beside the file */
    CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
    CPLSetConfigOption("CPL_DEBUG", "OFF");
    GDALSetCacheMax64(16 << 20);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    const std::string path =
        std::string("/vsimem/fuzz/") + kNames[data[0] % (sizeof kNames / sizeof kNames[0])];
    VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(data + 1),
                                       static_cast<vsi_l_offset>(size - 1), FALSE);
    if (!f)
        return 0;
    VSIFCloseL(f);

    bool small = true;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    if (GDALDatasetH ds = GDALOpenEx(path.c_str(), GDAL_OF_RASTER, nullptr, nullptr, nullptr)) {
        small =
            static_cast<long long>(GDALGetRasterXSize(ds)) * GDALGetRasterYSize(ds) <= kMaxPixels;
        GDALClose(ds);
    }
    CPLPopErrorHandler();

    if (small) {
        tp_dem* dem = nullptr;
        tp_error err = {{0}};
        tp_status s = tp_dem_read(path.c_str(), &dem, &err);
        if (s == TP_OK) {
            TP_FUZZ_CHECK(dem && dem->width > 0 && dem->height > 0 && dem->heights,
                          "TP_OK without heights");
            tp_dem_destroy(dem);
        } else {
            TP_FUZZ_CHECK(dem == nullptr, "status %d wrote *out", (int)s);
            TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
        }
    }
    VSIUnlink(path.c_str());
    return 0;
}
