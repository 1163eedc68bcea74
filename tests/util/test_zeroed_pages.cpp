// zeroed_pages (util/zeroed_pages.h): zeroed memory of its own, whatever the allocator holds,
// whose pages the kernel maps only where it is touched.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include "util/zeroed_pages.h"

using namespace cm;

TEST(ZeroedPages, ZeroedEvenWhereTheAllocatorHadDirtyMemory) {
    // A block freed dirty: a calloc of the same size may get it back and clear it; the
    // mapping never holds its bytes.
    const std::size_t n = std::size_t(8) << 20;
    auto* dirty = static_cast<unsigned char*>(std::malloc(n));
    ASSERT_NE(dirty, nullptr);
    std::memset(dirty, 0xAB, n);
    std::free(dirty);
    const auto z = zeroed_pages<std::uint64_t>(n / 8);
    ASSERT_NE(z.get(), nullptr);
    std::uint64_t any = 0;
    for (std::size_t i = 0; i < n / 8; i += 511) any |= z[i];
    EXPECT_EQ(any, 0u);
    z[n / 8 - 1] = 7; // the last element is writable
    EXPECT_EQ(z[n / 8 - 1], 7u);
}

TEST(ZeroedPages, OnlyTheTouchedPagesAreMapped) {
    const long page = ::sysconf(_SC_PAGESIZE);
    const std::size_t pages = 4096; // 16 MB of 4 kB pages
    const auto z = zeroed_pages<unsigned char>(pages * std::size_t(page));
    z[0] = 1;
    std::vector<unsigned char> in(pages);
    ASSERT_EQ(::mincore(z.get(), pages * std::size_t(page), in.data()), 0);
    std::size_t mapped = 0;
    for (unsigned char c : in) mapped += c & 1;
    EXPECT_GE(mapped, 1u);
    // At most one huge page (2 MB) about the one touched.
    EXPECT_LE(mapped * std::size_t(page), std::size_t(2) << 20);
}

TEST(ZeroedPages, NoElementsNoMapping) {
    using Block = std::array<std::uint64_t, 8>;
    EXPECT_EQ(zeroed_pages<Block>(0).get(), nullptr);
}
