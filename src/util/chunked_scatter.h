// A counting sort of items into buckets, in a few chunks of items side by side, for the
// passes over millions of faces that group something by vertex or by block: each chunk
// counts its keys per bucket in an array of its own (no atomic increments: on 16 M faces a
// hundred million of them cost a quarter of a second), the counts give every (bucket, chunk)
// its place, and each chunk then writes its values from there. Within a bucket the values
// come in item order, whatever the threads.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace cm {

/// @brief `keys(i, emit)` calls emit(bucket, value) for each key of item i (bucket below
/// `buckets`), the same ones on both calls made per item. On return `start` (buckets + 1
/// entries) holds where each bucket begins in `out`, and `out` its values. TBB-parallel.
template <typename Keys>
void chunked_scatter(std::size_t items, std::size_t buckets, Keys&& keys, std::vector<std::uint32_t>& start,
                     std::vector<std::uint32_t>& out) {
    const std::size_t chunks = items < (std::size_t(1) << 16)
                                   ? 1
                                   : std::min<std::size_t>(8, std::max(1, tbb::this_task_arena::max_concurrency()));
    const std::size_t per = (items + chunks - 1) / chunks;
    std::vector<std::vector<std::uint32_t>> at(chunks); // per chunk: counts, then where it writes next
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
        at[k].assign(buckets, 0);
        std::uint32_t* c = at[k].data();
        for (std::size_t i = k * per, e = std::min(items, i + per); i < e; ++i)
            keys(i, [c](std::size_t b, std::uint32_t) { ++c[b]; });
    });
    start.assign(buckets + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 1 << 14), [&](const auto& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            std::uint32_t n = 0;
            for (std::size_t k = 0; k < chunks; ++k) n += at[k][b];
            start[b + 1] = n;
        }
    });
    for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 1 << 14), [&](const auto& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
            std::uint32_t next = start[b];
            for (std::size_t k = 0; k < chunks; ++k) {
                const std::uint32_t n = at[k][b];
                at[k][b] = next;
                next += n;
            }
        }
    });
    out.resize(start[buckets]);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
        std::uint32_t* c = at[k].data();
        std::uint32_t* o = out.data();
        for (std::size_t i = k * per, e = std::min(items, i + per); i < e; ++i)
            keys(i, [c, o](std::size_t b, std::uint32_t value) { o[c[b]++] = value; });
    });
}

} // namespace cm
