// The silhouette coverage kept over the box of its nonzero values (core/views.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>

#include "core/views.h"

using namespace cm;

namespace {

// A w x h image with nonzero values only in [x0, x1) x [y0, y1), some fractional, some
// zero inside that box too.
std::vector<float> blob(int w, int h, int x0, int y0, int x1, int y1, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<float> v(std::size_t(w) * h, 0.0f);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const unsigned r = rng() % 4;
            v[std::size_t(y) * w + x] = r == 0 ? 0.0f : (r == 1 ? 1.0f : float(rng() % 1000) / 1000.0f);
        }
    // The box's corners are set, so the box is exactly [x0, x1) x [y0, y1).
    v[std::size_t(y0) * w + x0] = 1.0f;
    v[std::size_t(y1 - 1) * w + x1 - 1] = 0.25f;
    return v;
}

} // namespace

TEST(Coverage, KeepsTheBoxOfItsNonzeroValuesAndReadsZeroBeyondIt) {
    const int w = 37, h = 23;
    const std::vector<float> full = blob(w, h, 5, 3, 30, 20, 7);
    const Coverage c(full, w, h);
    EXPECT_EQ(c.width(), w);
    EXPECT_EQ(c.height(), h);
    EXPECT_EQ(c.size(), std::size_t(w) * h);
    EXPECT_EQ(c.x0(), 5);
    EXPECT_EQ(c.y0(), 3);
    EXPECT_EQ(c.window_width(), 25);
    EXPECT_EQ(c.window_height(), 17);
    EXPECT_EQ(c.window_values().size(), std::size_t(25 * 17));
    EXPECT_EQ(c.full(), full);
    // The box of the inside pixels, against a scan of every pixel.
    Coverage::Box in;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (full[std::size_t(y) * w + x] >= 0.5f) {
                if (in.empty()) in = {x, y, x, y};
                in = {std::min(in.x0, x), std::min(in.y0, y), std::max(in.x1, x), std::max(in.y1, y)};
            }
    ASSERT_FALSE(in.empty());
    EXPECT_EQ(c.inside_box().x0, in.x0);
    EXPECT_EQ(c.inside_box().y0, in.y0);
    EXPECT_EQ(c.inside_box().x1, in.x1);
    EXPECT_EQ(c.inside_box().y1, in.y1);
    std::size_t wrong = 0;
    for (int y = -2; y < h + 2; ++y)
        for (int x = -2; x < w + 2; ++x) {
            const bool in = x >= 0 && y >= 0 && x < w && y < h;
            const float expect = in ? full[std::size_t(y) * w + x] : 0.0f;
            wrong += c.at(x, y) != expect;
            if (in) wrong += c[std::size_t(y) * w + x] != expect;
            const float* row = c.window_row(y);
            EXPECT_EQ(row != nullptr, y >= 3 && y < 20) << y;
        }
    EXPECT_EQ(wrong, 0u);
}

TEST(Coverage, AWindowIsCutToItsNonzeroBoxAndAnEmptyOneKeepsNothing) {
    const int w = 50, h = 40;
    // A window 30 x 20 at (10, 8) whose nonzero values lie in its part [4, 21) x [2, 15).
    std::vector<float> part = blob(30, 20, 4, 2, 21, 15, 3);
    const Coverage c = Coverage::of_window(part, w, h, 10, 8, 30, 20);
    EXPECT_EQ(c.x0(), 14);
    EXPECT_EQ(c.y0(), 10);
    EXPECT_EQ(c.window_width(), 17);
    EXPECT_EQ(c.window_height(), 13);
    std::size_t wrong = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool in = x >= 10 && y >= 8 && x < 40 && y < 28;
            wrong += c.at(x, y) != (in ? part[std::size_t(y - 8) * 30 + (x - 10)] : 0.0f);
        }
    EXPECT_EQ(wrong, 0u);

    const Coverage none = Coverage::of_window(std::vector<float>(600, 0.0f), w, h, 10, 8, 30, 20);
    EXPECT_EQ(none.size(), std::size_t(w) * h);
    EXPECT_FALSE(none.empty());
    EXPECT_TRUE(none.window_values().empty());
    EXPECT_EQ(none.window_width() * none.window_height(), 0);
    EXPECT_EQ(none.at(20, 20), 0.0f);
    EXPECT_EQ(none.window_row(20), nullptr);
    EXPECT_EQ(none.full(), std::vector<float>(std::size_t(w) * h, 0.0f));
    EXPECT_TRUE(none.inside_box().empty());
    // Nonzero but nowhere inside: a window kept, no inside box.
    const Coverage faint(std::vector<float>(12, 0.3f), 4, 3);
    EXPECT_EQ(faint.window_values().size(), 12u);
    EXPECT_TRUE(faint.inside_box().empty());

    EXPECT_TRUE(Coverage().empty());
    EXPECT_THROW(Coverage::of_window(part, w, h, 30, 8, 30, 20), std::invalid_argument); // beyond the image
    EXPECT_THROW(Coverage::of_window(part, w, h, 10, 8, 30, 21), std::invalid_argument); // too few values
}

// A window handed over (an rvalue) keeps its own memory, moved into the box's layout, with
// the same values and boxes as a copy.
TEST(Coverage, AWindowHandedOverKeepsItsMemoryAndTheSameValues) {
    const int w = 50, h = 40;
    const std::vector<float> part = blob(30, 20, 4, 2, 21, 15, 11);
    const Coverage copied = Coverage::of_window(part, w, h, 10, 8, 30, 20);
    std::vector<float> handed = part;
    const float* memory = handed.data();
    const Coverage moved = Coverage::of_window(std::move(handed), w, h, 10, 8, 30, 20);
    EXPECT_EQ(moved.window_values().data(), memory);
    EXPECT_EQ(moved.window_values(), copied.window_values());
    EXPECT_EQ(moved.x0(), copied.x0());
    EXPECT_EQ(moved.y0(), copied.y0());
    EXPECT_EQ(moved.window_width(), copied.window_width());
    EXPECT_EQ(moved.window_height(), copied.window_height());
    EXPECT_EQ(moved.inside_box().x0, copied.inside_box().x0);
    EXPECT_EQ(moved.inside_box().y1, copied.inside_box().y1);
    EXPECT_EQ(moved.full(), copied.full());
    EXPECT_THROW(Coverage::of_window(std::vector<float>(5, 1.0f), w, h, 10, 8, 30, 20), std::invalid_argument);
}
