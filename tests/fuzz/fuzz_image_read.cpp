/*
 * fuzz_image_read.cpp - libFuzzer entry point for tp_dem_read_image (io/src/image_read.cpp),
 * the heightmap-image reader (`--spacing/--zscale` DEMs, through OpenImageIO). The first byte
 * picks the file name, so the extension (and OpenImageIO's first reader; it tries the others
 * when that one fails); the rest is written to a file in a private temporary folder, as the
 * reader takes a path. ".tif" is not a heightmap extension: that name goes through the GDAL
 * check that refuses georeferenced rasters first, then OpenImageIO's TIFF reader.
 *
 * OpenImageIO is told not to try its other readers when the extension's fails
 * ("try_all_readers" 0): each of the ten extensions has its reader fuzzed anyway, and trying
 * all of them (LibRaw's among them, which clears megabytes per attempt) ran 4 inputs a second.
 *
 * Images whose header claims more than kMaxSamples samples are skipped (OpenImageIO reads the
 * header here first): a 90-byte WebP may claim 16383 x 16383 pixels, and the reader then
 * rightly allocates and decodes a gigabyte, a timeout for the fuzzer but no bug. Sizes beyond
 * memory are tp_dem_read_image's to refuse, tested in tests/test_image.c.
 *
 * OpenEXR files whose header attributes claim more bytes than the file holds are skipped:
 * OpenEXR 3.1 allocates and clears what a string attribute's size says (800 MB from a
 * 113-byte file: "capDate" of size 0x30000013) before it finds the file short, 20 s and more
 * under ASan (tests/fuzz/third_party/openexr_string_attribute_size.exr.bin). Not ours.
 */
#include "fuzz_util.h"
#include "tp_io.h"

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstring>

namespace {
constexpr long long kMaxSamples = 1 << 16; /* 256 x 256 x 1: the seeds are 16 x 16 */
const char* const kNames[] = {"h.png", "h.pgm", "h.ppm", "h.tga",  "h.bmp",
                              "h.hdr", "h.exr", "h.jpg", "h.webp", "h.tif"};
/* 1 if an OpenEXR header's attributes (name NUL type NUL int32-size value ...) each fit in the
 * file; anything that is not an OpenEXR header passes. */
bool exr_sizes_fit(const uint8_t* p, size_t n)
{
    if (n < 8 || p[0] != 0x76 || p[1] != 0x2f || p[2] != 0x31 || p[3] != 0x01)
        return true;
    size_t i = 8;
    for (int attr = 0; attr < 1000; ++attr) {
        for (int field = 0; field < 2; ++field) { /* name, type */
            const void* nul = i < n ? std::memchr(p + i, 0, n - i) : nullptr;
            if (!nul)
                return true; /* cut short: OpenEXR refuses it quickly */
            size_t len = static_cast<size_t>(static_cast<const uint8_t*>(nul) - (p + i));
            if (field == 0 && len == 0)
                return true; /* the end of the header */
            i += len + 1;
        }
        if (i + 4 > n)
            return true;
        uint32_t size =
            p[i] | p[i + 1] << 8 | p[i + 2] << 16 | static_cast<uint32_t>(p[i + 3]) << 24;
        i += 4;
        if (size > n - i)
            return false;
        i += size;
    }
    return true;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    OIIO::attribute("threads", 1); /* one core per fuzzer: the machine is shared */
    OIIO::attribute("exr_threads", 1);
    OIIO::attribute("try_all_readers", 0);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    if (!exr_sizes_fit(data + 1, size - 1))
        return 0;
    const char* name = kNames[data[0] % (sizeof kNames / sizeof kNames[0])];
    const char* path = tp_fuzz_write_file(name, data + 1, size - 1);
    if (!path)
        return 0;
    if (auto in = OIIO::ImageInput::open(path)) {
        const OIIO::ImageSpec& spec = in->spec();
        if (static_cast<long long>(spec.width) * spec.height * spec.nchannels > kMaxSamples)
            return 0;
    }
    (void)OIIO::geterror(); /* OpenImageIO keeps the open's error for the next caller */
    tp_image_options options = {};
    options.spacing_m = 30;
    options.zscale = 0.1;
    if (data[0] & 0x80) { /* placed on the globe: the UTM path */
        options.has_origin = 1;
        options.origin_lat_deg = 45.37;
        options.origin_lon_deg = -121.7;
    }
    tp_dem* dem = nullptr;
    tp_error err = {{0}};
    tp_status s = tp_dem_read_image(path, &options, &dem, &err);
    if (s == TP_OK) {
        TP_FUZZ_CHECK(dem && dem->width > 0 && dem->height > 0 && dem->heights,
                      "TP_OK without heights");
        tp_dem_destroy(dem);
    } else {
        TP_FUZZ_CHECK(dem == nullptr, "status %d wrote *out", (int)s);
        TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
    }
    return 0;
}
