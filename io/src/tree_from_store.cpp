/* tree_from_store.cpp - a tree over an open store: the header's geometry and quantisation, the
 * store's mapped metas (tp_tree_create_from_store in tp_io.h). Every reader of a store (the
 * viewer, export, the stream tests and benches) makes its tree this way. */
#include "tp_io.h"

#include <cassert>
#include <cstring>

extern "C" tp_status tp_tree_create_from_store(const tp_store* s, tp_tree** out, tp_error* err)
{
    /* C calls only: nothing here throws */
    assert(s && out);
    tp_store_info si;
    tp_store_get_info(s, &si);
    size_t count = 0;
    tp_tree_desc td;
    std::memset(&td, 0, sizeof td);
    td.geometry = si.header.geometry;
    std::memcpy(td.geotransform, si.header.geotransform, sizeof td.geotransform);
    td.height_step_m = si.header.height_step_m;
    td.quant_max_error_m = si.header.quant_max_error_m;
    td.err_unit_steps = si.header.err_unit_steps;
    td.metas = tp_store_metas(s, &count);
    td.meta_count = count;
    return tp_tree_create(&td, out, err);
}
