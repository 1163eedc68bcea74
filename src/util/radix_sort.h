// A stable LSD radix sort by an unsigned key, TBB-parallel: per pass, each chunk of the array
// counts its digits, the counts give every (digit, chunk) its place, and the chunks scatter
// side by side. Stable, so elements with equal keys keep their order (an array filled in
// index order comes out sorted by (key, index)); the order is the same whatever the threads.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

namespace cm {

/// @brief Sorts `a` (a vector) by key(a[i]) (an unsigned integer below 2^bits), stably.
template <typename Vec, typename Key>
void radix_sort(Vec& a, Key&& key, int bits) {
    using T = typename Vec::value_type;
    constexpr int kDigit = 11;
    constexpr std::size_t kBuckets = std::size_t(1) << kDigit;
    const std::size_t n = a.size();
    if (n < 2 || bits <= 0) return;
    const std::size_t chunk = std::max<std::size_t>(std::size_t(1) << 16, (n + 63) / 64);
    const std::size_t chunks = (n + chunk - 1) / chunk;
    Vec b(n);
    std::vector<std::size_t> count(chunks * kBuckets);
    for (int shift = 0; shift < bits; shift += kDigit) {
        auto digit = [&](const T& x) { return std::size_t((std::uint64_t(key(x)) >> shift) & (kBuckets - 1)); };
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            std::size_t* h = count.data() + c * kBuckets;
            std::fill(h, h + kBuckets, std::size_t(0));
            for (std::size_t i = c * chunk, e = std::min(n, i + chunk); i < e; ++i) ++h[digit(a[i])];
        });
        std::size_t at = 0; // digit-major, chunk-minor: the chunks' runs of a digit in order
        for (std::size_t d = 0; d < kBuckets; ++d)
            for (std::size_t c = 0; c < chunks; ++c) {
                const std::size_t k = count[c * kBuckets + d];
                count[c * kBuckets + d] = at;
                at += k;
            }
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            std::size_t* h = count.data() + c * kBuckets;
            for (std::size_t i = c * chunk, e = std::min(n, i + chunk); i < e; ++i) b[h[digit(a[i])]++] = a[i];
        });
        a.swap(b);
    }
}

} // namespace cm
