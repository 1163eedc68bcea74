// SVG files read as images: drawn by librsvg on white paper at the size asked for.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "io/image_io.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;

namespace {

// A rectangle in red lines 2 units wide, in a 200 x 150 viewBox.
void write_rect(const std::filesystem::path& file) {
    test::write_svg(file, "viewBox=\"0 0 200 150\"",
                    "<rect x=\"40\" y=\"30\" width=\"120\" height=\"90\" fill=\"none\" stroke=\"#c02020\" "
                    "stroke-width=\"2\"/>");
}

} // namespace

TEST(ImageSvg, DrawnOnWhitePaperAtTheAskedSize) {
    test::TempDir dir("image_svg");
    write_rect(dir / "face.svg");
    ImageInfo info;
    const Image img = read_image(dir / "face.svg", &info, false, 400);
    auto px = [&](int x, int y) { return img.rgba(std::size_t(y) * std::size_t(img.width) + std::size_t(x)); };
    EXPECT_EQ(img.width, 400);
    EXPECT_EQ(img.height, 300);
    EXPECT_FALSE(info.has_alpha);
    const auto paper = px(10, 10);
    EXPECT_FLOAT_EQ(paper[0], 1.0f);
    EXPECT_FLOAT_EQ(paper[2], 1.0f);
    const auto ink = px(80, 150); // on the rectangle's left side (x 40 units = 80 px)
    EXPECT_GT(ink[0], 0.6f);
    EXPECT_LT(ink[1], 0.4f);
    // Without width/height the viewBox sizes it; with neither it is refused, naming the file.
    test::write_text(dir / "nosize.svg",
                     "<svg xmlns=\"http://www.w3.org/2000/svg\"><rect width=\"5\" height=\"5\"/></svg>");
    const std::string e = error_of([&] { read_image(dir / "nosize.svg"); });
    EXPECT_NE(e.find("nosize.svg"), std::string::npos) << e;
    EXPECT_NE(e.find("no size"), std::string::npos) << e;
    // An SVG by its content whatever its name.
    write_rect(dir / "drawing.txt");
    EXPECT_TRUE(is_svg_file(dir / "drawing.txt"));
    EXPECT_EQ(read_image(dir / "drawing.txt", nullptr, false, 200).width, 200);
}
