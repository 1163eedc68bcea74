#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/distance_transform.h"

using namespace cm;

namespace {

// A mask of discs, boxes and pinholes, some of them cut by the image border.
std::vector<char> random_mask(int w, int h, std::mt19937& rng) {
    std::vector<char> m(std::size_t(w) * h, 0);
    std::uniform_int_distribution<int> px(-w / 4, w + w / 4), py(-h / 4, h + h / 4), size(0, std::max(w, h) / 3);
    const int shapes = 1 + int(rng() % 6);
    for (int k = 0; k < shapes; ++k) {
        const int cx = px(rng), cy = py(rng), r = size(rng), disc = int(rng() % 2);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int dx = x - cx, dy = y - cy;
                if (disc ? dx * dx + dy * dy <= r * r : std::abs(dx) <= r && std::abs(dy) <= r / 2)
                    m[std::size_t(y) * w + x] = 1;
            }
    }
    for (int k = int(rng() % 20); k > 0; --k) m[rng() % m.size()] ^= 1; // pinholes and specks
    return m;
}

// squared_edt_signed() against squared_edt() of either kind: the same value for every inside
// pixel and every outside pixel within reach, infinity for the others.
void expect_signed_matches(const std::vector<char>& inside, int w, int h, int reach) {
    std::vector<char> outside(inside.size());
    for (std::size_t i = 0; i < inside.size(); ++i) outside[i] = !inside[i];
    const std::vector<float> to_in = squared_edt(inside, w, h), to_out = squared_edt(outside, w, h);
    std::vector<float> got(inside.size(), -1.0f);
    squared_edt_signed(inside.data(), w, h, reach,
                       [&](int y, const float* row) { std::copy(row, row + w, got.begin() + std::ptrdiff_t(y) * w); });
    const float r2 = float(reach * reach);
    for (std::size_t i = 0; i < inside.size(); ++i) {
        const float want = inside[i] ? to_out[i] : (to_in[i] <= r2 ? to_in[i] : std::numeric_limits<float>::infinity());
        ASSERT_EQ(got[i], want) << "pixel " << i % std::size_t(w) << "," << i / std::size_t(w) << " of " << w << "x"
                                << h << ", reach " << reach;
    }
}

} // namespace

// The signed transform on shapes of every kind and size (one pixel, one row, one column, more
// columns than one strip of the column pass), with small and large reaches.
TEST(DistanceTransform, SignedMatchesBothTransformsWithinReach) {
    std::mt19937 rng(7);
    const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {5, 5}, {64, 48}, {300, 70}, {70, 260}};
    for (const auto& s : sizes)
        for (int trial = 0; trial < 12; ++trial) {
            const std::vector<char> mask = random_mask(s[0], s[1], rng);
            for (int reach : {1, 3, 8, 40}) expect_signed_matches(mask, s[0], s[1], reach);
        }
    // All inside: kEdtFar; all outside: nothing within reach.
    expect_signed_matches(std::vector<char>(60 * 40, 1), 60, 40, 8);
    expect_signed_matches(std::vector<char>(60 * 40, 0), 60, 40, 8);
}

// The row pass of the transform works in float; its distances are those of brute force on
// sparse seeds far apart (long rows of large values), the case where rounding would show.
TEST(DistanceTransform, MatchesBruteForceOnSparseSeeds) {
    std::mt19937 rng(11);
    const int w = 320, h = 180;
    for (int trial = 0; trial < 4; ++trial) {
        std::vector<char> seed(std::size_t(w) * h, 0);
        std::vector<std::array<int, 2>> seeds;
        for (int k = 3 + trial * 5; k > 0; --k) {
            const int x = int(rng() % w), y = int(rng() % h);
            seed[std::size_t(y) * w + x] = 1;
            seeds.push_back({x, y});
        }
        const std::vector<float> d = squared_edt(seed, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::int64_t best = std::numeric_limits<std::int64_t>::max();
                for (const auto& s : seeds)
                    best = std::min<std::int64_t>(
                        best, std::int64_t(s[0] - x) * (s[0] - x) + std::int64_t(s[1] - y) * (s[1] - y));
                ASSERT_EQ(d[std::size_t(y) * w + x], float(best)) << x << "," << y << " trial " << trial;
            }
    }
}
