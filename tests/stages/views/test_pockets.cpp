// Pockets of partial coverage a drawn view encloses: filled as the paper between strokes,
// while an opening of a real size stays open.
#include <gtest/gtest.h>

#include "io/image_io.h"
#include "load.h"
#include "pockets.h"
#include "support/test_support.h"

using namespace cm;

namespace {

constexpr int kW = 100, kH = 100;

// A square object [10, 90)^2 holding a 3x3 pocket of coverage 0.3 at [20, 23)^2 (6.3 px of
// paper) and a 40x40 hole at [40, 80)^2.
std::vector<float> square_with_pocket_and_hole() {
    std::vector<float> c(std::size_t(kW) * kH, 0.0f);
    for (int y = 10; y < 90; ++y)
        for (int x = 10; x < 90; ++x) {
            const bool pocket = x >= 20 && x < 23 && y >= 20 && y < 23;
            const bool hole = x >= 40 && x < 80 && y >= 40 && y < 80;
            c[std::size_t(y) * kW + x] = pocket ? 0.3f : hole ? 0.0f : 1.0f;
        }
    return c;
}

float at(const Coverage& c, int x, int y) { return c.at(x, y); }

} // namespace

TEST(Pockets, SmallPocketIsFilledTrueHoleKept) {
    Coverage c(square_with_pocket_and_hole(), kW, kH);
    EXPECT_EQ(fill_pockets(c), 1u);
    for (int y = 20; y < 23; ++y)
        for (int x = 20; x < 23; ++x) EXPECT_EQ(at(c, x, y), 1.0f) << x << "," << y;
    for (int y = 40; y < 80; ++y)
        for (int x = 40; x < 80; ++x) ASSERT_EQ(at(c, x, y), 0.0f) << x << "," << y;
    EXPECT_EQ(at(c, 5, 5), 0.0f);   // the outside stays outside
    EXPECT_EQ(fill_pockets(c), 0u); // nothing left to fill
}

TEST(Pockets, WhatTheBackgroundReachesStaysOpen) {
    // A notch of 4 px from the outline in, and a pocket touching the outside diagonally:
    // both are the background's, however small.
    std::vector<float> v(std::size_t(kW) * kH, 0.0f);
    for (int y = 10; y < 90; ++y)
        for (int x = 10; x < 90; ++x) v[std::size_t(y) * kW + x] = 1.0f;
    for (int x = 10; x < 14; ++x) v[std::size_t(50) * kW + x] = 0.2f; // a notch in from the left
    v[std::size_t(10) * kW + 10] = 0.4f;                              // a corner pixel
    Coverage c(v, kW, kH);
    EXPECT_EQ(fill_pockets(c), 0u);
    EXPECT_LT(at(c, 11, 50), 0.5f);
    EXPECT_LT(at(c, 10, 10), 0.5f);
    // Holding the paper of a gap between strokes or more (9 px wholly uncovered), a pocket is
    // no longer filled: 12 px at 0.1 hold 10.8 px of paper.
    std::vector<float> big = square_with_pocket_and_hole();
    for (int y = 60; y < 63; ++y)
        for (int x = 20; x < 24; ++x) big[std::size_t(y) * kW + x] = 0.1f; // 12 px
    Coverage d(big, kW, kH);
    EXPECT_EQ(fill_pockets(d), 1u); // the 3x3 one only
    EXPECT_LT(at(d, 21, 61), 0.5f);
}

TEST(Pockets, DrawnViewsAreFilledAndHolesKeepKeepsThem) {
    test::TempDir dir("pockets");
    const std::vector<float> cov = square_with_pocket_and_hole();
    Image mask{kW, kH, 3, std::vector<float>(std::size_t(kW) * kH * 3), {}};
    for (std::size_t i = 0; i < cov.size(); ++i)
        for (int k = 0; k < 3; ++k) mask.pixels[i * 3 + std::size_t(k)] = cov[i];
    write_image(mask, dir / "mask.png");
    test::write_text(dir / "views.yaml", "views:\n  front: {image: mask.png, mask: mask.png}\n");
    const auto r = load_views(dir / "views.yaml", {});
    const Coverage& c = r.value.views[0].coverage;
    for (int y = 20; y < 23; ++y)
        for (int x = 20; x < 23; ++x) EXPECT_GE(at(c, x, y), 0.5f) << x << "," << y;
    EXPECT_LT(at(c, 60, 60), 0.5f); // the 40x40 hole stays a hole
    ASSERT_EQ(r.stats.pockets_filled.size(), 1u);
    EXPECT_EQ(r.stats.pockets_filled[0], 1u);

    // `holes: keep` keeps every enclosed region, the pocket too.
    test::write_text(dir / "keep.yaml", "views:\n  front: {image: mask.png, mask: mask.png, holes: keep}\n");
    const auto k = load_views(dir / "keep.yaml", {});
    EXPECT_LT(at(k.value.views[0].coverage, 21, 21), 0.5f);
    EXPECT_EQ(k.stats.pockets_filled[0], 0u);
}
