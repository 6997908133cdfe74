/*
 * tp_io/input.h - the checks every command makes on a path it is about to read, and the name a
 * cache gives an input file.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_INPUT_H
#define TP_IO_INPUT_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Inputs (io/src/input_file.cpp): how every command checks a path it is about to read, and
 * names it for the store cache.
 */

/* Refuses, in one line naming path, an input that is not a regular file before anything opens
 * it: a FIFO (opening it waits for a writer, forever if none comes), a character or block
 * device (/dev/zero never ends), a socket, a missing path, and a directory unless
 * allow_directory (a raster can be one: an ArcInfo binary grid). `what` is what the file
 * should have been ("a route file (GPX, GeoJSON, KML, CSV)"). A GDAL virtual path (/vsizip/,
 * /vsigzip/, /vsitar/, /vsicurl/, ...) is asked of GDAL's virtual file system (VSIStatL): one
 * it cannot find is "PATH: cannot open: no such file (GDAL virtual path)"; the local archive
 * such a path reads (/vsizip/DIR/a.zip/...) must be a regular file. TP_ERR_IO with a message
 * starting with the path; TP_OK otherwise. */
tp_status tp_input_check(const char* path, const char* what, int allow_directory, tp_error* err);

/* 1 when path is a GDAL virtual path ("/vsi" followed by a handler name and '/'). */
int tp_input_is_virtual(const char* path);

/* 1 when path is an http:// or https:// URL (the scheme in any case): terrapatch's own files
 * (stores, imagery pyramids, light maps) are read from one with range requests (tp_store_open,
 * tp_imagery_open). */
int tp_input_is_url(const char* path);
/* The first n bytes of the file at url into head (a HEAD and a range request through GDAL's
 * /vsicurl/, whose cache keeps them for the open that follows). TP_ERR_IO naming url when the
 * server does not have the file, cannot be reached or sends fewer bytes. */
tp_status tp_input_url_head(const char* url, unsigned char* head, size_t n, tp_error* err);

/* What names an input file for a cache: its absolute path (a relative path made absolute, as
 * realpath does; in a virtual path, the archive's path after /vsizip/, /vsigzip/, /vsitar/,
 * /vsi7z/ or /vsirar/ made absolute, so that the name reads the same file from any folder),
 * its size and its modification time (ns since the epoch; for a member of a local archive, the
 * archive's time, and its size mixed into the member's).
 * Call tp_input_check first: this only names. TP_ERR_IO naming path when it cannot be found;
 * TP_ERR_INVALID_ARG when the absolute path does not fit cap bytes. */
typedef struct tp_input_identity {
    int64_t size_bytes;
    int64_t mtime_ns;
} tp_input_identity;
tp_status tp_input_identify(const char* path, char* abs_path, size_t cap, tp_input_identity* out,
                            tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_INPUT_H */
