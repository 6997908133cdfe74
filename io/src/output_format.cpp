/* output_format.cpp - the one place that decides, from an output path's extension, the format
 * it is written in (tp_io.h, "Output formats").
 *
 * Rasters: the formats below, each through its GDAL driver, taken when GDAL's own metadata
 * says the driver is there, writes rasters (GDAL_DCAP_CREATE or GDAL_DCAP_CREATECOPY: every one
 * is written with CreateCopy from a MEM dataset, GDAL's default CreateCopy calling Create
 * where a driver has no CreateCopy of its own), writes into /vsimem/ (GDAL_DCAP_VIRTUALIO: the
 * writer encodes in memory, then writes whole) and takes Byte (GDAL_DMD_CREATIONDATATYPES); the
 * extensions are the driver's own (GDAL_DMD_EXTENSIONS). A short list rather than every driver
 * that passes those tests: most of the others cannot hold an arbitrary grid (DTED and SRTMHGT
 * need their tile's size, MBTiles Web Mercator, GRIB and PDS4 their own metadata), and JPEG and
 * WEBP are lossy (a visibility of 255 would come back as 254 near an edge); those are refused
 * with the reason rather than written wrong. Float32 rasters (terrain's slope and aspect) go to
 * those of the same list whose driver takes Float32 (GDAL_DMD_CREATIONDATATYPES): GeoTIFF,
 * GeoPackage, Erdas Imagine, Arc/Info ASCII Grid; PNG, BMP and JPEG 2000 are refused with the
 * reason.
 *
 * Vectors: the extensions contours have always taken (.gpkg GeoPackage, .shp Shapefile, ...),
 * then any other extension an OGR driver that creates vector files declares. Stores and plots
 * are terrapatch's own (.tpt) and gnuplot's PNG. Meshes are VTK's three files (vtk_mesh_write.cpp
 * and the mesh reader take the format from here too). Screenshots go through OpenImageIO's
 * writer for the extension, encoded in memory (image_rgba.cpp): the list below is the formats
 * whose writer encodes an RGBA picture that way (tests/test_image.c writes each); others that
 * OpenImageIO has either cannot encode in memory (SGI, ICO, RLA, FITS, HEIF) or not four
 * channels (HDR, PNM), and failed only after the frame was drawn.
 */
#include "output_format.hpp"
#include "gdal_util.hpp"
#include "tp_io.h"

#include <cctype>
#include <string>
#include <vector>

using tpio::fail;

namespace {

struct RasterFormat {
    const char* driver;
    const char* name;
    const char* options[3]; /* creation options, NULL-ended */
};

/* In the order the lists give them. PNG, BMP: a world file (.wld) with the georeference and
 * the CRS in GDAL's .aux.xml beside; JPEG 2000 reversible (lossless). */
const RasterFormat k_rasters[] = {
    {"GTiff", "GeoTIFF", {"COMPRESS=DEFLATE", "TILED=YES", nullptr}},
    {"PNG", "PNG", {"WORLDFILE=YES", nullptr, nullptr}},
    {"GPKG", "GeoPackage", {nullptr, nullptr, nullptr}},
    {"JP2OpenJPEG", "lossless JPEG 2000", {"REVERSIBLE=YES", "QUALITY=100", nullptr}},
    {"HFA", "Erdas Imagine", {"COMPRESSED=YES", nullptr, nullptr}},
    {"AAIGrid", "Arc/Info ASCII Grid", {nullptr, nullptr, nullptr}},
    {"BMP", "BMP", {"WORLDFILE=YES", nullptr, nullptr}},
};

/* GDAL drivers a raster output is refused from, and why. */
const char* const k_lossy[] = {"JPEG", "WEBP", "JPEGXL"};

struct VectorFormat {
    const char* ext;
    const char* driver;
    const char* name;
};

const VectorFormat k_vectors[] = {
    {"gpkg", "GPKG", "GeoPackage"},
    {"shp", "ESRI Shapefile", "Shapefile"},
    {"geojson", "GeoJSON", "GeoJSON"},
    {"json", "GeoJSON", "GeoJSON"},
    {"kml", "KML", "KML"},
    {"gml", "GML", "GML"},
    {"csv", "CSV", "CSV with WKT geometry"},
    {"fgb", "FlatGeobuf", "FlatGeobuf"},
    {"sqlite", "SQLite", "SQLite"},
    {"gpx", "GPX", "GPX"},
    {"dxf", "DXF", "DXF"},
    {"geojsonl", "GeoJSONSeq", "GeoJSON Sequence"},
    {"geojsons", "GeoJSONSeq", "GeoJSON Sequence"},
    {"tab", "MapInfo File", "MapInfo"},
    {"mif", "MapInfo File", "MapInfo"},
};

struct MeshFormat {
    const char* ext;
    const char* name;
    tp_mesh_format format;
};

const MeshFormat k_meshes[] = {
    {"vtp", "VTK XML PolyData", TP_MESH_VTP},
    {"vtk", "legacy VTK", TP_MESH_VTK},
    {"vtm", "VTK XML multiblock", TP_MESH_VTM},
};

struct PictureFormat {
    const char* oiio; /* OpenImageIO's format name */
    const char* name;
    const char* exts[3]; /* NULL-ended */
};

const PictureFormat k_pictures[] = {
    {"png", "PNG", {"png", nullptr, nullptr}},         {"tiff", "TIFF", {"tif", "tiff", nullptr}},
    {"jpeg", "JPEG", {"jpg", "jpeg", nullptr}},        {"bmp", "BMP", {"bmp", nullptr, nullptr}},
    {"targa", "Targa", {"tga", nullptr, nullptr}},     {"webp", "WebP", {"webp", nullptr, nullptr}},
    {"openexr", "OpenEXR", {"exr", nullptr, nullptr}},
};

std::string lower(std::string s)
{
    for (char& c : s)
        c = (char)std::tolower((unsigned char)c);
    return s;
}

/* The extension of path's file name, lower case, without the dot; "" for none. */
std::string extension_of(const std::string& path)
{
    const size_t slash = path.rfind('/');
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = name.rfind('.');
    return dot == std::string::npos || dot == 0 ? std::string() : lower(name.substr(dot + 1));
}

std::vector<std::string> driver_extensions(GDALDriver* d)
{
    std::vector<std::string> out;
    const char* exts = d ? d->GetMetadataItem(GDAL_DMD_EXTENSIONS) : nullptr;
    if (!exts)
        return out;
    CPLStringList list(CSLTokenizeString(exts));
    for (int j = 0; j < list.size(); ++j)
        out.push_back(lower(list[j]));
    return out;
}

bool has_extension(GDALDriver* d, const std::string& ext)
{
    for (const std::string& e : driver_extensions(d))
        if (e == ext)
            return true;
    return false;
}

/* The driver of f when this GDAL has it and it can write one band of type ("Byte",
 * "Float32") into memory. */
GDALDriver* raster_driver(const RasterFormat& f, const char* type = "Byte")
{
    GDALDriver* d = GetGDALDriverManager()->GetDriverByName(f.driver);
    if (!d || !d->GetMetadataItem(GDAL_DCAP_RASTER) || !d->GetMetadataItem(GDAL_DCAP_VIRTUALIO) ||
        !(d->GetMetadataItem(GDAL_DCAP_CREATE) || d->GetMetadataItem(GDAL_DCAP_CREATECOPY)))
        return nullptr;
    const char* types = d->GetMetadataItem(GDAL_DMD_CREATIONDATATYPES);
    if (types) {
        CPLStringList list(CSLTokenizeString(types));
        if (list.FindString(type) < 0)
            return nullptr;
    }
    return d;
}

bool writes_vectors(GDALDriver* d)
{
    return d && d->GetMetadataItem(GDAL_DCAP_VECTOR) && d->GetMetadataItem(GDAL_DCAP_CREATE);
}

/* The vector driver for ext (lower case, no dot) and its name in the lists, or nullptr. */
GDALDriver* vector_driver(const std::string& ext, std::string* name)
{
    GDALDriverManager* dm = GetGDALDriverManager();
    for (const VectorFormat& k : k_vectors)
        if (ext == k.ext) {
            GDALDriver* d = dm->GetDriverByName(k.driver);
            if (writes_vectors(d)) {
                *name = k.name;
                return d;
            }
        }
    for (int i = 0; i < dm->GetDriverCount(); ++i) {
        GDALDriver* d = dm->GetDriver(i);
        if (writes_vectors(d) && !d->GetMetadataItem(GDAL_DCAP_RASTER) && has_extension(d, ext)) {
            const char* ln = d->GetMetadataItem(GDAL_DMD_LONGNAME);
            *name = ln ? ln : d->GetDescription();
            return d;
        }
    }
    return nullptr;
}

/* The name of a kind written in one format of our own (or gnuplot's). */
const char* single_name(tp_output_kind kind)
{
    return kind == TP_OUTPUT_STORE     ? "terrapatch store"
           : kind == TP_OUTPUT_PLOT    ? "PNG"
           : kind == TP_OUTPUT_IMAGERY ? "terrapatch imagery pyramid"
                                       : "terrapatch light map";
}

/* The GDAL data type a raster output of kind holds; nullptr for a kind that is no raster. */
const char* raster_type(tp_output_kind kind)
{
    return kind == TP_OUTPUT_BYTE_RASTER    ? "Byte"
           : kind == TP_OUTPUT_FLOAT_RASTER ? "Float32"
                                            : nullptr;
}

/* Why no format of kind is written as ext: the message after "PATH: ". */
std::string refusal(tp_output_kind kind, const std::string& ext)
{
    if (ext.empty())
        return "no extension to say its format";
    GDALDriverManager* dm = GetGDALDriverManager();
    if (kind == TP_OUTPUT_FLOAT_RASTER)
        for (const RasterFormat& f : k_rasters) {
            GDALDriver* d = raster_driver(f);
            if (d && has_extension(d, ext))
                return std::string(f.name) + " holds no Float32 values";
        }
    if (kind == TP_OUTPUT_BYTE_RASTER || kind == TP_OUTPUT_FLOAT_RASTER)
        for (int i = 0; i < dm->GetDriverCount(); ++i) {
            GDALDriver* d = dm->GetDriver(i);
            if (!d->GetMetadataItem(GDAL_DCAP_RASTER) || !has_extension(d, ext))
                continue;
            for (const char* l : k_lossy)
                if (!std::strcmp(d->GetDescription(), l))
                    return std::string(d->GetDescription()) +
                           " is lossy: the values written would not be the ones computed";
            return "'." + ext + "' is GDAL's " + d->GetDescription() +
                   " driver, not one of the raster formats written";
        }
    return "unknown extension '." + ext + "'";
}

void copy_field(char* dst, size_t cap, const std::string& s)
{
    std::snprintf(dst, cap, "%s", s.c_str());
}

/* The format of path for kind; status and message as tp_output_format_for. */
tp_status decide(const std::string& path, tp_output_kind kind, tp_output_format* fmt,
                 GDALDriver** drv, const char* const** options, tp_error* err)
{
    const std::string ext = extension_of(path);
    *drv = nullptr;
    *options = nullptr;
    fmt->mesh = TP_MESH_VTP;
    switch (kind) {
    case TP_OUTPUT_BYTE_RASTER:
    case TP_OUTPUT_FLOAT_RASTER:
        tpio::register_drivers();
        for (const RasterFormat& f : k_rasters) {
            GDALDriver* d = raster_driver(f, raster_type(kind));
            if (d && has_extension(d, ext)) {
                copy_field(fmt->driver, sizeof fmt->driver, f.driver);
                copy_field(fmt->name, sizeof fmt->name, f.name);
                *drv = d;
                *options = f.options;
                return TP_OK;
            }
        }
        break;
    case TP_OUTPUT_VECTOR: {
        tpio::register_drivers();
        std::string name;
        if (GDALDriver* d = ext.empty() ? nullptr : vector_driver(ext, &name)) {
            copy_field(fmt->driver, sizeof fmt->driver, d->GetDescription());
            copy_field(fmt->name, sizeof fmt->name, name);
            *drv = d;
            return TP_OK;
        }
        break;
    }
    case TP_OUTPUT_MESH:
        for (const MeshFormat& f : k_meshes)
            if (ext == f.ext) {
                copy_field(fmt->driver, sizeof fmt->driver, "");
                copy_field(fmt->name, sizeof fmt->name, f.name);
                fmt->mesh = f.format;
                return TP_OK;
            }
        break;
    case TP_OUTPUT_SCREENSHOT:
        for (const PictureFormat& f : k_pictures)
            for (const char* e : f.exts)
                if (e && ext == e) {
                    copy_field(fmt->driver, sizeof fmt->driver, f.oiio);
                    copy_field(fmt->name, sizeof fmt->name, f.name);
                    return TP_OK;
                }
        break;
    case TP_OUTPUT_STORE:
    case TP_OUTPUT_PLOT:
    case TP_OUTPUT_IMAGERY:
    case TP_OUTPUT_LIGHT_MAP: {
        const char* want = kind == TP_OUTPUT_STORE     ? "tpt"
                           : kind == TP_OUTPUT_PLOT    ? "png"
                           : kind == TP_OUTPUT_IMAGERY ? "tpi"
                                                       : "tpl";
        if (ext == want) {
            copy_field(fmt->driver, sizeof fmt->driver, "");
            copy_field(fmt->name, sizeof fmt->name, single_name(kind));
            return TP_OK;
        }
        break;
    }
    default:
        return fail(err, TP_ERR_INVALID_ARG, "%s: output format: unknown kind %d", path.c_str(),
                    (int)kind);
    }
    return fail(err, TP_ERR_INVALID_ARG, "%s: %s", path.c_str(), refusal(kind, ext).c_str());
}

} // namespace

namespace tpio {

tp_status output_driver(const char* path, tp_output_kind kind, GDALDriver** drv,
                        const char* const** options, tp_error* err)
{
    tp_output_format fmt;
    GDALDriver* d;
    const char* const* o;
    tp_status s = decide(path, kind, &fmt, &d, &o, err);
    if (s == TP_OK) {
        *drv = d;
        *options = o;
    }
    return s;
}

} // namespace tpio

extern "C" tp_status tp_output_format_for(const char* path, tp_output_kind kind,
                                          tp_output_format* out, tp_error* err)
{
    if (!path || !*path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "output format: bad arguments (path or out)");
    try {
        tp_output_format fmt;
        GDALDriver* d;
        const char* const* o;
        tp_status s = decide(path, kind, &fmt, &d, &o, err);
        if (s == TP_OK)
            *out = fmt;
        return s;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" size_t tp_output_formats(tp_output_kind kind, char* buf, size_t cap)
{
    std::string list;
    try {
        auto item = [&](const std::string& name, const std::vector<std::string>& exts) {
            if (!list.empty())
                list += ", ";
            list += name + " (";
            for (size_t i = 0; i < exts.size(); ++i)
                list += (i ? ", ." : ".") + exts[i];
            list += ")";
        };
        switch (kind) {
        case TP_OUTPUT_BYTE_RASTER:
        case TP_OUTPUT_FLOAT_RASTER:
            tpio::register_drivers();
            for (const RasterFormat& f : k_rasters)
                if (GDALDriver* d = raster_driver(f, raster_type(kind)))
                    item(f.name, driver_extensions(d));
            break;
        case TP_OUTPUT_VECTOR: {
            tpio::register_drivers();
            GDALDriverManager* dm = GetGDALDriverManager();
            for (size_t i = 0; i < sizeof k_vectors / sizeof k_vectors[0]; ++i) {
                const VectorFormat& k = k_vectors[i];
                if ((i && !std::strcmp(k_vectors[i - 1].driver, k.driver)) ||
                    !writes_vectors(dm->GetDriverByName(k.driver)))
                    continue; /* listed with the one before */
                std::vector<std::string> exts;
                for (const VectorFormat& e : k_vectors)
                    if (!std::strcmp(e.driver, k.driver))
                        exts.push_back(e.ext);
                item(k.name, exts);
            }
            list += ", or another OGR vector format by the extension its driver declares";
            break;
        }
        case TP_OUTPUT_STORE: item(single_name(kind), {"tpt"}); break;
        case TP_OUTPUT_PLOT: item(single_name(kind), {"png"}); break;
        case TP_OUTPUT_IMAGERY: item(single_name(kind), {"tpi"}); break;
        case TP_OUTPUT_LIGHT_MAP: item(single_name(kind), {"tpl"}); break;
        case TP_OUTPUT_MESH:
            for (const MeshFormat& f : k_meshes)
                item(f.name, {f.ext});
            break;
        case TP_OUTPUT_SCREENSHOT:
            for (const PictureFormat& f : k_pictures) {
                std::vector<std::string> exts;
                for (const char* e : f.exts)
                    if (e)
                        exts.push_back(e);
                item(f.name, exts);
            }
            break;
        default: break;
        }
    } catch (...) {
        list = "(out of memory)";
    }
    if (buf && cap)
        std::snprintf(buf, cap, "%s", list.c_str());
    return list.size();
}
