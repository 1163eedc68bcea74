// Where the outline of line art lies within its stroke: drawings of known shapes outlined
// with strokes centred on their edges, as an artist draws them, at widths from 1 to 5 px.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "io/image_io.h"
#include "silhouette.h"
#include "support/shapes.h"

using namespace cm;

namespace {

using Sdf = std::function<double(double x, double y)>; // signed distance, px, positive inside

// A w x h drawing: ink where `ink(x, y)`, paper elsewhere; each pixel the mean of 4x4
// samples (anti-aliased, as a scan or a paint program gives it).
Image draw(int w, int h, const std::function<bool(double, double)>& ink) {
    return test::ink_drawing(w, h, ink, {0.12f, 0.12f, 0.14f}, {0.97f, 0.96f, 0.93f});
}

// The outline of `shape` drawn with a stroke of `width(x, y)` px centred on it.
Image outline(int w, int h, const Sdf& shape, const std::function<double(double, double)>& width) {
    return draw(w, h, [&](double x, double y) { return std::abs(shape(x, y)) <= 0.5 * width(x, y); });
}

SilhouetteResult extract(const Image& img) {
    ImageInfo info;
    return extract_silhouette(img, info, SilhouetteOptions{});
}

// The silhouette's width across column x: its coverage summed over the rows.
double column_sum(const SilhouetteResult& s, int x, int h) {
    double sum = 0;
    for (int y = 0; y < h; ++y) sum += s.coverage.at(x, y);
    return sum;
}

// The silhouette's width across row y.
double row_sum(const SilhouetteResult& s, int y, int w) {
    double sum = 0;
    for (int x = 0; x < w; ++x) sum += s.coverage.at(x, y);
    return sum;
}

// A body (box 120 x 80 at the top) with a leg `leg` px wide hanging 120 px below it.
Sdf body_with_leg(double leg) {
    return [leg](double x, double y) {
        const double body = std::min(std::min(x - 40, 160 - x), std::min(y - 30, 110 - y));
        const double l = std::min(std::min(x - (100 - 0.5 * leg), (100 + 0.5 * leg) - x), std::min(y - 100, 230 - y));
        return std::max(body, l);
    };
}

} // namespace

TEST(LineArt, ThinBarOutlinedWithAFourPixelStrokeComesBackAtItsTrueWidth) {
    // A leg 12 px wide, outlined with a 4 px stroke: the strokes' outer edges are 16 px apart.
    const SilhouetteResult s = extract(outline(200, 260, body_with_leg(12), [](double, double) { return 4.0; }));
    EXPECT_NEAR(s.stroke.stroke_width, 4.0, 1.0);
    for (int y = 150; y <= 210; y += 10) EXPECT_NEAR(row_sum(s, y, 200), 12.0, 1.0) << "row " << y;
    // The body too: its true 120 x 80 box, not the strokes' 124 x 84.
    EXPECT_NEAR(row_sum(s, 60, 200), 120.0, 1.0);
    EXPECT_NEAR(column_sum(s, 60, 260), 80.0, 1.0);
}

TEST(LineArt, EveryStrokeWidthFromOneToFivePixels) {
    for (double stroke : {1.0, 2.0, 3.0, 4.0, 5.0}) {
        const SilhouetteResult s =
            extract(outline(200, 260, body_with_leg(14), [&](double, double) { return stroke; }));
        EXPECT_NEAR(row_sum(s, 180, 200), 14.0, 1.0) << stroke << " px";
        EXPECT_NEAR(row_sum(s, 60, 200), 120.0, 1.0) << stroke << " px";
    }
}

TEST(LineArt, AWaveringStrokeIsFollowed) {
    // A disc of radius 80 outlined with a stroke wavering from 1 to 5 px around it.
    const Sdf disc = [](double x, double y) { return 80 - std::hypot(x - 110, y - 110); };
    const auto width = [](double x, double y) { return 3 + 2 * std::sin(3 * std::atan2(y - 110, x - 110)); };
    const SilhouetteResult s = extract(outline(220, 220, disc, width));
    double area = 0;
    for (int y = 0; y < 220; ++y) area += row_sum(s, y, 220);
    const double truth = 3.14159265358979 * 80 * 80;
    EXPECT_NEAR(area / truth, 1.0, 0.01); // the strokes' outer edge: +3.8 %
}

TEST(LineArt, PartsThinnerThanTwoStrokesAreKept) {
    // A leg 3 px wide outlined with 4 px strokes: its two strokes run together into one band
    // of ink 7 px wide. It comes back at its own width, not cut away.
    const SilhouetteResult touching = extract(outline(200, 260, body_with_leg(3), [](double, double) { return 4.0; }));
    for (int y = 150; y <= 210; y += 20) EXPECT_NEAR(row_sum(touching, y, 200), 3.0, 1.0) << "row " << y;
    // A tail drawn as a single 5 px stroke (a single stroke thinner than the gap closing's
    // disc is an overshoot, see remove_thin_spurs): kept along its line, thinner than the stroke.
    const Sdf box = [](double x, double y) { return std::min(std::min(x - 40, 160 - x), std::min(y - 30, 110 - y)); };
    const Image img = draw(200, 260, [&](double x, double y) {
        return std::abs(box(x, y)) <= 2.5 || (std::abs(x - 100) <= 2.5 && y >= 110 && y <= 230);
    });
    const SilhouetteResult single = extract(img);
    for (int y = 150; y <= 210; y += 20) {
        EXPECT_GE(row_sum(single, y, 200), 1.5) << "row " << y;
        EXPECT_LT(row_sum(single, y, 200), 5.0) << "row " << y;
        EXPECT_GT(single.coverage.at(100, y), 0.5f) << "row " << y;
    }
}

TEST(LineArt, FilledDrawingsKeepTheirOuterEdge) {
    // The same leg filled in colour with a 4 px outline: a filled drawing, whose outline is
    // the renderer's, drawn inside; nothing is pulled in.
    const Sdf shape = body_with_leg(12);
    Image img = draw(200, 260, [&](double x, double y) { return shape(x, y) >= 0 && shape(x, y) <= 4; });
    for (int y = 0; y < 260; ++y)
        for (int x = 0; x < 200; ++x) {
            float* p = &img.pixels[(std::size_t(y) * 200 + x) * 3];
            if (shape(x + 0.5, y + 0.5) > 4) p[0] = 0.8f, p[1] = 0.5f, p[2] = 0.3f;
        }
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.stroke.samples, 0u);
    EXPECT_NEAR(row_sum(s, 180, 200), 12.0, 1.0);
}
