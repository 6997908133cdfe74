/* node_prefetch.cpp - nodes' stored bytes read ahead over HTTP (see node_prefetch.hpp). */
#include "node_prefetch.hpp"

#include <cpl_conv.h>

#include <algorithm>
#include <atomic>
#include <thread>

namespace tpio {

namespace {
/* A merged request: bytes [offset, offset + bytes) holding wants[first .. first + count). */
struct Run {
    uint64_t offset, bytes;
    size_t first, count;
};
} // namespace

void NodePrefetch::keep(int64_t node, const uint8_t* bytes, uint32_t size)
{
    std::lock_guard<std::mutex> lock(mu_);
    if (held_.count(node))
        return;
    held_[node].assign(bytes, bytes + size);
    order_.push_back(node);
    held_bytes_ += size;
    while (held_bytes_ > BUDGET_BYTES && !order_.empty()) {
        auto it = held_.find(order_.front());
        order_.pop_front();
        if (it != held_.end()) {
            held_bytes_ -= it->second.size();
            held_.erase(it);
        }
    }
}

size_t NodePrefetch::prefetch(const RangeFile& f, std::vector<Want> wants)
{
    {
        std::lock_guard<std::mutex> lock(mu_);
        wants.erase(std::remove_if(wants.begin(), wants.end(),
                                   [this](const Want& w) { return held_.count(w.node) > 0; }),
                    wants.end());
    }
    std::sort(wants.begin(), wants.end(),
              [](const Want& a, const Want& b) { return a.offset < b.offset; });
    wants.erase(std::unique(wants.begin(), wants.end(),
                            [](const Want& a, const Want& b) { return a.node == b.node; }),
                wants.end());
    std::vector<Run> runs;
    for (size_t i = 0; i < wants.size(); ++i) {
        const Want& w = wants[i];
        if (!runs.empty()) {
            Run& r = runs.back();
            const uint64_t end = r.offset + r.bytes;
            if (w.offset >= r.offset && w.offset <= end + MERGE_GAP &&
                w.offset + w.bytes - r.offset <= MERGE_MAX) {
                r.bytes = std::max(end, w.offset + w.bytes) - r.offset;
                r.count++;
                continue;
            }
        }
        runs.push_back(Run{w.offset, w.bytes, i, 1});
    }
    std::atomic<size_t> next{0};
    auto work = [&]() {
        /* no retries here: a range that fails is left to the nodes' own reads, which retry
         * (GDAL's and the stream's backoff) without holding up the others */
        const char* was = CPLGetThreadLocalConfigOption("GDAL_HTTP_MAX_RETRY", nullptr);
        const std::string saved = was ? was : "";
        CPLSetThreadLocalConfigOption("GDAL_HTTP_MAX_RETRY", "0");
        struct Restore {
            const char* was;
            const std::string& saved;
            ~Restore() { CPLSetThreadLocalConfigOption("GDAL_HTTP_MAX_RETRY", was ? saved.c_str() : nullptr); }
        } restore{was, saved};
        std::vector<uint8_t> buf;
        std::string why;
        for (size_t k; (k = next.fetch_add(1)) < runs.size();) {
            const Run& r = runs[k];
            buf.resize((size_t)r.bytes);
            const bool ok = f.read(buf.data(), buf.size(), r.offset, &why);
            {
                std::lock_guard<std::mutex> lock(mu_);
                requests_++;
                bytes_read_ += ok ? r.bytes : 0;
            }
            if (!ok)
                continue; /* the node's own read asks again and says why */
            for (size_t j = r.first; j < r.first + r.count; ++j)
                keep(wants[j].node, buf.data() + (wants[j].offset - r.offset), wants[j].bytes);
        }
    };
    const size_t threads = std::min<size_t>(runs.size(), PREFETCH_REQUESTS);
    std::vector<std::thread> pool;
    try {
        for (size_t t = 1; t < threads; ++t)
            pool.emplace_back(work);
    } catch (...) { /* no more threads: the ones started and this one read it all */
    }
    work();
    for (std::thread& t : pool)
        t.join();
    return runs.size();
}

bool NodePrefetch::get(int64_t node, std::vector<uint8_t>* out) const
{
    std::lock_guard<std::mutex> lock(mu_);
    auto it = held_.find(node);
    if (it == held_.end())
        return false;
    *out = it->second;
    return true;
}

void NodePrefetch::counts(size_t* requests, uint64_t* bytes) const
{
    std::lock_guard<std::mutex> lock(mu_);
    *requests = requests_;
    *bytes = bytes_read_;
}

} // namespace tpio
