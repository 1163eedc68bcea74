// Line art gives the same silhouette in any ink: the same drawing in red and in blue, 8-bit
// as a PNG holds it, read to the same outline.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "silhouette.h"

using namespace cm;

namespace {

constexpr int kSize = 200;
constexpr int kLo = 40, kHi = 160; // the box's outline runs along these pixel rows and columns

// The box outlined in 1 px lines of `pen` (8-bit RGB) on white, as render-views draws a
// 1 px blueprint line centred on an edge that crosses a pixel's middle: the columns at full
// ink, the rows at 2/3 of it on one pixel each (the stroke's samples all in that pixel, none
// beside it). Each channel the byte a PNG holds.
Image box_in(std::array<int, 3> pen) {
    Image img;
    img.width = img.height = kSize;
    img.channels = 3;
    img.pixels.assign(std::size_t(kSize) * kSize * 3, 1.0f);
    auto put = [&](int x, int y, double ink) {
        for (std::size_t k = 0; k < 3; ++k) {
            const double v = 255.0 + ink * (pen[k] - 255.0);
            img.pixels[(std::size_t(y) * kSize + std::size_t(x)) * 3 + k] = float(std::round(v) / 255.0);
        }
    };
    for (int i = kLo; i <= kHi; ++i) {
        put(kLo, i, 1.0);
        put(kHi, i, 1.0);
    }
    for (int i = kLo + 1; i < kHi; ++i) {
        put(i, kLo, 2.0 / 3.0);
        put(i, kHi, 2.0 / 3.0);
    }
    return img;
}

// The same box with a line drawn along the inside of its top edge, run into the outline:
// across it 2/3 ink, 1/3 (the valley between the two lines, half the peak) and 2/3.
Image box_with_inner_line_in(std::array<int, 3> pen) {
    Image img = box_in(pen);
    auto put = [&](int x, int y, double ink) {
        for (std::size_t k = 0; k < 3; ++k) {
            const double v = 255.0 + ink * (pen[k] - 255.0);
            img.pixels[(std::size_t(y) * kSize + std::size_t(x)) * 3 + k] = float(std::round(v) / 255.0);
        }
    };
    for (int i = kLo + 1; i < kHi; ++i) {
        put(i, kLo + 1, 1.0 / 3.0);
        put(i, kLo + 2, 2.0 / 3.0);
    }
    return img;
}

std::vector<char> inside(const Image& img, int& area) {
    ImageInfo info;
    const SilhouetteResult s = extract_silhouette(img, info, SilhouetteOptions{});
    std::vector<char> in(std::size_t(kSize) * kSize);
    area = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) area += in[std::size_t(y) * kSize + x] = s.coverage.at(x, y) >= 0.5f;
    return in;
}

} // namespace

TEST(InkColours, RedAndBlueOnePixelLinesGiveOneSilhouette) {
    // Each row's stroke lies on one pixel, the outline through its middle: the pixel is
    // half inside by the ink, whatever the ink's colour (before, the rounding of red's ink
    // fraction put those pixels a hair under half, blue's at half: red lost two rows).
    int red_area = 0, blue_area = 0;
    const std::vector<char> red = inside(box_in({0xbf, 0x1f, 0x1a}), red_area);
    const std::vector<char> blue = inside(box_in({0x1f, 0x3f, 0x8f}), blue_area);
    int differ = 0;
    for (std::size_t i = 0; i < red.size(); ++i) differ += red[i] != blue[i];
    EXPECT_LE(differ, 4) << "red " << red_area << " px, blue " << blue_area << " px";
    // The box to its strokes' centre lines: 120 x 120, the rows' pixels counted in (a tie).
    const int truth = (kHi - kLo) * (kHi - kLo + 1);
    for (const int area : {red_area, blue_area}) EXPECT_NEAR(area, truth, 2 * (kHi - kLo));
}

namespace {

using Pen = std::array<int, 3>;

// Each pen's drawing (made by `draw`) gives blue's silhouette within 4 px.
void expect_like_blue(Image (*draw)(Pen), const std::vector<Pen>& pens) {
    int blue_area = 0;
    const std::vector<char> blue = inside(draw({0x1f, 0x3f, 0x8f}), blue_area);
    for (const auto& pen : pens) {
        int area = 0;
        const std::vector<char> in = inside(draw(pen), area);
        int differ = 0;
        for (std::size_t i = 0; i < in.size(); ++i) differ += in[i] != blue[i];
        EXPECT_LE(differ, 4) << "pen " << pen[0] << "," << pen[1] << "," << pen[2] << ": " << area
                             << " px against blue's " << blue_area;
    }
}

// Red, green, sepia, orange, light cyan, black and grey.
const std::vector<Pen> kInks{{0xbf, 0x1f, 0x1a}, {0x2a, 0x7a, 0x2a}, {0x70, 0x42, 0x14}, {0xe0, 0x70, 0x20},
                             {0x40, 0xa0, 0xc0}, {0x0d, 0x0d, 0x0f}, {0x70, 0x70, 0x70}};

} // namespace

TEST(InkColours, EveryInkOfTheIssueGivesOneSilhouette) { expect_like_blue(box_in, kInks); }

TEST(InkColours, AValleyOfHalfTheInkIsReadAlikeInEveryInk) {
    // The valley between the outline and the line run into it holds exactly half the
    // outline's ink: whether it ends the outline stroke is decided alike in every ink (before,
    // by each colour's bytes: red and blue differed along the top edge).
    expect_like_blue(box_with_inner_line_in, kInks);
}
