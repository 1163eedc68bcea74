// Photographs, generated here from a known mask: a light plaster object lit from one side,
// with dark shadows on it (one reaching its outline, one enclosed), on a dark velvet with a
// dark stand behind it touching the object and a woven cloth reaching the frame; sensor
// noise and 8-bit steps. The threshold alone cuts the shadows out; segmented as a
// photograph they stay object while the stand and the cloth stay out.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "io/image_io.h"
#include "io/manifest.h"
#include "load.h"
#include "silhouette.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

constexpr int kSize = 400;

// The object (as in test_real_drawings): a body (box) under a head (disc).
bool object(double x, double y) {
    const bool box = std::abs(x - 200) <= 90 && std::abs(y - 270) <= 70;
    return box || std::hypot(x - 200, y - 140) <= 75;
}

// Shadows on it: a crevice across the body reaching its right side, and an enclosed pocket.
bool shadow(double x, double y) {
    return (std::abs(y - 250 - 0.3 * (x - 200)) < 6 && x > 150) || std::hypot(x - 160, y - 300) < 12;
}

struct Scene {
    bool stand = true;          ///< a dark stand behind the object, touching its left side
    bool cloth = true;          ///< a woven cloth over the bottom, clear of the object
    double shadow_level = 0.13; ///< the shadows' light, a fraction of the lit plaster's
};

// RGBA, 2 x 2 samples per pixel, Gaussian noise (0.006 per channel), 8-bit steps.
Image photograph(const Scene& s, unsigned seed = 3) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0, 0.006f);
    Image img;
    img.width = img.height = kSize;
    img.channels = 4;
    img.pixels.assign(std::size_t(kSize) * kSize * 4, 1.0f);
    auto colour = [&](double x, double y) -> std::array<double, 3> {
        if (object(x, y)) {
            // Lit from the upper left.
            const double light =
                shadow(x, y) ? s.shadow_level : 0.55 + 0.45 * std::clamp(1.2 - (x + y) / 500, 0.0, 1.0);
            return {0.82 * light, 0.79 * light, 0.72 * light};
        }
        if (s.cloth && y > 365 + 6 * std::sin(x / 40)) {
            const double weave = 0.04 * std::sin(x * 0.9) * std::sin(y * 0.9);
            return {0.33 + weave, 0.26 + weave, 0.2 + weave};
        }
        if (s.stand && x > 60 && x < 125) return {0.095, 0.063, 0.047};
        return {0.035, 0.022, 0.016};
    };
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            std::array<double, 3> sum{};
            for (int sy = 0; sy < 2; ++sy)
                for (int sx = 0; sx < 2; ++sx) {
                    const auto c = colour(x + (sx + 0.5) / 2, y + (sy + 0.5) / 2);
                    for (std::size_t k = 0; k < 3; ++k) sum[k] += c[k] / 4;
                }
            for (std::size_t k = 0; k < 3; ++k) {
                const float v = std::clamp(float(sum[k]) + noise(rng), 0.0f, 1.0f);
                img.pixels[(std::size_t(y) * kSize + x) * 4 + k] = std::round(v * 255.0f) / 255.0f;
            }
        }
    return img;
}

SilhouetteResult extract(const Image& img, const std::string& photo) {
    SilhouetteOptions opt;
    opt.photo = photo;
    ImageInfo info;
    return extract_silhouette(img, info, opt);
}

double iou(const Coverage& coverage) { return test::coverage_iou(coverage.full(), kSize, kSize, object); }

} // namespace

TEST(Photo, ShadowsOnTheObjectStayObject) {
    const Image img = photograph({});
    // As a drawing, the threshold cuts the crevice and the pocket out.
    const SilhouetteResult drawing = extract(img, "off");
    EXPECT_FALSE(drawing.photo);
    EXPECT_LT(iou(drawing.coverage), 0.97);
    // As a photograph they are grown back, and the stand and the cloth stay out.
    const SilhouetteResult photo = extract(img, "on");
    EXPECT_TRUE(photo.photo);
    EXPECT_EQ(photo.border_colours, 2);
    EXPECT_GT(photo.grown, 1000u);
    EXPECT_GE(iou(photo.coverage), 0.99);
}

TEST(Photo, ShadowsAsDarkAsTheBackdropAreFilledWhenEnclosed) {
    // Shadows at the velvet's own light: the crevice reaching the outline cannot be told from
    // the backdrop and stays a notch; the enclosed pocket is filled (holes: auto), or kept
    // open with holes: keep.
    Scene s;
    s.shadow_level = 0.04;
    const Image img = photograph(s);
    const SilhouetteResult r = extract(img, "on");
    EXPECT_GT(r.regions_filled, 0);
    EXPECT_GT(r.coverage[std::size_t(300) * kSize + 160], 0.5f);
    EXPECT_LT(r.coverage[std::size_t(262) * kSize + 240], 0.5f);
    SilhouetteOptions keep;
    keep.photo = "on";
    keep.holes = "keep";
    ImageInfo info;
    EXPECT_LT(extract_silhouette(img, info, keep).coverage[std::size_t(300) * kSize + 160], 0.5f);
}

TEST(Photo, AClearSilhouetteStaysAsItIs) {
    // A binary silhouette (as calibrated data sets hand them over): nothing to grow.
    Image img;
    img.width = img.height = kSize;
    img.channels = 4;
    img.pixels.assign(std::size_t(kSize) * kSize * 4, 1.0f);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            if (object(x + 0.5, y + 0.5))
                for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * kSize + x) * 4 + std::size_t(k)] = 0.0f;
    const SilhouetteResult photo = extract(img, "on"), drawing = extract(img, "off");
    EXPECT_EQ(photo.grown, 0u);
    // The mask to the pixel (the drawing's default gap closing fills a few corner pixels).
    EXPECT_GT(iou(photo.coverage), 0.9999);
    EXPECT_GE(iou(photo.coverage), iou(drawing.coverage));
}

TEST(Photo, TinyAndBlankImagesGiveASilhouetteOrNothing) {
    // Images of a pixel or a row, blank or not: a silhouette (maybe empty), never a crash.
    for (const auto& [w, h] : {std::pair{1, 1}, std::pair{2, 3}, std::pair{3, 1}, std::pair{1, 5}, std::pair{9, 9}})
        for (float level : {0.0f, 0.5f}) {
            Image img;
            img.width = w;
            img.height = h;
            img.channels = 4;
            img.pixels.assign(std::size_t(w) * h * 4, 1.0f);
            for (int i = 0; i < w * h; ++i)
                for (int k = 0; k < 3; ++k) img.pixels[std::size_t(i) * 4 + std::size_t(k)] = i % 3 ? level : 1.0f;
            const SilhouetteResult r = extract(img, "on");
            EXPECT_EQ(r.coverage.size(), std::size_t(w) * h) << w << "x" << h;
            for (float c : r.coverage.full()) EXPECT_TRUE(c >= 0.0f && c <= 1.0f) << w << "x" << h;
        }
}

TEST(Photo, CalibratedViewsAreSegmentedAsPhotographs) {
    test::TempDir dir("photo_views");
    write_image(photograph({}), dir / "p.png");
    const std::string camera = "matrix: [[400, 0, 200, 800], [0, 400, 200, 800], [0, 0, 1, 4]]";
    test::write_text(dir / "views.yaml", "views:\n  a: {image: p.png, " + camera + "}\n");
    test::write_text(dir / "off.yaml", "views:\n  a: {image: p.png, photo: off, " + camera + "}\n");
    test::write_text(dir / "drawn.yaml", "height: 1\nviews:\n  front: p.png\n");
    test::write_text(dir / "drawn_on.yaml", "height: 1\nviews:\n  front: {image: p.png, photo: on}\n");
    EXPECT_GE(iou(load_views(dir / "views.yaml", {}).value.views[0].coverage), 0.99);
    EXPECT_LT(iou(load_views(dir / "off.yaml", {}).value.views[0].coverage), 0.97);
    EXPECT_LT(iou(load_views(dir / "drawn.yaml", {}).value.views[0].coverage), 0.97);
    EXPECT_GE(iou(load_views(dir / "drawn_on.yaml", {}).value.views[0].coverage), 0.99);
}

TEST(Photo, TheKeyRoundTripsAndABadValueIsAOneLineError) {
    test::TempDir dir("photo_key");
    test::write_text(dir / "views.yaml",
                     "views:\n  front: {image: f.png, photo: on}\n  right: {image: f.png, photo: "
                     "off}\n  top: {image: f.png, photo: auto}\n");
    const Manifest m = read_manifest(dir / "views.yaml");
    ASSERT_EQ(m.views.size(), 3u);
    EXPECT_EQ(m.views[0].photo, "on");
    EXPECT_EQ(m.views[1].photo, "off");
    EXPECT_EQ(m.views[2].photo, "auto");
    write_manifest(dir / "back.yaml", m);
    const Manifest b = read_manifest(dir / "back.yaml");
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(b.views[i].photo, m.views[i].photo);
    test::write_text(dir / "bad.yaml", "views:\n  front: {image: f.png,\n    photo: maybe}\n");
    const std::string e = test::error_of([&] { read_manifest(dir / "bad.yaml"); });
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const char* part : {"bad.yaml:3", "view \"front\"", "photo must be auto, on or off", "\"maybe\""})
        EXPECT_NE(e.find(part), std::string::npos) << part << " in " << e;
}
