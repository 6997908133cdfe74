/* byte_raster.hpp - what the raster writers of io/ share (byte_raster.cpp): a MEM dataset
 * written in the format its path names. Private to io/. */
#pragma once

#include "tp_io.h"

#include <gdal_priv.h>

namespace tpio {

/* Writes mem (a dataset of GDAL's MEM driver, with its georeference, band description and
 * nodata) to path in the format path's extension names for kind (TP_OUTPUT_BYTE_RASTER or
 * TP_OUTPUT_FLOAT_RASTER), as tp_byte_raster_write does: encoded in a folder of /vsimem/ by
 * CreateCopy with the format's creation options, then the file and its sidecars written all or
 * none, older sidecars that the new file lacks removed. Errors as tp_byte_raster_write. */
tp_status raster_write(const char* path, tp_output_kind kind, GDALDataset* mem, tp_error* err);

} // namespace tpio
