#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "core/views.h"
#include "drawing/fill.h"

using namespace cm;

namespace {

// A 60 x 60 sheet of white paper with the square [lo, hi)^2 painted by `paint(x, y, channel)`;
// `inside` marks the square.
template <class Paint>
Image square_on_paper(std::vector<char>& inside, int lo, int hi, Paint paint) {
    Image img;
    img.width = img.height = 60;
    img.channels = 3;
    img.pixels.assign(60 * 60 * 3, 1.0f);
    inside.assign(60 * 60, 0);
    for (int y = lo; y < hi; ++y)
        for (int x = lo; x < hi; ++x) {
            inside[std::size_t(y) * 60 + x] = 1;
            for (int k = 0; k < 3; ++k) img.at(x, y, k) = paint(x, y, k);
        }
    return img;
}

// A 60 x 60 grey-on-white drawing: a square of fill (0.6, 0.2, 0.4) from 10 to 50, crossed by
// vertical white slivers (1 px) every 6 px and dark strokes (1 px) between them.
Image marker_square(std::vector<char>& inside) {
    return square_on_paper(inside, 10, 50, [](int x, int, int k) {
        const float c[3] = {0.6f, 0.2f, 0.4f};
        if (x % 6 == 0) return 0.98f;       // paper between strokes
        if (x % 6 == 3) return c[k] * 0.4f; // a stroke over another
        return c[k];
    });
}

} // namespace

TEST(Fill, PaperSliversAreTheThinLightPaperColouredPixelsOnly) {
    std::vector<char> inside;
    const Image img = marker_square(inside);
    const auto paper = paper_colour(img, inside);
    EXPECT_NEAR(paper[0], 1.0f, 1e-6f);
    const std::vector<char> s = find_paper_slivers(img, inside, paper, 4, 0.12f);
    for (int y = 12; y < 48; ++y)
        for (int x = 12; x < 48; ++x) EXPECT_EQ(s[std::size_t(y) * 60 + x] != 0, x % 6 == 0) << x << "," << y;
    // Outside the silhouette nothing is looked at.
    EXPECT_EQ(s[5 * 60 + 5], 0);
}

TEST(Fill, TheFillUnderStrokesIsTheMeanOfTheKeptPixels) {
    std::vector<char> inside;
    const Image img = marker_square(inside);
    std::vector<char> keep(inside.size()), strokes(inside.size());
    for (int y = 0; y < 60; ++y)
        for (int x = 0; x < 60; ++x) {
            const std::size_t i = std::size_t(y) * 60 + x;
            strokes[i] = inside[i] && (x % 6 == 0 || x % 6 == 3);
            keep[i] = inside[i] && !strokes[i];
        }
    std::vector<float> share;
    const auto fill = fill_under_strokes(img, keep, strokes, 3, share);
    for (int y = 15; y < 45; ++y)
        for (int x = 15; x < 45; ++x) {
            const std::size_t i = std::size_t(y) * 60 + x;
            EXPECT_NEAR(fill[i][0], 0.6f, 1e-5f);
            EXPECT_NEAR(fill[i][1], 0.2f, 1e-5f);
            EXPECT_NEAR(fill[i][2], 0.4f, 1e-5f);
            // 2 or 3 of the window's 7 columns are strokes (every third column).
            EXPECT_TRUE(share[i] > 2.0f / 7 - 1e-5f && share[i] < 3.0f / 7 + 1e-5f) << share[i];
        }
    // Far from any kept pixel, a pixel keeps its own colour.
    EXPECT_FLOAT_EQ(fill[0][0], 1.0f);
    EXPECT_FLOAT_EQ(share[0], 0.0f);
}

TEST(Fill, PaleStreaksAreThinRepeatedAndTowardsThePaper) {
    // Left half: a fill (0.3, 0.5, 0.7) with dry streaks (1 px, a third of the way to the
    // white paper) every 6 px; right half: a band drawn as pale as a streak, 20 px wide, and a
    // thin line of another hue (orange) as pale. Only the streaks are taken.
    const float fill[3] = {0.3f, 0.5f, 0.7f}, orange[3] = {0.9f, 0.6f, 0.3f};
    std::vector<char> inside;
    const Image img = square_on_paper(inside, 5, 55, [&](int x, int, int k) {
        const bool streak = x < 30 && x % 6 == 0, band = x >= 36 && x < 56, line = x == 32;
        float v = fill[k];
        if (streak || band) v += 0.35f * (1 - v);
        return line ? orange[k] : v;
    });
    // The fill around as texturing takes it: the mean over 17 x 17 px, across the band's edge.
    std::vector<float> share;
    const auto around = fill_under_strokes(img, inside, std::vector<char>(60 * 60, 0), 8, share);
    const auto pale = find_pale_streaks(img, inside, around, {1, 1, 1}, 4);
    int streaks = 0, others = 0;
    for (int y = 10; y < 50; ++y)
        for (int x = 5; x < 55; ++x) (x < 30 && x % 6 == 0 ? streaks : others) += pale[std::size_t(y) * 60 + x];
    EXPECT_EQ(streaks, 4 * 40); // x = 6, 12, 18, 24
    EXPECT_EQ(others, 0);
}

TEST(Fill, TheGapsOfHatchingOnPaperAreNoDryStreaks) {
    // Coloured hatching on white paper as a scan gives it: strokes 4 px wide, and between
    // them 3 px of paper tinted by the strokes' blur (half, 72 % and half the way to the
    // paper). The gaps are the drawing's lightness: none of their pixels is a dry streak
    // (before, 3 in 7 of the square's pixels were, and the texture came out darker).
    const float line[3] = {0.15f, 0.10f, 0.55f}, toward[7] = {0, 0, 0, 0, 0.5f, 0.72f, 0.5f};
    std::vector<char> inside;
    const Image img = square_on_paper(
        inside, 5, 55, [&](int x, int y, int k) { return line[k] + toward[(x + y) % 7] * (1 - line[k]); });
    std::vector<float> share;
    const auto around = fill_under_strokes(img, inside, std::vector<char>(60 * 60, 0), 8, share);
    const auto pale = find_pale_streaks(img, inside, around, {1, 1, 1}, 4);
    int taken = 0;
    for (int y = 10; y < 50; ++y)
        for (int x = 10; x < 50; ++x) taken += pale[std::size_t(y) * 60 + x];
    EXPECT_EQ(taken, 0);
}
