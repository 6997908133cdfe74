/* image_rgba.cpp - RGBA8 images in and out through OpenImageIO (screenshots, references). */
#include "io_util.hpp"
#include "tp_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace OIIO = OIIO_NAMESPACE;
using tpio::fail;

namespace {
/* OpenImageIO's writer for the format path's extension names (tp_output_format_for, a
 * screenshot), able to encode in memory; NULL after a message. */
std::unique_ptr<OIIO::ImageOutput> memory_encoder(const char* path, tp_error* err)
{
    tp_output_format fmt;
    if (tp_output_format_for(path, TP_OUTPUT_SCREENSHOT, &fmt, err) != TP_OK) {
        char list[512];
        tp_output_formats(TP_OUTPUT_SCREENSHOT, list, sizeof list);
        const std::string why = err ? err->message : path;
        fail(err, TP_ERR_INVALID_ARG, "%s; pictures are written as %s", why.c_str(), list);
        return nullptr;
    }
    auto out = OIIO::ImageOutput::create(fmt.driver);
    if (!out) {
        fail(err, TP_ERR_INVALID_ARG, "%s: no image format for this name: %s", path,
             OIIO::geterror().c_str());
        return nullptr;
    }
    if (!out->supports("ioproxy")) {
        fail(err, TP_ERR_INVALID_ARG,
             "%s: OpenImageIO's %s writer cannot encode in memory; use .png, .tif or .jpg", path,
             out->format_name());
        return nullptr;
    }
    return out;
}
} // namespace

extern "C" tp_status tp_image_output_check(const char* path, tp_error* err)
{
    if (!path)
        return fail(err, TP_ERR_INVALID_ARG, "image: bad arguments");
    tp_status s = tp_output_check(path, err);
    if (s != TP_OK)
        return s;
    try {
        return memory_encoder(path, err) ? TP_OK : TP_ERR_INVALID_ARG;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_image_write_rgba(const char* path, int w, int h, const uint8_t* rgba,
                                         tp_error* err)
{
    if (!path || !rgba || w < 1 || h < 1)
        return fail(err, TP_ERR_INVALID_ARG, "image: bad arguments");
    try {
        /* Encoded in memory, so that OpenImageIO never writes a file itself: its writers do not
         * report a full disk reliably (a cut PNG was renamed into place), and the bytes then go
         * through the one atomic writer. */
        auto out = memory_encoder(path, err);
        if (!out)
            return TP_ERR_INVALID_ARG;
        std::vector<unsigned char> bytes;
        OIIO::Filesystem::IOVecOutput vec(bytes);
        OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
        if (!out->set_ioproxy(&vec) || !out->open(path, spec) ||
            !out->write_image(OIIO::TypeDesc::UINT8, rgba) || !out->close())
            return fail(err, TP_ERR_BACKEND, "%s: OpenImageIO could not encode the image: %s", path,
                        out->geterror().c_str());
        if (bytes.empty())
            return fail(err, TP_ERR_BACKEND, "%s: OpenImageIO encoded an empty image", path);
        return tp_file_write(path, bytes.data(), bytes.size(), err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_image_read_rgba(const char* path, int* w, int* h, uint8_t** rgba,
                                        tp_error* err)
{
    if (!path || !w || !h || !rgba)
        return fail(err, TP_ERR_INVALID_ARG, "image: bad arguments");
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in)
            return fail(err, TP_ERR_IO, "%s: cannot open as an image: %s", path,
                        OIIO::geterror().c_str());
        const OIIO::ImageSpec& spec = in->spec();
        int iw = spec.width, ih = spec.height, ch = spec.nchannels;
        std::vector<uint8_t> px((size_t)iw * ih * ch);
        if (!in->read_image(0, 0, 0, ch, OIIO::TypeDesc::UINT8, px.data()))
            return fail(err, TP_ERR_BAD_DATA, "%s: cannot read the pixels: %s", path,
                        in->geterror().c_str());
        uint8_t* out = static_cast<uint8_t*>(std::malloc((size_t)iw * ih * 4));
        if (!out)
            return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        for (size_t i = 0; i < (size_t)iw * ih; i++) {
            const uint8_t* s = &px[i * ch];
            out[4 * i + 0] = s[0];
            out[4 * i + 1] = ch >= 3 ? s[1] : s[0];
            out[4 * i + 2] = ch >= 3 ? s[2] : s[0];
            out[4 * i + 3] = ch == 4 ? s[3] : ch == 2 ? s[1] : 255;
        }
        *w = iw;
        *h = ih;
        *rgba = out;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
