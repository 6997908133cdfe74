/* node_prefetch.hpp - nodes' stored bytes read ahead over HTTP, many ranges in flight at once,
 * and kept until their reader asks (store_read.cpp: tp_store_prefetch). A reader over HTTP that
 * asks for one node at a time waits a round trip for each; one that knows the nodes it will
 * need (the roots and the coarse scales before a first frame, the leaves a screen-error measure
 * samples, a normal-map block's nodes) hands them here first: their ranges are sorted, those
 * closer than a gap merged into one request, and the requests made by up to PREFETCH_REQUESTS
 * threads at once (RangeFile::read, one pooled handle each). The bytes are kept, the oldest
 * dropped first past a budget, and copied out on each read: the reader still checks them
 * against the node's CRC32, and they were read with the same If-Match as any other read, so a
 * file replaced on the server is never mixed in. Private to io/. */
#pragma once

#include "range_file.hpp"

#include <cstdint>
#include <deque>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace tpio {

class NodePrefetch {
public:
    /* A node's stored range (its location table entry). */
    struct Want {
        int64_t node;
        uint64_t offset;
        uint32_t bytes;
    };
    static constexpr int PREFETCH_REQUESTS = 16;     /* threads, each one request in flight */
    static constexpr uint64_t MERGE_GAP = 16 << 10;  /* ranges closer than this: one request */
    static constexpr uint64_t MERGE_MAX = 512 << 10; /* a merged request at most this long */
    static constexpr size_t BUDGET_BYTES = 64 << 20; /* kept at most; the oldest dropped first */

    /* Reads the wanted ranges not held yet from f, concurrently; failures are dropped (the
     * node's own read asks again and reports). Returns the number of requests made. */
    size_t prefetch(const RangeFile& f, std::vector<Want> wants);
    /* The bytes held for node into out (resized to them): true; false when none are held. */
    bool get(int64_t node, std::vector<uint8_t>* out) const;
    /* Ranges (requests) and bytes read so far (tests, measurements). */
    void counts(size_t* requests, uint64_t* bytes) const;

private:
    void keep(int64_t node, const uint8_t* bytes, uint32_t size);
    mutable std::mutex mu_;
    std::unordered_map<int64_t, std::vector<uint8_t>> held_;
    std::deque<int64_t> order_; /* insertion order, for the budget */
    size_t held_bytes_ = 0;
    size_t requests_ = 0;
    uint64_t bytes_read_ = 0;
};

} // namespace tpio
