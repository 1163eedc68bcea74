// reserve_prefaulted (util/prefault.h): reserves like std::vector::reserve, leaves what the
// vector holds as it was, and has the kernel map the new room's pages ahead of the first touch.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include "util/prefault.h"

using namespace cm;

namespace {

std::vector<std::uint32_t> pattern(std::size_t n) {
    std::vector<std::uint32_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = std::uint32_t(i * 2654435761u);
    return v;
}

// Resident pages of this process (/proc/self/statm, second field).
long resident_pages() {
    std::ifstream f("/proc/self/statm");
    long size = 0, resident = -1;
    f >> size >> resident;
    return resident;
}

} // namespace

TEST(Prefault, KeepsTheContentsAndReserves) {
    std::vector<std::uint32_t> v = pattern(10007); // a few pages, the last one partly used
    const auto want = v;
    reserve_prefaulted(v, std::size_t(5) << 20, 0);
    EXPECT_GE(v.capacity(), std::size_t(5) << 20);
    ASSERT_EQ(v, want);
    v.resize(std::size_t(5) << 20);
    for (std::size_t i = 0; i < want.size(); ++i) ASSERT_EQ(v[i], want[i]);
    for (std::size_t i = want.size(); i < v.size(); ++i) ASSERT_EQ(v[i], 0u) << i;
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i);
    for (std::size_t i = 0; i < v.size(); i += 4099) ASSERT_EQ(v[i], std::uint32_t(i));
}

TEST(Prefault, SmallerThanTheSizeOrBelowTheThresholdOnlyReserves) {
    std::vector<std::uint32_t> v = pattern(1000);
    const auto want = v;
    const std::size_t cap = v.capacity();
    reserve_prefaulted(v, 10); // fewer than it holds: nothing to do
    EXPECT_EQ(v.capacity(), cap);
    EXPECT_EQ(v, want);
    reserve_prefaulted(v, 4000); // 12 KB, under the 64 MB threshold: a plain reserve
    EXPECT_GE(v.capacity(), std::size_t(4000));
    EXPECT_EQ(v, want);
    std::vector<std::uint32_t> empty;
    reserve_prefaulted(empty, 0, 0);
    EXPECT_TRUE(empty.empty());
}

TEST(Prefault, MapsThePagesAhead) {
#ifndef MADV_POPULATE_WRITE
    GTEST_SKIP() << "this system's headers have no MADV_POPULATE_WRITE";
#else
    // Whether the kernel knows the advice (Linux 5.14 and later).
    const long page = sysconf(_SC_PAGESIZE);
    void* probe = mmap(nullptr, std::size_t(page), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(probe, MAP_FAILED);
    const bool known = madvise(probe, std::size_t(page), MADV_POPULATE_WRITE) == 0;
    munmap(probe, std::size_t(page));
    if (!known) GTEST_SKIP() << "this kernel does not know MADV_POPULATE_WRITE";
    if (resident_pages() < 0) GTEST_SKIP() << "no /proc/self/statm";
    const std::size_t bytes = std::size_t(96) << 20;
    std::vector<std::uint8_t> v;
    const long before = resident_pages();
    reserve_prefaulted(v, bytes);
    const long after = resident_pages();
    EXPECT_TRUE(v.empty());
    // Nothing was written, yet (nearly) all of the room is resident.
    EXPECT_GE(double(after - before) * double(page), 0.9 * double(bytes)) << before << " -> " << after << " pages";
#endif
}
