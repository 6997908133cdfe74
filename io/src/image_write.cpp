/* image_write.cpp - RGBA8 images in and out through OpenImageIO (screenshots, references). */
#include "io_util.hpp"
#include "tp_io.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <exception>
#include <string>
#include <unistd.h>
#include <vector>

namespace OIIO = OIIO_NAMESPACE;
using tpio::fail;

extern "C" tp_status tp_image_write_rgba(const char* path, int w, int h, const uint8_t* rgba,
                                         tp_error* err)
{
    if (!path || !rgba || w < 1 || h < 1)
        return fail(err, TP_ERR_INVALID_ARG, "image: bad arguments");
    std::string tmp;
    try {
        /* the temporary keeps the extension so OpenImageIO picks the same format */
        std::string p = path;
        size_t slash = p.find_last_of('/'), dot = p.find_last_of('.');
        std::string ext = dot != std::string::npos && (slash == std::string::npos || dot > slash)
                              ? p.substr(dot) : std::string(".png");
        tmp = p + ".tmp" + std::to_string((long)getpid()) + ext;
        /* A clear reason (no such directory, permission) before the image library's own. */
        if (FILE* probe = std::fopen(tmp.c_str(), "wb"))
            std::fclose(probe);
        else
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path, std::strerror(errno));
        auto out = OIIO::ImageOutput::create(tmp);
        if (!out) {
            std::remove(tmp.c_str());
            return fail(err, TP_ERR_INVALID_ARG, "%s: no image format for this name: %s", path,
                        OIIO::geterror().c_str());
        }
        OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
        if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgba) || !out->close()) {
            std::string why = out->geterror();
            std::remove(tmp.c_str());
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path, why.c_str());
        }
        if (std::rename(tmp.c_str(), path) != 0) {
            std::remove(tmp.c_str());
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path, std::strerror(errno));
        }
        return TP_OK;
    } catch (...) {
        if (!tmp.empty())
            std::remove(tmp.c_str());
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
