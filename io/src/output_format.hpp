/* output_format.hpp - what the writers of io/ need of output_format.cpp besides tp_io.h: the
 * GDAL driver an output path is written with. Private to io/. */
#pragma once

#include "tp_io.h"

#include <gdal_priv.h>

namespace tpio {

/* The driver tp_output_format_for chose for path (kind TP_OUTPUT_BYTE_RASTER,
 * TP_OUTPUT_FLOAT_RASTER or TP_OUTPUT_VECTOR) and, for a raster, the creation options it is written
 * with (NULL-ended, static). Fails as tp_output_format_for; *drv and *options written only on
 * success. */
tp_status output_driver(const char* path, tp_output_kind kind, GDALDriver** drv,
                        const char* const** options, tp_error* err);

} // namespace tpio
