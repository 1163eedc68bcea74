// The radix sort the geometry indices sort their entries with: stable, equal to std::stable_sort.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "util/radix_sort.h"

using namespace cm;

TEST(RadixSort, EqualsAStableSortForEveryKeyWidth) {
    std::mt19937_64 rng(3);
    for (int bits : {1, 7, 11, 12, 22, 33, 64})
        for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(300000)}) {
            struct Item {
                std::uint64_t key;
                std::uint32_t index;
            };
            std::vector<Item> a(n);
            const std::uint64_t mask = bits == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << bits) - 1;
            for (std::size_t i = 0; i < n; ++i) a[i] = {rng() & mask & (i % 3 ? mask : 0xFF), std::uint32_t(i)};
            std::vector<Item> want = a;
            std::stable_sort(want.begin(), want.end(), [](const Item& x, const Item& y) { return x.key < y.key; });
            radix_sort(
                a, [](const Item& x) { return x.key; }, bits);
            ASSERT_EQ(a.size(), want.size());
            for (std::size_t i = 0; i < n; ++i)
                ASSERT_TRUE(a[i].key == want[i].key && a[i].index == want[i].index)
                    << "bits " << bits << " n " << n << " at " << i;
        }
}
