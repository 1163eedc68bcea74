// The ink of a drawing (drawing/ink.h): thin dark strokes are ink, dark fills and the paper
// are not, only pixels inside the given mask are looked at, and the fringe is one pixel.
#include <gtest/gtest.h>

#include <vector>

#include "core/views.h"
#include "drawing/ink.h"

namespace cm {
namespace {

constexpr int kSide = 40;

// Paper at 0.8 grey with a 2-pixel vertical stroke at x = 10, 11, a dark 20 x 20 fill from
// (18, 10), and a second stroke at x = 2 (outside the mask of the tests).
Image drawing(int channels) {
    Image img;
    img.width = img.height = kSide;
    img.channels = channels;
    img.pixels.assign(std::size_t(kSide) * kSide * std::size_t(channels), 0.8f);
    const auto dark = [&](int x, int y) {
        for (int c = 0; c < channels; ++c) img.at(x, y, c) = 0.1f;
    };
    for (int y = 0; y < kSide; ++y) {
        dark(10, y);
        dark(11, y);
        dark(2, y);
    }
    for (int y = 10; y < 30; ++y)
        for (int x = 18; x < 38; ++x) dark(x, y);
    return img;
}

// Every pixel but the first five columns.
std::vector<char> mask() {
    std::vector<char> in(std::size_t(kSide) * kSide, 1);
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < 5; ++x) in[std::size_t(y) * kSide + std::size_t(x)] = 0;
    return in;
}

bool at(const std::vector<char>& m, int x, int y) { return m[std::size_t(y) * kSide + std::size_t(x)] != 0; }

TEST(Ink, AThinStrokeIsInkAndADarkFillOrThePaperIsNot) {
    for (int channels : {1, 3, 4}) {
        const auto ink = find_ink(drawing(channels), mask(), 3.0f, 0.3f, false);
        EXPECT_TRUE(at(ink, 10, 20) && at(ink, 11, 20)) << channels << " channels";
        EXPECT_FALSE(at(ink, 27, 20)) << "the middle of the fill";
        EXPECT_FALSE(at(ink, 18, 20) || at(ink, 37, 20)) << "the fill's edges";
        EXPECT_FALSE(at(ink, 14, 3) || at(ink, 9, 20) || at(ink, 12, 20)) << "the paper";
        EXPECT_FALSE(at(ink, 2, 20)) << "a stroke outside the mask is not looked at";
    }
}

TEST(Ink, AStrokeIsInkOnlyWhenNarrowerThanTheLineWidthsWindow) {
    // A 6-pixel band: wider than the window of line width 3 (5 pixels), narrower than that of 7 (9).
    Image img = drawing(3);
    for (int y = 0; y < kSide; ++y)
        for (int x = 10; x < 16; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.1f;
    EXPECT_FALSE(at(find_ink(img, mask(), 3.0f, 0.3f, false), 12, 20));
    EXPECT_TRUE(at(find_ink(img, mask(), 7.0f, 0.3f, false), 12, 20));
}

TEST(Ink, ContrastBelowTheThresholdIsNotInk) {
    const auto ink = find_ink(drawing(3), mask(), 3.0f, 0.75f, false);
    EXPECT_FALSE(at(ink, 10, 20)) << "0.7 darker than the paper, threshold 0.75";
}

TEST(Ink, TheFringeIsOnePixelAroundTheStrokeWithinTheMask) {
    const auto ink = find_ink(drawing(3), mask(), 3.0f, 0.3f, true);
    EXPECT_TRUE(at(ink, 9, 20) && at(ink, 12, 20));
    EXPECT_FALSE(at(ink, 8, 20) || at(ink, 13, 20));
    // grow_ink alone: one ink pixel grows into its eight neighbours inside the mask.
    std::vector<char> one(std::size_t(kSide) * kSide, 0), in = mask();
    one[std::size_t(20) * kSide + 6] = 1;
    const auto grown = grow_ink(one, in, kSide, kSide);
    int count = 0;
    for (char c : grown) count += c;
    EXPECT_EQ(count, 9);
    EXPECT_TRUE(at(grown, 5, 19) && at(grown, 7, 21));
    one.assign(one.size(), 0);
    one[std::size_t(20) * kSide + 5] = 1; // on the mask's edge: the column left of it is outside
    const auto edge = grow_ink(one, in, kSide, kSide);
    count = 0;
    for (char c : edge) count += c;
    EXPECT_EQ(count, 6);
    EXPECT_FALSE(at(edge, 4, 20));
}

} // namespace
} // namespace cm
