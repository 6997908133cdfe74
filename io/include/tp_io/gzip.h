/*
 * tp_io/gzip.h - bytes gzip-compressed in memory (zlib; io/src/gzip.cpp), as web servers send
 * files with Content-Encoding: gzip (Cesium's terrain tiles). Part of tp_io.h, which includes
 * it; the error conventions stated there hold here. C11.
 */
#ifndef TP_IO_GZIP_H
#define TP_IO_GZIP_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Compresses size bytes of data (level 1..9; 6 is zlib's default) into a new buffer *out of
 * *out_size bytes, a gzip stream (RFC 1952) gunzip reads; free it with free(). */
tp_status tp_gzip(const void* data, size_t size, int level, uint8_t** out, size_t* out_size,
                  tp_error* err);

/* Decompresses a whole gzip stream into a new buffer (free()); TP_ERR_BAD_DATA for a stream
 * that is not gzip or is cut short. */
tp_status tp_gunzip(const void* data, size_t size, uint8_t** out, size_t* out_size,
                    tp_error* err);

#ifdef __cplusplus
}
#endif
#endif
