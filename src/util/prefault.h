// Fresh memory costs a page fault on its first touch, taken by the thread that touches it, and
// std::vector::resize touches (zeroes) all of it from one thread: for the largest arrays
// (Marching Cubes' triangles at 4096, 1.2 GB) the faults alone take seconds on one core while
// the other waits. reserve_prefaulted() reserves the storage and has the kernel map its pages
// from every worker first (madvise MADV_POPULATE_WRITE, Linux 5.14 and later), so the resize
// that follows writes to pages already there. Where the kernel cannot, nothing changes.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cm {

/// Reserves room for `n` elements in `v` and maps the pages of the room not yet in use ahead
/// of the first touch, in parallel. Below `min_bytes` it only reserves.
template <typename T, typename A>
void reserve_prefaulted(std::vector<T, A>& v, std::size_t n, std::size_t min_bytes = std::size_t(64) << 20) {
    v.reserve(n);
#ifdef MADV_POPULATE_WRITE
    if (n <= v.size() || (n - v.size()) * sizeof(T) < min_bytes) return;
    const auto page = std::uintptr_t(sysconf(_SC_PAGESIZE));
    const auto from = (reinterpret_cast<std::uintptr_t>(v.data() + v.size()) + page - 1) / page * page;
    const auto to = reinterpret_cast<std::uintptr_t>(v.data() + n) / page * page;
    if (to <= from) return;
    constexpr std::uintptr_t kChunk = std::uintptr_t(16) << 20; // a multiple of any page size
    tbb::parallel_for(tbb::blocked_range<std::uintptr_t>(0, (to - from + kChunk - 1) / kChunk, 1), [&](const auto& r) {
        for (auto c = r.begin(); c != r.end(); ++c) {
            const std::uintptr_t a = from + c * kChunk, b = std::min(to, a + kChunk);
            // Failure (an older kernel: EINVAL) only leaves the faults to the first touch.
            (void)madvise(reinterpret_cast<void*>(a), b - a, MADV_POPULATE_WRITE);
        }
    });
#endif
}

} // namespace cm
