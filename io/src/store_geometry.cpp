/* store_geometry.cpp - the tree geometry a store's header must describe, derived from n and the
 * source size as tp_core.h's "Hierarchy" section defines it, so that a reader trusts no count
 * in a file it has not recomputed (docs/store.md, "Geometry"). */
#include "store_format.hpp"

#include <algorithm>

namespace tpio {
namespace store {

bool geometry_for(int n, int src_width, int src_height, tp_tree_geometry* out)
{
    if (n < 4 || n > TP_MAX_N || src_width < 1 || src_height < 1 || src_width > (1 << 30) ||
        src_height > (1 << 30))
        return false;
    tp_tree_geometry g;
    std::memset(&g, 0, sizeof g);
    g.n = n;
    g.src_width = src_width;
    g.src_height = src_height;
    const int64_t step = (int64_t)1 << n;
    /* the fewest leaves whose samples cover the grid: cols * 2^n + 1 >= src_width */
    g.cols = (int)std::max<int64_t>(1, (src_width - 1 + step - 1) / step);
    g.rows = (int)std::max<int64_t>(1, (src_height - 1 + step - 1) / step);
    g.width = (int)(g.cols * step + 1);
    g.height = (int)(g.rows * step + 1);
    int scales = 0;
    while (scales < 31 && (g.cols >> scales) >= 1 && (g.rows >> scales) >= 1)
        ++scales;
    if (scales > TP_TREE_MAX_SCALES)
        return false;
    g.scales = scales;
    for (int s = 0; s < TP_TREE_MAX_SCALES; ++s) {
        g.node_cols[s] = g.cols >> s;
        g.node_rows[s] = g.rows >> s;
    }
    int64_t id = 0;
    for (int s = scales - 1; s >= 0; --s) {
        g.first_node[s] = id;
        id += (int64_t)g.node_cols[s] * g.node_rows[s];
    }
    g.node_count = id;
    /* roots: every node of the top scale, and below it the nodes whose parent (c/2, r/2) does
     * not exist */
    int64_t roots = (int64_t)g.node_cols[scales - 1] * g.node_rows[scales - 1];
    for (int s = 0; s + 1 < scales; ++s) {
        const int64_t covered_c = std::min<int64_t>(g.node_cols[s], 2 * (int64_t)g.node_cols[s + 1]);
        const int64_t covered_r = std::min<int64_t>(g.node_rows[s], 2 * (int64_t)g.node_rows[s + 1]);
        roots += (int64_t)g.node_cols[s] * g.node_rows[s] - covered_c * covered_r;
    }
    g.root_count = roots;
    *out = g;
    return true;
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
    int scale = 0;
    while (scale + 1 < g.scales && id < g.first_node[scale])
        ++scale;
    const int64_t k = id - g.first_node[scale];
    *s = scale;
    *c = (int)(k % g.node_cols[scale]);
    *r = (int)(k / g.node_cols[scale]);
}

} // namespace store
} // namespace tpio
