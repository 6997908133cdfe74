/*
 * int16_voids.cpp - an untagged Int16 raster's two void values as one, through a VRT written
 * into /vsimem/ (int16_voids.hpp).
 */
#include "int16_voids.hpp"
#include "crs.hpp"

#include <cpl_string.h>
#include <cpl_vsi.h>

const char* const tpio::int16_voids_lut = "-32768:-32768,-32767:-32768,-32766:-32766,32767:32767";

namespace {

std::string xml_escaped(const std::string& s)
{
    char* e = CPLEscapeString(s.c_str(), -1, CPLES_XML);
    std::string out = e ? e : "";
    CPLFree(e);
    return out;
}

} // namespace

tpio::Dataset tpio::int16_voids_vrt(const std::string& path, int w, int h, const double gt[6],
                                    bool has_gt, const OGRSpatialReference* srs,
                                    const std::string& vrt_name)
{
    std::string x = CPLSPrintf("<VRTDataset rasterXSize=\"%d\" rasterYSize=\"%d\">\n", w, h);
    if (srs) {
        const std::string wkt = tpio::crs_wkt2(*srs);
        if (wkt.empty()) {
            CPLError(CE_Failure, CPLE_AppDefined, "%s: its CRS has no WKT", path.c_str());
            return nullptr;
        }
        std::string mapping;
        for (int a : srs->GetDataAxisToSRSAxisMapping())
            mapping += (mapping.empty() ? "" : ",") + std::to_string(a);
        x += "  <SRS dataAxisToSRSAxisMapping=\"" + mapping + "\">" + xml_escaped(wkt) + "</SRS>\n";
    }
    if (has_gt)
        x += CPLSPrintf("  <GeoTransform>%.17g, %.17g, %.17g, %.17g, %.17g, %.17g</GeoTransform>\n",
                        gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]);
    x += "  <VRTRasterBand dataType=\"Int16\" band=\"1\">\n"
         "    <NoDataValue>-32768</NoDataValue>\n"
         "    <ComplexSource>\n"
         "      <SourceFilename relativeToVRT=\"0\">" +
         xml_escaped(path) +
         "</SourceFilename>\n"
         "      <SourceBand>1</SourceBand>\n";
    x += CPLSPrintf("      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"%d\" ySize=\"%d\" />\n"
                    "      <DstRect xOff=\"0\" yOff=\"0\" xSize=\"%d\" ySize=\"%d\" />\n",
                    w, h, w, h);
    x += std::string("      <LUT>") + int16_voids_lut +
         "</LUT>\n"
         "    </ComplexSource>\n"
         "  </VRTRasterBand>\n"
         "</VRTDataset>\n";
    VSILFILE* f = VSIFOpenL(vrt_name.c_str(), "wb");
    if (!f) {
        CPLError(CE_Failure, CPLE_FileIO, "%s: cannot create", vrt_name.c_str());
        return nullptr;
    }
    const bool written = VSIFWriteL(x.data(), 1, x.size(), f) == x.size();
    if (VSIFCloseL(f) != 0 || !written) {
        CPLError(CE_Failure, CPLE_FileIO, "%s: cannot write", vrt_name.c_str());
        return nullptr;
    }
    return Dataset(GDALDataset::Open(vrt_name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
}
