/*
 * gzip.cpp - gzip streams in memory with zlib (see tp_io/gzip.h).
 */
#include "io_util.hpp"
#include "tp_io.h"

#include <cstdlib>
#include <cstring>
#include <zlib.h>

using tpio::fail;

tp_status tp_gzip(const void* data, size_t size, int level, uint8_t** out, size_t* out_size,
                  tp_error* err)
{
    if ((!data && size) || !out || !out_size || level < 1 || level > 9)
        return fail(err, TP_ERR_INVALID_ARG, "tp_gzip: bad arguments");
    if (size > 0x7fffffffu)
        return fail(err, TP_ERR_INVALID_ARG, "tp_gzip: %zu bytes is more than one call takes",
                    size);
    z_stream z;
    std::memset(&z, 0, sizeof z);
    /* windowBits 15 + 16: a gzip header and trailer, not zlib's */
    if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "zlib: deflateInit2 failed");
    const size_t cap = deflateBound(&z, (uLong)size) + 32;
    uint8_t* buf = (uint8_t*)std::malloc(cap);
    if (!buf) {
        deflateEnd(&z);
        return fail(err, TP_ERR_OUT_OF_MEMORY, "out of memory compressing %zu bytes", size);
    }
    z.next_in = (Bytef*)data;
    z.avail_in = (uInt)size;
    z.next_out = buf;
    z.avail_out = (uInt)cap;
    const int rc = deflate(&z, Z_FINISH);
    const size_t got = cap - z.avail_out;
    deflateEnd(&z);
    if (rc != Z_STREAM_END) {
        std::free(buf);
        return fail(err, TP_ERR_BACKEND, "zlib: deflate failed (%d)", rc);
    }
    *out = buf;
    *out_size = got;
    return TP_OK;
}

tp_status tp_gunzip(const void* data, size_t size, uint8_t** out, size_t* out_size, tp_error* err)
{
    if ((!data && size) || !out || !out_size || size > 0x7fffffffu)
        return fail(err, TP_ERR_INVALID_ARG, "tp_gunzip: bad arguments");
    z_stream z;
    std::memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 16) != Z_OK)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "zlib: inflateInit2 failed");
    size_t cap = size * 4 + 1024, n = 0;
    uint8_t* buf = (uint8_t*)std::malloc(cap);
    z.next_in = (Bytef*)data;
    z.avail_in = (uInt)size;
    int rc = Z_OK;
    while (buf) {
        z.next_out = buf + n;
        z.avail_out = (uInt)(cap - n);
        rc = inflate(&z, Z_NO_FLUSH);
        n = cap - z.avail_out;
        if (rc != Z_OK)
            break;
        if (z.avail_out == 0) {
            uint8_t* b2 = (uint8_t*)std::realloc(buf, cap * 2);
            if (!b2) {
                std::free(buf);
                buf = nullptr;
                break;
            }
            buf = b2;
            cap *= 2;
        } else if (z.avail_in == 0) {
            break; /* input used up before the stream's end */
        }
    }
    inflateEnd(&z);
    if (!buf)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "out of memory decompressing %zu bytes", size);
    if (rc != Z_STREAM_END) {
        std::free(buf);
        return fail(err, TP_ERR_BAD_DATA, "not a whole gzip stream (zlib: %s)",
                    z.msg ? z.msg : "cut short");
    }
    *out = buf;
    *out_size = n;
    return TP_OK;
}
