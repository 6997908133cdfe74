/*
 * make_seeds.cpp - writes the seed corpora of fuzz_dem_read, fuzz_image_read,
 * fuzz_mesh_inspect, fuzz_store_read and fuzz_imagery_read (corpus/<fuzzer>/) from the real files:
 * 16x16 crops of the DEMs of data/ (data/PROVENANCE.md) through GDAL in each DEM format the reader
 * documents, crops of the Puget Sound heightmap through OpenImageIO in each heightmap format, a
 * 3x3-post mesh written by tp_mesh_write in each VTK format, and a 49x33 crop of Storm Lake
 * (with its nodata edge) as a terrain store of 17x17 nodes, and a 40x30 crop of the Crater Lake
 * imagery as an imagery pyramid (fuzz_imagery_read). Each seed is the byte that picks the file
 * name in the fuzzer (its kNames) and the file. Built in build-fuzz/ (not a test):
 *   build-fuzz/fuzz/tp_fuzz_make_seeds data tests/fuzz/corpus
 */
#include "tp_imagery.h"
#include "tp_io.h"
#include "../tp_test_tree.h"

#include <OpenImageIO/imageio.h>
#include <cpl_conv.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

std::string g_out;
int g_count = 0;
constexpr size_t kMaxSeed = 100 * 1024;

void save(const std::string& fuzzer, const std::string& name, unsigned char pick,
          const std::vector<unsigned char>& bytes)
{
    if (bytes.empty() || bytes.size() > kMaxSeed) {
        std::fprintf(stderr, "skipped %s/%s: %zu bytes\n", fuzzer.c_str(), name.c_str(),
                     bytes.size());
        return;
    }
    std::string dir = g_out + "/" + fuzzer;
    VSIMkdirRecursive(dir.c_str(), 0755);
    std::ofstream f(dir + "/" + name, std::ios::binary);
    f.put(static_cast<char>(pick));
    f.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
    ++g_count;
}

std::vector<unsigned char> slurp(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), {});
}

std::vector<unsigned char> vsimem_bytes(const std::string& path)
{
    vsi_l_offset n = 0;
    GByte* p = VSIGetMemFileBuffer(path.c_str(), &n, FALSE);
    return p ? std::vector<unsigned char>(p, p + n) : std::vector<unsigned char>();
}

/* gdal_translate SRC /vsimem/NAME ARGS..., saved as seed NAME with the fuzzer's pick byte. */
void dem(const std::string& src, const std::string& name, unsigned char pick,
         std::vector<const char*> args)
{
    args.push_back(nullptr);
    GDALTranslateOptions* o = GDALTranslateOptionsNew(const_cast<char**>(args.data()), nullptr);
    GDALDatasetH in = GDALOpen(src.c_str(), GA_ReadOnly);
    std::string out = "/vsimem/seeds/" + name;
    int bad = 0;
    GDALDatasetH ds = in ? GDALTranslate(out.c_str(), in, o, &bad) : nullptr;
    GDALTranslateOptionsFree(o);
    if (!ds) {
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), CPLGetLastErrorMsg());
    } else {
        GDALClose(ds);
        /* the seed's own name keeps its extension: the fuzzer's pick byte gives it back */
        save("fuzz_dem_read", name, pick, vsimem_bytes(out));
    }
    if (in)
        GDALClose(in);
    VSIRmdirRecursive("/vsimem/seeds");
}

void image(const std::string& name, unsigned char pick, const OIIO::ImageSpec& spec,
           const void* pixels)
{
    std::string path =
        std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/tp_seed_" + name;
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->open(path, spec) || !out->write_image(spec.format, pixels) || !out->close()) {
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), OIIO::geterror().c_str());
        return;
    }
    save("fuzz_image_read", name, pick, slurp(path));
    std::remove(path.c_str());
}

void mesh(const std::string& name, unsigned char pick, tp_mesh_format format)
{
    /* 3x3 posts, 8 triangles, every array and field tp_mesh_write writes */
    double xyz[27], elev[9];
    uint8_t filled[9] = {0, 0, 0, 0, 1, 0, 0, 0, 0};
    for (int i = 0; i < 9; ++i) {
        xyz[3 * i] = 323476.0 + 30.0 * (i % 3);
        xyz[3 * i + 1] = 5105082.0 - 30.0 * (i / 3);
        xyz[3 * i + 2] = elev[i] = 2438.0 + 7.0 * i;
    }
    std::vector<uint64_t> tri;
    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
            uint64_t a = r * 3 + c, b = a + 1, d = a + 3, e = a + 4;
            tri.insert(tri.end(), {a, d, b, b, d, e});
        }
    int32_t patch[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    uint8_t lod[8] = {1, 1, 1, 1, 0, 0, 0, 0};
    double maxerr[8] = {0, 0, 0, 0, 1.5, 1.5, 2, 2};
    tp_mesh m = {};
    m.point_count = 9;
    m.xyz = xyz;
    m.elevation_m = elev;
    m.void_filled = filled;
    m.triangle_count = 8;
    m.triangles = tri.data();
    m.patch_id = patch;
    m.lod = lod;
    m.max_error_m = maxerr;
    m.crs_wkt = "EPSG:26912";
    m.epsg = 26912;
    m.utm_zone = "12n";
    m.source_file = "storml_elev.tif";
    m.camera = "--camera-geo 46.09,-113.26,3500,0,-30";
    m.lod_params = "mode=error tau_px=1";
    m.program_version = "terrapatch seeds";
    std::string dir =
        std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/tp_seed_mesh";
    VSIMkdirRecursive(dir.c_str(), 0755);
    std::string path = dir + "/" + name;
    tp_error err = {{0}};
    if (tp_mesh_write(path.c_str(), format, &m, &err) != TP_OK)
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), err.message);
    else
        save("fuzz_mesh_inspect", name, pick, slurp(path));
    VSIRmdirRecursive(dir.c_str());
}

/* A 49 x 33 crop of a DEM (1 m steps) as a store of 17 x 17 nodes (3 x 2 leaves and their
 * parent: 7 nodes), written leaves first as the tree builder does. */
void store(const std::string& src, const std::string& name)
{
    tp_dem* d = nullptr;
    tp_error err = {{0}};
    if (tp_dem_read(src.c_str(), &d, &err) != TP_OK || d->width < 49 || d->height < 33) {
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), err.message);
        tp_dem_destroy(d);
        return;
    }
    const int w = 49, h = 33, side = 17;
    tp_store_header hd = {};
    tpt_tree_geometry(w, h, side, &hd.geometry);
    std::memcpy(hd.geotransform, d->geotransform, sizeof hd.geotransform);
    hd.height_step_m = 1;
    hd.quant_max_error_m = 0.5;
    hd.err_unit_steps = 1.0 / 16;
    hd.crs_wkt = "EPSG:26912";
    hd.notes = "seed: storml_elev_orig.tif 49x33";
    const std::string path =
        std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/tp_seed.tpt";
    tp_store_writer* sw = nullptr;
    tp_status s = tp_store_writer_begin(path.c_str(), &hd, &sw, &err);
    const tp_tree_geometry& g = hd.geometry;
    for (int sc = 0; s == TP_OK && sc < g.scales; ++sc)
        for (int r = 0; s == TP_OK && r < g.node_rows[sc]; ++r)
            for (int c = 0; s == TP_OK && c < g.node_cols[sc]; ++c) {
                std::vector<int32_t> q(side * side);
                tp_node_meta m = {};
                m.qmin = INT32_MAX, m.qmax = INT32_MIN;
                for (int j = 0; j < side; ++j)
                    for (int i = 0; i < side; ++i) {
                        const int x = (c << (4 + sc)) + (i << sc), y = (r << (4 + sc)) + (j << sc);
                        const float v = x < w && y < h ? d->heights[y * d->width + x] : NAN;
                        const int32_t qv = std::isnan(v) ? INT32_MIN : (int32_t)std::lrint(v);
                        q[j * side + i] = qv;
                        if (qv != INT32_MIN)
                            m.qmin = std::min(m.qmin, qv), m.qmax = std::max(m.qmax, qv);
                    }
                m.flags = m.qmin <= m.qmax ? TP_NODE_HAS_DRAWN : 0;
                for (int k = 0; k <= 4; ++k)
                    m.delta[k] = (uint16_t)(40 >> k);
                const int64_t id = g.first_node[sc] + (int64_t)r * g.node_cols[sc] + c;
                std::vector<uint16_t> mask(tp_node_mask_words(4));
                tp_node_mask_from_q(4, q.data(), mask.data());
                s = tp_store_writer_add_node(sw, id, &m, q.data(), mask.data(), &err);
            }
    if (s == TP_OK)
        s = tp_store_writer_commit(sw, &err);
    else
        tp_store_writer_abort(sw);
    if (s != TP_OK)
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), err.message);
    else
        save("fuzz_store_read", name, 1, slurp(path)); /* 1: the fuzzer fixes checksums */
    std::remove(path.c_str());
    tp_dem_destroy(d);
}

/* A 40 x 30 crop of the craterlake imagery's UTM grid (pixels of 60 m) as an imagery pyramid
 * at texel shift 1: 80 x 60 texels, one block (tp_imagery_build, as terrapatch imagery). */
void imagery(const std::string& data, const std::string& name)
{
    const std::string src = data + "/craterlake-imagery-30m.tif";
    const char* wkt = "EPSG:32610";
    tp_imagery_target t = {wkt, {570000.0, 60.0, 0.0, 4757000.0, 0.0, -60.0}, 40, 30};
    tp_imagery_build_options o = {};
    o.texel_shift = 1;
    o.threads = 1;
    const std::string path =
        std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/tp_seed.tpi";
    const char* sources[1] = {src.c_str()};
    tp_error err = {{0}};
    if (tp_imagery_build(sources, 1, &t, &o, path.c_str(), &err) != TP_OK)
        std::fprintf(stderr, "skipped %s: %s\n", name.c_str(), err.message);
    else
        save("fuzz_imagery_read", name, 1, slurp(path)); /* 1: the fuzzer fixes checksums */
    std::remove(path.c_str());
}

} // namespace

int main(int argc, char** argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s DATA_DIR OUT_CORPUS_DIR\n", argv[0]);
        return 2;
    }
    const std::string data = argv[1];
    g_out = argv[2];
    GDALAllRegister();

    store(data + "/storml_elev_orig.tif", "storml_49x33.tpt");
    imagery(data, "crater_40x30.tpi");

    /* DEMs; picks index fuzz_dem_read.cpp's kNames (0 .tif, 1 .asc, 2 .xyz, 3 .dem, 4 .bt,
     * 5 .grd, 6 .ter, 7 .img, 9 .dt1, 10 .txt) */
    const std::string storml = data + "/storml_elev_orig.tif",
                      hood = data + "/lf_elev_220_mt_hood_utm.tif",
                      crater = data + "/craterlake-elev-16bit-30m.tif",
                      rainier = data + "/mt_rainier_90m.tif",
                      front = data + "/front_range_srtmgl3_144.asc", dted = data + "/N42E001.dt1";
    dem(storml, "storml_edge.tif", 0, {"-srcwin", "0", "0", "16", "16"});
    dem(storml, "storml_deflate_tiled.tif", 0,
        {"-srcwin", "60", "40", "16", "16", "-co", "COMPRESS=DEFLATE", "-co", "TILED=YES", "-co",
         "BLOCKXSIZE=16", "-co", "BLOCKYSIZE=16"});
    dem(hood, "hood_lzw.tif", 0, {"-srcwin", "500", "400", "16", "16", "-co", "COMPRESS=LZW"});
    dem(crater, "crater_point.tif", 0, {"-srcwin", "200", "140", "16", "16"});
    dem(rainier, "rainier_nodata.tif", 0, {"-srcwin", "0", "0", "12", "12"});
    dem(storml, "storml_float_pred3.tif", 0,
        {"-srcwin", "60", "40", "16", "16", "-ot", "Float32", "-co", "COMPRESS=DEFLATE", "-co",
         "PREDICTOR=3"});
    dem(front, "front_range.asc", 1, {"-srcwin", "50", "50", "16", "16", "-of", "AAIGrid"});
    dem(storml, "storml.asc", 1, {"-srcwin", "0", "0", "8", "8", "-of", "AAIGrid"});
    dem(front, "front_range.xyz", 2, {"-srcwin", "50", "50", "8", "8", "-of", "XYZ"});
    dem(storml, "storml.dem", 3, {"-srcwin", "60", "40", "16", "16", "-of", "USGSDEM"});
    dem(storml, "storml.bt", 4, {"-srcwin", "60", "40", "16", "16", "-of", "BT"});
    dem(storml, "storml_ascii.grd", 5, {"-srcwin", "60", "40", "12", "12", "-of", "GSAG"});
    dem(storml, "storml_binary.grd", 5, {"-srcwin", "60", "40", "16", "16", "-of", "GSBG"});
    dem(storml, "storml_surfer7.grd", 5, {"-srcwin", "60", "40", "16", "16", "-of", "GS7BG"});
    dem(storml, "storml.ter", 6,
        {"-srcwin", "60", "40", "16", "16", "-ot", "Float32", "-of", "Terragen", "-co",
         "MINUSERPIXELVALUE=2400", "-co", "MAXUSERPIXELVALUE=3100"});
    dem(storml, "storml.img", 7, {"-srcwin", "60", "40", "16", "16", "-of", "HFA"});
    dem(dted, "n42_level0.dt1", 9, {"-outsize", "121", "121", "-of", "DTED"});
    dem(front, "front_range.txt", 10, {"-srcwin", "0", "0", "8", "8", "-of", "AAIGrid"});

    /* heightmap images: picks index fuzz_image_read.cpp's kNames (0 .png, 1 .pgm, 2 .ppm,
     * 3 .tga, 4 .bmp, 5 .hdr, 6 .exr, 7 .jpg, 8 .webp, 9 .tif) */
    auto in = OIIO::ImageInput::open(data + "/ps_height_1k.png");
    if (in) {
        const int n = 16, x0 = 700, y0 = 700; /* Mount Rainier's flank */
        std::vector<uint16_t> all(static_cast<size_t>(in->spec().width) * in->spec().height);
        in->read_image(0, 0, 0, 1, OIIO::TypeDesc::UINT16, all.data());
        std::vector<uint16_t> crop(n * n);
        std::vector<float> fcrop(n * n);
        std::vector<uint8_t> rgb(n * n * 3);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                uint16_t v = all[static_cast<size_t>(y0 + y) * in->spec().width + x0 + x];
                crop[y * n + x] = v;
                fcrop[y * n + x] = v * 0.1f;
                for (int c = 0; c < 3; ++c)
                    rgb[(y * n + x) * 3 + c] = static_cast<uint8_t>(v >> 8);
            }
        OIIO::ImageSpec grey16(n, n, 1, OIIO::TypeDesc::UINT16),
            grey8(n, n, 1, OIIO::TypeDesc::UINT8), rgb8(n, n, 3, OIIO::TypeDesc::UINT8),
            grey32f(n, n, 1, OIIO::TypeDesc::FLOAT), rgb32f(n, n, 3, OIIO::TypeDesc::FLOAT);
        std::vector<uint8_t> crop8(n * n);
        std::vector<float> frgb(n * n * 3);
        for (int i = 0; i < n * n; ++i) {
            crop8[i] = static_cast<uint8_t>(crop[i] >> 8);
            for (int c = 0; c < 3; ++c)
                frgb[i * 3 + c] = fcrop[i];
        }
        image("ps_16bit.png", 0, grey16, crop.data());
        image("ps_8bit.png", 0, grey8, crop8.data());
        image("ps_16bit.pgm", 1, grey16, crop.data());
        image("ps_rgb.ppm", 2, rgb8, rgb.data());
        image("ps_grey.tga", 3, grey8, crop8.data());
        image("ps_rgb.bmp", 4, rgb8, rgb.data());
        image("ps_rgb.hdr", 5, rgb32f, frgb.data());
        image("ps_float.exr", 6, grey32f, fcrop.data());
        image("ps_grey.jpg", 7, grey8, crop8.data());
        image("ps_rgb.webp", 8, rgb8, rgb.data());
        image("ps_plain.tif", 9, grey16, crop.data());
    }
    /* a GeoTIFF: refused by the GDAL check before OpenImageIO */
    {
        std::vector<const char*> a = {"-srcwin", "0", "0", "8", "8", nullptr};
        GDALTranslateOptions* o = GDALTranslateOptionsNew(const_cast<char**>(a.data()), nullptr);
        if (GDALDatasetH src = GDALOpen(storml.c_str(), GA_ReadOnly)) {
            if (GDALDatasetH ds = GDALTranslate("/vsimem/geo.tif", src, o, nullptr)) {
                GDALClose(ds);
                save("fuzz_image_read", "storml_georeferenced.tif", 9,
                     vsimem_bytes("/vsimem/geo.tif"));
            }
            GDALClose(src);
        }
        GDALTranslateOptionsFree(o);
    }

    /* meshes: picks index fuzz_mesh_inspect.c's names (0 .vtp, 1 .vtm; legacy .vtk is not
     * fuzzed, see there) */
    mesh("patch.vtp", 0, TP_MESH_VTP);
    mesh("patch.vtm", 1, TP_MESH_VTM);
    std::printf("%d seeds in %s\n", g_count, g_out.c_str());
    return 0;
}
