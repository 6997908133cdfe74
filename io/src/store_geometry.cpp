/* store_geometry.cpp - the tree geometry a store's header must describe: tp_tree_geometry_init
 * of n and the source size, so that a reader trusts no count in a file it has not recomputed
 * (docs/store.md, "Header"); and a node's place, for the messages. */
#include "store_format.hpp"

namespace tpio {
namespace store {

bool geometry_for(int n, int src_width, int src_height, tp_tree_geometry* out)
{
    if (n < 4 || n > TP_MAX_N)
        return false;
    return tp_tree_geometry_init(src_width, src_height, (1 << n) + 1, out, nullptr) == TP_OK;
}

bool geometry_same(const tp_tree_geometry& got, const tp_tree_geometry& want, std::string* why)
{
    struct Field {
        const char* name;
        int64_t got, want;
    };
    const Field fields[] = {
        {"n", got.n, want.n},
        {"src_width", got.src_width, want.src_width},
        {"src_height", got.src_height, want.src_height},
        {"width", got.width, want.width},
        {"height", got.height, want.height},
        {"cols", got.cols, want.cols},
        {"rows", got.rows, want.rows},
        {"scales", got.scales, want.scales},
        {"node_count", got.node_count, want.node_count},
        {"root_count", got.root_count, want.root_count},
    };
    for (const Field& f : fields)
        if (f.got != f.want) {
            *why = std::string(f.name) + " " + std::to_string(f.got) + ", expected " +
                   std::to_string(f.want);
            return false;
        }
    for (int s = 0; s < want.scales && s < TP_TREE_MAX_SCALES; ++s) {
        const Field per[] = {{"node_cols", got.node_cols[s], want.node_cols[s]},
                             {"node_rows", got.node_rows[s], want.node_rows[s]},
                             {"first_node", got.first_node[s], want.first_node[s]}};
        for (const Field& f : per)
            if (f.got != f.want) {
                *why = std::string(f.name) + "[" + std::to_string(s) + "] " +
                       std::to_string(f.got) + ", expected " + std::to_string(f.want);
                return false;
            }
    }
    return true;
}

void node_locate(const tp_tree_geometry& g, int64_t id, int* s, int* c, int* r)
{
    tp_tree_node_locate(&g, id, s, c, r);
}

} // namespace store
} // namespace tpio
