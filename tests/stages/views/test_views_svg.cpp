// Vector drawings: views given as SVG files, drawn by librsvg, read as line art.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "core/error.h"
#include "load.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;

namespace {

// A box's face in thin red lines with a circle drawn on it (detail, not a hole), in SVG
// units of a 200 x 150 viewBox, and its top (200 x 200, sized in millimetres).
const char* kLines = "fill=\"none\" stroke=\"#c02020\" stroke-width=\"1\"";

void write_face(const std::filesystem::path& file) {
    test::write_svg(file, "viewBox=\"0 0 200 150\"",
                    std::string("<rect x=\"40\" y=\"30\" width=\"120\" height=\"90\" ") + kLines +
                        "/>\n<circle cx=\"100\" cy=\"75\" r=\"20\" " + kLines + "/>");
}

void write_top(const std::filesystem::path& file) {
    test::write_svg(file, "width=\"100mm\" height=\"100mm\" viewBox=\"0 0 200 200\"",
                    std::string("<rect x=\"40\" y=\"40\" width=\"120\" height=\"120\" ") + kLines + "/>");
}

} // namespace

TEST(ViewsSvg, ALineArtBoxWithACircleIsAWholeFace) {
    test::TempDir dir("views_svg");
    write_face(dir / "face.svg");
    write_top(dir / "top.svg");
    test::write_text(dir / "views.yaml", "views:\n  front: face.svg\n  right: face.svg\n  top: top.svg\n");
    LoadViewsOptions opt;
    opt.svg_size = 1000; // 5 px per SVG unit
    const Views views = load_views(dir / "views.yaml", opt).value;
    ASSERT_EQ(views.views.size(), 3u);
    const View& front = views.views[0];
    EXPECT_EQ(front.width, 1000);
    EXPECT_EQ(front.height, 750);
    // The face is the rectangle to its strokes' centre line: x 200..800, y 150..600 px.
    const std::vector<float> c = front.coverage.full();
    auto at = [&](int x, int y) { return c[std::size_t(y) * std::size_t(front.width) + std::size_t(x)]; };
    EXPECT_GT(at(500, 375), 0.5f) << "the circle's inside is the face, not a hole";
    EXPECT_GT(at(420, 375), 0.5f) << "so is the ring between the circle and the rectangle";
    EXPECT_GT(at(205, 155), 0.5f);
    EXPECT_LT(at(190, 140), 0.5f) << "outside the rectangle is paper";
    // The strokes' outer corners are no part of it (no speck beside each corner of the box).
    for (const auto& [x, y] : {std::pair{198, 148}, std::pair{801, 148}, std::pair{198, 601}, std::pair{801, 601}})
        EXPECT_LT(at(x, y), 0.5f) << x << ", " << y;
    double area = 0;
    for (float v : c) area += v;
    EXPECT_NEAR(area, 600.0 * 450.0, 0.02 * 600.0 * 450.0);
    EXPECT_EQ(views.views[2].width, 1000);
    EXPECT_EQ(views.views[2].height, 1000);
}

TEST(ViewsSvg, ABrokenSvgNamesTheViewAndTheFile) {
    test::TempDir dir("views_svg_broken");
    write_face(dir / "face.svg");
    test::write_text(dir / "broken.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\"><rect");
    test::write_text(dir / "views.yaml", "views:\n  front: face.svg\n  right: broken.svg\n");
    const std::string e = error_of([&] { load_views(dir / "views.yaml", {}); });
    EXPECT_NE(e.find("view \"right\""), std::string::npos) << e;
    EXPECT_NE(e.find("broken.svg"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}
