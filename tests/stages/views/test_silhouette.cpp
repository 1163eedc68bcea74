// Silhouette extraction on drawings generated here, each against its known mask.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>

#include <OpenImageIO/imageio.h>

#include "background_model.h"
#include "core/error.h"
#include "io/image_io.h"
#include "silhouette.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

using Shape = std::function<bool(double x, double y)>;

// RGBA image; each pixel mixes `inside` and `outside` colours by the shape's area coverage
// (4x4 samples), as an anti-aliased drawing would.
Image draw(int w, int h, const Shape& shape, std::array<float, 4> inside, std::array<float, 4> outside) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 4;
    img.pixels.resize(std::size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int hits = 0;
            for (int sy = 0; sy < 4; ++sy)
                for (int sx = 0; sx < 4; ++sx) hits += shape(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4);
            const float a = hits / 16.0f;
            for (int k = 0; k < 4; ++k)
                img.pixels[(std::size_t(y) * w + x) * 4 + k] =
                    a * inside[std::size_t(k)] + (1 - a) * outside[std::size_t(k)];
        }
    return img;
}

// Overwrites the pixels of `shape` (anti-aliased) with `colour` on an existing image.
void paint(Image& img, const Shape& shape, std::array<float, 3> colour) {
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            int hits = 0;
            for (int sy = 0; sy < 4; ++sy)
                for (int sx = 0; sx < 4; ++sx) hits += shape(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4);
            const float a = hits / 16.0f;
            float* p = &img.pixels[(std::size_t(y) * img.width + x) * 4];
            for (int k = 0; k < 3; ++k) p[k] = a * colour[std::size_t(k)] + (1 - a) * p[k];
        }
}

double iou(const Coverage& coverage, int w, int h, const Shape& truth) {
    return test::coverage_iou(coverage.full(), w, h, truth);
}

// A character-like object: a body (ellipse) with a head (disc) and a leg (rectangle).
bool figure(double x, double y) {
    const double ex = (x - 100) / 55, ey = (y - 120) / 35;
    const double hx = x - 150, hy = y - 70;
    return ex * ex + ey * ey <= 1 || hx * hx + hy * hy <= 28 * 28 || (x >= 70 && x <= 90 && y >= 130 && y <= 185);
}

SilhouetteResult extract(const Image& img, bool has_alpha = false, SilhouetteOptions opt = {}) {
    ImageInfo info;
    info.has_alpha = has_alpha;
    return extract_silhouette(img, info, opt);
}

Image reread(const Image& img, const std::string& name, test::TempDir& dir, ImageInfo* info = nullptr) {
    const auto file = dir / name;
    write_image(img, file);
    return read_image(file, info);
}

} // namespace

TEST(Silhouette, AlphaPngIsTheCoverage) {
    test::TempDir dir("sil_alpha");
    // Colour noise under alpha 0 must not matter.
    Image img = draw(220, 200, figure, {0.8f, 0.2f, 0.2f, 1.0f}, {0.1f, 0.9f, 0.3f, 0.0f});
    std::mt19937 rng(3);
    for (std::size_t i = 0; i < img.pixels.size(); i += 4)
        if (img.pixels[i + 3] == 0) img.pixels[i] = float(rng() % 256) / 255.0f;
    ImageInfo info;
    const Image back = reread(img, "alpha.png", dir, &info);
    ASSERT_TRUE(info.has_alpha);
    const SilhouetteResult s = extract_silhouette(back, info, {});
    EXPECT_EQ(s.method, "alpha");
    EXPECT_GT(iou(s.coverage, 220, 200, figure), 0.99);
    // Anti-aliased edges stay fractional.
    std::size_t fractional = 0;
    for (float c : s.coverage.full()) fractional += c > 0.05f && c < 0.95f;
    EXPECT_GT(fractional, 100u);
}

TEST(Silhouette, ClosedLineDrawingWithWhiteInteriorFills) {
    test::TempDir dir("sil_line");
    // A 2.5 px dark outline centred on the figure's edge (as an artist draws it), white
    // inside and outside.
    const Shape outline = [](double x, double y) {
        for (int k = 0; k < 8; ++k) {
            const double a = k * 3.14159265 / 4;
            if (figure(x, y) != figure(x + 1.25 * std::cos(a), y + 1.25 * std::sin(a))) return true;
        }
        return false;
    };
    Image img = draw(220, 200, outline, {0.1f, 0.1f, 0.1f, 1}, {1, 1, 1, 1});
    // An interior detail line (an eye) must not matter.
    paint(img, [](double x, double y) { return std::hypot(x - 155, y - 65) < 4; }, {0.1f, 0.1f, 0.1f});
    const Image back = reread(img, "line.png", dir);
    const SilhouetteResult s = extract(back);
    EXPECT_EQ(s.method, "background");
    EXPECT_GT(s.regions_filled, 0);
    EXPECT_EQ(s.holes_kept, 0);
    EXPECT_GT(iou(s.coverage, 220, 200, figure), 0.99);
}

TEST(Silhouette, GreyNoisyPaperSavedAsJpeg) {
    test::TempDir dir("sil_jpeg");
    Image img = draw(220, 200, figure, {0.25f, 0.22f, 0.3f, 1}, {0.62f, 0.6f, 0.57f, 1});
    // Grain, and a vignette darker at the corners.
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 220; ++x) {
            const double u = (x - 110) / 110.0, v = (y - 100) / 100.0;
            const float vig = float(1.0 - 0.08 * (u * u + v * v));
            const float g = noise(rng);
            float* p = &img.pixels[(std::size_t(y) * 220 + x) * 4];
            for (int k = 0; k < 3; ++k) p[k] = std::clamp(p[k] * vig + g, 0.0f, 1.0f);
        }
    const Image back = reread(img, "paper.jpg", dir);
    const SilhouetteResult s = extract(back);
    EXPECT_GT(iou(s.coverage, 220, 200, figure), 0.99);
}

TEST(Silhouette, SeparateTextLikeMarkIsDropped) {
    Image img = draw(220, 200, figure, {0.2f, 0.3f, 0.5f, 1}, {0.97f, 0.96f, 0.93f, 1});
    // A signature in the corner: a few strokes, one of them closed (an "o").
    paint(img, [](double x, double y) { return y > 185 && y < 187.5 && x > 175 && x < 212; }, {0.1f, 0.1f, 0.1f});
    paint(img, [](double x, double y) { return std::abs(std::hypot(x - 185, y - 178) - 4) < 1.2; }, {0.1f, 0.1f, 0.1f});
    paint(img, [](double x, double y) { return x > 196 && x < 198 && y > 172 && y < 185; }, {0.1f, 0.1f, 0.1f});
    // An arrow pointing at the object from the top left, not touching it.
    paint(img, [](double x, double y) { return std::abs((x - 8) - (y - 8)) < 1.2 && x > 8 && x < 40; },
          {0.1f, 0.1f, 0.1f});
    const SilhouetteResult s = extract(img);
    EXPECT_GE(s.components_dropped, 3);
    EXPECT_EQ(s.components_kept, 1);
    EXPECT_GT(iou(s.coverage, 220, 200, figure), 0.99);
    for (int y = 170; y < 200; ++y)
        for (int x = 172; x < 215; ++x) ASSERT_EQ(s.coverage[std::size_t(y) * 220 + x], 0.0f) << x << "," << y;
    // keep: all keeps them.
    SilhouetteOptions all;
    all.keep = "all";
    const SilhouetteResult k = extract(img, false, all);
    EXPECT_GT(k.coverage[std::size_t(186) * 220 + 190], 0.5f);
}

TEST(Silhouette, SixteenBitTiff) {
    test::TempDir dir("sil_tiff");
    const int w = 220, h = 200;
    const Image img = draw(w, h, figure, {0.05f, 0.05f, 0.05f, 1}, {0.85f, 0.85f, 0.85f, 1});
    std::vector<std::uint16_t> grey(std::size_t(w) * h);
    for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = std::uint16_t(std::lround(img.pixels[i * 4] * 65535));
    const auto file = dir / "grey16.tif";
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::UINT16)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, grey.data()));
    out->close();
    ImageInfo info;
    const Image back = read_image(file, &info);
    EXPECT_EQ(info.bits, 16);
    EXPECT_FALSE(info.has_alpha);
    const SilhouetteResult s = extract_silhouette(back, info, {});
    EXPECT_GT(iou(s.coverage, w, h, figure), 0.99);
}

TEST(Silhouette, FloatExrAndBlackObjectOnWhite) {
    test::TempDir dir("sil_exr");
    // A calibrated-set silhouette: black object on white, as a float EXR.
    const Image img = draw(220, 200, figure, {0, 0, 0, 1}, {1, 1, 1, 1});
    const Image back = reread(img, "mask.exr", dir);
    const SilhouetteResult s = extract(back);
    EXPECT_GT(iou(s.coverage, 220, 200, figure), 0.995);
    SilhouetteOptions white;
    white.background = "white";
    EXPECT_GT(iou(extract(back, false, white).coverage, 220, 200, figure), 0.995);
}

TEST(Silhouette, HolesThroughAFilledDrawingStayOpen) {
    // A filled ring: the blank middle is a hole, not interior.
    const Shape ring = [](double x, double y) {
        const double r = std::hypot(x - 100, y - 100);
        return r <= 70 && r >= 30;
    };
    const Image img = draw(200, 200, ring, {0.3f, 0.35f, 0.5f, 1}, {1, 1, 1, 1});
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.holes_kept, 1);
    EXPECT_GT(iou(s.coverage, 200, 200, ring), 0.99);
    SilhouetteOptions fill;
    fill.holes = "fill";
    const Shape disc = [](double x, double y) { return std::hypot(x - 100, y - 100) <= 70; };
    EXPECT_GT(iou(extract(img, false, fill).coverage, 200, 200, disc), 0.99);
}

TEST(Silhouette, TinyPocketsAreFilledUnlessHolesAreKept) {
    // A filled square with a 2 x 2 px pocket: under 9 px, `auto` reads it as a gap between
    // strokes and fills it; `keep` keeps every enclosed region, however small.
    const Shape square_with_pocket = [](double x, double y) {
        const bool square = x > 40 && x < 160 && y > 40 && y < 160;
        const bool pocket = x >= 100 && x < 102 && y >= 100 && y < 102;
        return square && !pocket;
    };
    const Image img = draw(200, 200, square_with_pocket, {0.3f, 0.35f, 0.5f, 1}, {1, 1, 1, 1});
    const SilhouetteResult filled = extract(img);
    EXPECT_EQ(filled.holes_kept, 0);
    EXPECT_EQ(filled.coverage[std::size_t(100) * 200 + 100], 1.0f);
    SilhouetteOptions keep;
    keep.holes = "keep";
    const SilhouetteResult kept = extract(img, false, keep);
    EXPECT_EQ(kept.holes_kept, 1);
    EXPECT_LT(kept.coverage[std::size_t(100) * 200 + 100], 0.5f);
    EXPECT_GT(iou(kept.coverage, 200, 200, square_with_pocket), 0.995);
}

TEST(Silhouette, WhiteOnBlackMaskAndAntiAliasedCoverage) {
    // A half-plane edge at x = 100.25: the pixel column 100 is 75 % covered.
    const Shape half = [](double x, double y) { return x < 100.75 && y > 20 && y < 180 && x > 20; };
    const Image img = draw(200, 200, half, {1, 1, 1, 1}, {0, 0, 0, 1});
    const SilhouetteResult s = extract(img);
    EXPECT_NEAR(s.coverage[std::size_t(100) * 200 + 100], 0.75f, 0.02f);
    EXPECT_EQ(s.coverage[std::size_t(100) * 200 + 101], 0.0f);
    EXPECT_EQ(s.coverage[std::size_t(100) * 200 + 99], 1.0f);
}

TEST(Silhouette, BadOptionsAreClearErrors) {
    const Image img = draw(50, 50, [](double x, double) { return x < 25; }, {0, 0, 0, 1}, {1, 1, 1, 1});
    SilhouetteOptions o;
    o.background = "chartreuse-ish";
    try {
        extract(img, false, o);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("chartreuse-ish"), std::string::npos) << e.what();
    }
    o.background = "alpha";
    EXPECT_THROW(extract(img, false, o), Error);
    o.background = "255,255,255";
    EXPECT_NO_THROW(extract(img, false, o));
}

// BackgroundField::model_distance_row gives colour_distance(pixel, of_model(x, y)) to the last
// bit, for 8-bit and float images, under a constant model (a mask's black, or any colour: the
// runs of one colour reuse their first pixel's distance) and under a varying one.
TEST(BackgroundDistance, RowsAreEachPixelsColourDistanceToTheLastBit) {
    const int w = 301, h = 7;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> byte(0, 255), run(1, 40);
    Image bytes, floats;
    bytes.width = floats.width = w;
    bytes.height = floats.height = h;
    bytes.channels = floats.channels = 4;
    bytes.bytes.resize(std::size_t(w) * h * 4);
    // Runs of one colour, alpha varying inside them; each run changes one channel of the last
    // run's colour (red, green, blue in turn), so a run told apart by fewer channels shows.
    std::array<std::uint8_t, 3> colour{10, 20, 30};
    for (std::size_t i = 0, k = 0; i < bytes.bytes.size(); ++k) {
        colour[k % 3] = std::uint8_t(colour[k % 3] + 1 + byte(rng) % 255);
        for (int n = run(rng); n > 0 && i < bytes.bytes.size(); --n, i += 4) {
            bytes.bytes[i] = colour[0];
            bytes.bytes[i + 1] = colour[1];
            bytes.bytes[i + 2] = colour[2];
            bytes.bytes[i + 3] = std::uint8_t(byte(rng));
        }
    }
    floats.pixels.resize(bytes.bytes.size());
    for (std::size_t i = 0; i < bytes.bytes.size(); ++i) floats.pixels[i] = bytes.value(i);
    floats.pixels[5 * 4] = -0.0f; // a negative zero beside a zero
    // The same kind of rows in grey (one byte or float per pixel) and in RGB floats.
    Image grey, grey_floats, rgb;
    grey.width = grey_floats.width = rgb.width = w;
    grey.height = grey_floats.height = rgb.height = h;
    grey.channels = grey_floats.channels = 1;
    rgb.channels = 3;
    grey.bytes.resize(std::size_t(w) * h);
    for (std::size_t i = 0; i < grey.bytes.size();) {
        const auto g = std::uint8_t(byte(rng));
        for (int n = run(rng); n > 0 && i < grey.bytes.size(); --n) grey.bytes[i++] = g;
    }
    for (std::size_t i = 0; i < grey.bytes.size(); ++i) {
        grey_floats.pixels.push_back(grey.value(i));
        for (int k = 0; k < 3; ++k) rgb.pixels.push_back(bytes.value(i * 4 + std::size_t(k)));
    }
    std::vector<BackgroundModel> models(4);
    models[0].set_constant({0, 0, 0});
    models[1].set_constant({0.93, 0.91, 0.88});
    models[2] = models[1];
    models[2].coef[1][4] = 1e-17; // varying, however little
    models[3].coef = {{{0.9, -0.01, 0.02, -0.03, 0.01, 0.005}, {0.8, 0, 0, 0, 0, 0}, {0.7, 0.1, 0, 0, 0, 0}}};
    for (const Image* img : {&bytes, &floats, &grey, &grey_floats, &rgb})
        for (const auto& model : models) {
            BackgroundField field;
            field.model = model;
            field.w = w;
            field.h = h;
            std::vector<double> row(static_cast<std::size_t>(w));
            for (int y = 0; y < h; ++y) {
                field.model_distance_row(*img, y, row.data());
                for (int x = 0; x < w; ++x) {
                    const auto p = img->rgba(std::size_t(y) * w + x);
                    ASSERT_EQ(row[std::size_t(x)], colour_distance({p[0], p[1], p[2]}, field.of_model(x, y)))
                        << img->channels << (img->eight_bit() ? " bytes" : " floats") << " at " << x << "," << y;
                }
            }
        }
}

// An 8-bit grey drawing is kept as it is read, one byte per pixel (a quarter of RGBA bytes):
// every pixel reads as its RGBA expansion, and the silhouette is the same to the last bit.
TEST(Silhouette, GreyDrawingKeptAsOneChannelGivesTheSameSilhouette) {
    test::TempDir dir("sil_grey");
    const int w = 220, h = 200;
    Image grey;
    grey.width = w;
    grey.height = h;
    grey.channels = 1;
    grey.pixels.resize(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) // a dark figure on light paper, with a ramp across the paper
            grey.pixels[std::size_t(y) * w + x] = figure(x + 0.5, y + 0.5) ? 0.15f : 0.8f + 0.1f * float(x) / float(w);
    write_image(grey, dir / "grey.png");
    ImageInfo info_bytes, info_rgba;
    const Image kept = read_image(dir / "grey.png", &info_bytes, true);
    const Image rgba = read_image(dir / "grey.png", &info_rgba);
    ASSERT_EQ(kept.channels, 1);
    ASSERT_TRUE(kept.eight_bit());
    EXPECT_EQ(kept.bytes.size(), std::size_t(w) * h);
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_FALSE(info_bytes.has_alpha);
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
        ASSERT_EQ(kept.rgba(i), rgba.rgba(i)) << i;
        const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
        for (int c = 0; c < 4; ++c) ASSERT_EQ(kept.at(x, y, c), rgba.at(x, y, c)) << i << " channel " << c;
    }
    const SilhouetteResult a = extract_silhouette(kept, info_bytes, {}), b = extract_silhouette(rgba, info_rgba, {});
    EXPECT_EQ(a.method, "background");
    EXPECT_GT(iou(a.coverage, w, h, figure), 0.99);
    EXPECT_EQ(a.coverage.full(), b.coverage.full());
}

namespace {

// A band `width` px wide around the outline of `shape` (inside it): an ink outline.
Shape outline_of(const Shape& shape, double width) {
    return [shape, width](double x, double y) {
        if (!shape(x, y)) return false;
        for (int k = 0; k < 8; ++k) {
            const double a = k * 3.14159265 / 4;
            if (!shape(x + width * std::cos(a), y + width * std::sin(a))) return true;
        }
        return false;
    };
}

// A band `width` px wide centred on the outline of `shape`: an outline as an artist draws it.
Shape centred_outline_of(const Shape& shape, double width) {
    return [shape, width](double x, double y) {
        for (int k = 0; k < 8; ++k) {
            const double a = k * 3.14159265 / 4;
            if (shape(x, y) != shape(x + 0.5 * width * std::cos(a), y + 0.5 * width * std::sin(a))) return true;
        }
        return false;
    };
}

} // namespace

TEST(SilhouetteHoles, LineDrawingOfABoxWithACircleOnItsFaceHasNoHole) {
    // Line art: a box's outline and a circle drawn on its face. The circle is surface
    // detail, not an opening; holes: keep opens it.
    const Shape box = [](double x, double y) { return x > 40 && x < 170 && y > 30 && y < 160; };
    const Shape circle = [](double x, double y) { return std::hypot(x - 105, y - 95) < 35; };
    Image img = draw(210, 190, centred_outline_of(box, 2.5), {0.1f, 0.1f, 0.12f, 1}, {0.97f, 0.96f, 0.93f, 1});
    paint(img, outline_of(circle, 2.0), {0.1f, 0.1f, 0.12f});
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.holes_kept, 0);
    EXPECT_GT(iou(s.coverage, 210, 190, box), 0.99);
    bool candidate = false;
    for (const EnclosedRegion& g : s.regions) candidate = candidate || (g.candidate && !g.hole);
    EXPECT_TRUE(candidate); // the circle's inside is listed, not opened
    SilhouetteOptions keep;
    keep.holes = "keep";
    const SilhouetteResult k = extract(img, false, keep);
    EXPECT_EQ(k.holes_kept, 1);
    EXPECT_LT(k.coverage[std::size_t(95) * 210 + 105], 0.5f);
    EXPECT_GT(k.coverage[std::size_t(40) * 210 + 50], 0.5f);
}

TEST(SilhouetteHoles, HatchedRingWithOutlinesIsARing) {
    // A ring drawn as a marker artist does: dark outlines on both edges, the band hatched
    // (vertical 4 px strokes every 6 px, 2 px of paper showing between them). The paper
    // between the strokes is not a hole; the middle is, showing the paper around the ring.
    const Shape ring = [](double x, double y) {
        const double r = std::hypot(x - 100, y - 100);
        return r <= 70 && r >= 30;
    };
    const Shape hatch = [ring](double x, double y) { return ring(x, y) && std::fmod(x, 6.0) < 4.0; };
    Image img = draw(200, 200, hatch, {0.45f, 0.2f, 0.55f, 1}, {1, 1, 1, 1});
    paint(img, outline_of(ring, 3.0), {0.08f, 0.08f, 0.1f});
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.holes_kept, 1);
    EXPECT_GT(iou(s.coverage, 200, 200, ring), 0.98);
    EXPECT_LT(s.coverage[std::size_t(100) * 200 + 100], 0.5f);
    // Every pixel of the band is object.
    std::size_t band_gaps = 0;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) {
            const double r = std::hypot(x + 0.5 - 100, y + 0.5 - 100);
            band_gaps += r > 32 && r < 68 && s.coverage[std::size_t(y) * 200 + x] < 0.5f;
        }
    EXPECT_EQ(band_gaps, 0u);
}

TEST(SilhouetteHoles, DrawnFaceKeepsItsWhiteEyes) {
    // A head (skin-coloured, outlined) with two eyes left white inside ink outlines: one
    // inside the head with a pupil, one on the edge of the head reaching beyond it. Both are
    // parts of the head, not holes.
    const Shape head = [](double x, double y) { return std::hypot(x - 110, y - 110) < 70; };
    const Shape eye_in = [](double x, double y) { return std::hypot(x - 85, y - 100) < 16; };
    const Shape eye_edge = [](double x, double y) { return std::hypot(x - 172, y - 85) < 18; };
    const Shape face = [&](double x, double y) { return head(x, y) || eye_edge(x, y); };
    Image img = draw(230, 220, face, {0.93f, 0.72f, 0.58f, 1}, {1, 1, 1, 1});
    paint(img, outline_of(face, 3.0), {0.08f, 0.06f, 0.06f});
    paint(img, eye_in, {1, 1, 1});
    paint(img, eye_edge, {1, 1, 1});
    paint(img, outline_of(eye_in, 2.0), {0.08f, 0.06f, 0.06f});
    paint(img, outline_of(eye_edge, 2.5), {0.08f, 0.06f, 0.06f});
    paint(img, [](double x, double y) { return std::hypot(x - 88, y - 102) < 5; }, {0.05f, 0.05f, 0.05f});
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.holes_kept, 0);
    EXPECT_GT(iou(s.coverage, 230, 220, face), 0.99);
    EXPECT_GT(s.coverage[std::size_t(95) * 230 + 78], 0.5f);  // the inner eye's white
    EXPECT_GT(s.coverage[std::size_t(85) * 230 + 175], 0.5f); // the edge eye's white
    // The same head with a real opening (no outline of its own near the edge, nothing
    // inside it) keeps that opening.
    Image pierced = img;
    paint(pierced, [](double x, double y) { return std::hypot(x - 110, y - 150) < 14; }, {1, 1, 1});
    const SilhouetteResult p = extract(pierced);
    EXPECT_EQ(p.holes_kept, 1);
    EXPECT_LT(p.coverage[std::size_t(150) * 230 + 110], 0.5f);
}

TEST(SilhouetteHoles, GapBetweenArmAndBodyInAMaskIsAHole) {
    // A white-on-black mask (render-views --style mask) of a figure whose hand touches the
    // hip: the gap between arm and body comes within a pixel of the outside only where the
    // hand's one-pixel bridge closes it. It shows the background through the figure, so it
    // is a hole; the rule that keeps an eye on the edge of a head (a long stretch of its rim
    // beside the outline) does not take it.
    const Shape figure = [](double x, double y) {
        const bool body = x > 60 && x < 120 && y > 30 && y < 180;
        const bool shoulder = x >= 120 && x < 150 && y > 40 && y < 55;
        const bool arm = x >= 135 && x < 150 && y > 40 && y < 165;
        const bool hand = x >= 120 && x < 135 && y >= 150 && y < 151;
        return body || shoulder || arm || hand;
    };
    const Shape gap = [](double x, double y) { return x >= 120 && x < 135 && y >= 55 && y < 150; };
    const Shape truth = [&](double x, double y) { return figure(x, y) && !gap(x, y); };
    const Image img = draw(200, 210, figure, {1, 1, 1, 1}, {0, 0, 0, 1});
    const SilhouetteResult s = extract(img);
    EXPECT_EQ(s.holes_kept, 1);
    EXPECT_LT(s.coverage[std::size_t(100) * 200 + 127], 0.5f) << "the gap between arm and body";
    EXPECT_GT(iou(s.coverage, 200, 210, truth), 0.99);
}
