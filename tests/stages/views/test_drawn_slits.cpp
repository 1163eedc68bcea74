// Line art where two outlines run close: a slit of paper between two parts narrower than
// the gap closing (the man's foot and shin seen from above), and an outline with lines run
// together beside it inside (his back and hips), drawn 1 px wide.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <tuple>

#include "io/image_io.h"
#include "silhouette.h"
#include "support/shapes.h"

using namespace cm;

namespace {

using Sdf = std::function<double(double, double)>;

// A w x h drawing in blue (#1f3f8f) on white of the pixels where `ink(x, y)`, each pixel the
// mean of 4 x 4 samples.
Image draw(int w, int h, const std::function<bool(double, double)>& ink) {
    return test::ink_drawing(w, h, ink, {0.122f, 0.247f, 0.561f}, {1.0f, 1.0f, 1.0f});
}

SilhouetteResult extract(const Image& img) { return extract_silhouette(img, ImageInfo{}, SilhouetteOptions{}); }

// Pixels whose silhouette (coverage >= 0.5) and the shape (`sdf` <= 0 at the pixel centre)
// disagree, within the box [x0, x1) x [y0, y1) (the whole image when it is empty).
std::size_t wrong_pixels(const SilhouetteResult& s, int w, int h, const Sdf& sdf, int x0 = 0, int y0 = 0, int x1 = 0,
                         int y1 = 0) {
    if (x1 <= x0) std::tie(x0, y0, x1, y1) = std::make_tuple(0, 0, w, h);
    std::size_t wrong = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) wrong += (s.coverage.at(x, y) >= 0.5f) != (sdf(x + 0.5, y + 0.5) <= 0);
    return wrong;
}

double box(double x, double y, double x0, double y0, double x1, double y1) {
    return std::max(std::max(x0 - x, x - x1), std::max(y0 - y, y - y1));
}

} // namespace

TEST(LineSlits, SlitBetweenTwoOutlinedPartsStaysOpen) {
    // Two legs joined at the hips, the slit between them 4.4 px wide and 90 px deep, open
    // below, outlined with 1 px lines: about 3.4 px of paper between the two strokes, which
    // the gap closing (3 px here, a disc of 2.5 px) bridged along its whole depth, so the
    // slit was object (447 px wrong before, 2 after).
    const Sdf legs = [](double x, double y) {
        return std::min({box(x, y, 40.3, 40.3, 100.3, 200.3), box(x, y, 104.7, 40.3, 160.3, 200.3),
                         box(x, y, 40.3, 40.3, 160.3, 110.3)});
    };
    const Image img = draw(200, 240, [&](double x, double y) { return std::abs(legs(x, y)) <= 0.5; });
    const SilhouetteResult s = extract(img);
    EXPECT_GT(s.slits_opened, 200u);
    // The slit itself, and the whole drawing: about 900 px of outline.
    EXPECT_LT(wrong_pixels(s, 200, 240, legs, 98, 108, 107, 203), 30u);
    EXPECT_LT(wrong_pixels(s, 200, 240, legs), 60u);
}

TEST(LineSlits, DoubledOutlineKeepsItsOuterStroke) {
    // A box outlined twice, the second stroke 3.5 px outside the first along the bottom and
    // parting from it at one end: the paper between them is bridged and reaches the
    // background at that end, but the outer stroke has the background behind it: doubled
    // strokes, not two parts, so the paper between them stays object.
    const Sdf inner = [](double x, double y) { return box(x, y, 40.3, 40.3, 160.3, 160.3); };
    const auto ink = [&](double x, double y) {
        const bool outer = std::abs(y - 163.9) <= 0.5 && x >= 40.3 && x <= 150.0;
        return std::abs(inner(x, y)) <= 0.5 || outer;
    };
    const SilhouetteResult s = extract(draw(200, 200, ink));
    EXPECT_EQ(s.slits_opened, 0u);
    // Between the strokes, under the doubled stretch: object.
    std::size_t object = 0;
    for (int x = 50; x < 140; ++x) object += s.coverage.at(x, 162) >= 0.5f;
    EXPECT_EQ(object, 90u);
}

TEST(LineSlits, OutlineWithLinesRunTogetherInsideLiesOnTheOutline) {
    // A box outlined with 1 px lines and two more lines just inside its bottom edge (1.2 and
    // 2.4 px in), run together with it into a band about 3.4 px wide with no gap between:
    // read as one stroke, the outline went to the band's middle, a pixel and more inside
    // along the whole edge (110 px wrong there before, none after); it is the band's
    // outermost stroke.
    const Sdf shape = [](double x, double y) { return box(x, y, 40.3, 40.3, 160.3, 160.3); };
    const auto ink = [&](double x, double y) {
        const bool inside = x >= 40.3 && x <= 160.3;
        return std::abs(shape(x, y)) <= 0.5 || (inside && std::abs(y - 159.1) <= 0.5) ||
               (inside && std::abs(y - 157.9) <= 0.5);
    };
    const SilhouetteResult s = extract(draw(200, 200, ink));
    EXPECT_LT(wrong_pixels(s, 200, 200, shape, 45, 150, 155, 170), 30u);
    EXPECT_LT(wrong_pixels(s, 200, 200, shape), 60u);
}
