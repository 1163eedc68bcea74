// Drawings as they are handed over, each generated here from a known mask: sketchy outlines
// with breaks, overshoots, doubled strokes and construction lines; a mask file; a backdrop
// with a cloth reaching the frame; a soft ground shadow.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "load.h"
#include "silhouette.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;

namespace {

constexpr int kSize = 400;

// Signed distance (px, positive inside) of the object: a body (box) under a head (disc).
double object_sdf(double x, double y) {
    const double bx = std::max(std::abs(x - 200) - 90, std::abs(y - 270) - 70);
    const double box =
        bx > 0 ? -std::hypot(std::max(std::abs(x - 200) - 90, 0.0), std::max(std::abs(y - 270) - 70, 0.0)) : -bx;
    const double disc = 75 - std::hypot(x - 200, y - 140);
    return std::max(box, disc);
}
bool object(double x, double y) { return object_sdf(x, y) >= 0; }

using Sampler = std::function<std::array<float, 3>(double x, double y)>;

// An RGBA image; each pixel the mean of 4x4 samples.
Image render(int w, int h, const Sampler& colour) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 4;
    img.pixels.assign(std::size_t(w) * h * 4, 1.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::array<float, 3> sum{};
            for (int sy = 0; sy < 4; ++sy)
                for (int sx = 0; sx < 4; ++sx) {
                    const auto c = colour(x + (sx + 0.5) / 4, y + (sy + 0.5) / 4);
                    for (int k = 0; k < 3; ++k) sum[std::size_t(k)] += c[std::size_t(k)] / 16.0f;
                }
            for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * w + x) * 4 + k] = sum[std::size_t(k)];
        }
    return img;
}

double iou(const Coverage& coverage, int w, int h, const std::function<bool(double, double)>& truth) {
    return test::coverage_iou(coverage.full(), w, h, truth);
}

// Breaks in a stroke: points on the outline, each with a width (px) across which the stroke
// is erased, along the outline's tangent there.
struct Break {
    double x, y, tx, ty, width;
};

std::vector<Break> random_breaks(int count, double min_w, double max_w, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0, 2 * 3.14159265358979), width(min_w, max_w);
    std::vector<Break> out;
    for (int i = 0; i < count; ++i) {
        // Along a ray from the object's middle to its outline (it is star-shaped about it).
        const double a = angle(rng), cx = 200, cy = 220;
        double lo = 0, hi = 300;
        for (int it = 0; it < 60; ++it) {
            const double m = 0.5 * (lo + hi);
            (object(cx + m * std::cos(a), cy + m * std::sin(a)) ? lo : hi) = m;
        }
        const double x = cx + lo * std::cos(a), y = cy + lo * std::sin(a);
        const double gx = object_sdf(x + 0.5, y) - object_sdf(x - 0.5, y);
        const double gy = object_sdf(x, y + 0.5) - object_sdf(x, y - 0.5);
        const double g = std::hypot(gx, gy);
        out.push_back({x, y, -gy / g, gx / g, width(rng)});
    }
    return out;
}

bool in_break(double x, double y, const std::vector<Break>& breaks) {
    for (const auto& b : breaks) {
        const double dx = x - b.x, dy = y - b.y;
        if (std::hypot(dx, dy) < 3 && std::abs(dx * b.tx + dy * b.ty) < 0.5 * b.width) return true;
    }
    return false;
}

struct Sketch {
    double stroke = 1.5;       ///< width (px), centred on the outline as an artist draws it
    std::vector<Break> breaks; ///< in the outline
    bool overshoot = false;    ///< strokes running 9 px past the body's lower corners
    bool doubled = false;      ///< a second, wavering stroke 2-4 px inside the first
    bool construction = false; ///< light lines across the whole sheet
    std::array<float, 3> ink{0.12f, 0.12f, 0.14f};
};

Image sketch(const Sketch& s) {
    const auto breaks2 = random_breaks(int(s.breaks.size()), 1, 4, 99);
    return render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        const double f = object_sdf(x, y);
        bool line = std::abs(f) <= 0.5 * s.stroke && !in_break(x, y, s.breaks);
        if (s.doubled) {
            const double o = 3.0 + std::sin(0.05 * x + 0.07 * y);
            line = line || (f >= o && f <= o + s.stroke && !in_break(x, y, breaks2));
        }
        if (s.overshoot) {
            // The bottom edge and the sides of the body, continued past the corners.
            const bool bottom = std::abs(y - 340) <= 0.5 * s.stroke && x >= 101 && x <= 299;
            const bool sides = (std::abs(x - 110.0) <= 0.5 * s.stroke || std::abs(x - 290.0) <= 0.5 * s.stroke) &&
                               y >= 330 && y <= 349;
            line = line || bottom || sides;
        }
        if (line) return s.ink;
        if (s.construction && (std::abs(y - 200) < 0.6 || std::abs(x - 200) < 0.6 || std::abs(x - y - 20) < 0.6))
            return {0.78f, 0.8f, 0.84f};
        return {0.97f, 0.96f, 0.93f};
    });
}

SilhouetteResult extract(const Image& img, SilhouetteOptions opt = {}) {
    ImageInfo info;
    return extract_silhouette(img, info, opt);
}

} // namespace

TEST(RealDrawings, BrokenOutlineFillsOnlyWithGapClosing) {
    Sketch s;
    s.breaks = random_breaks(14, 1, 4, 7);
    const Image img = sketch(s);
    SilhouetteOptions off;
    off.close_gaps = 0;
    // Without closing the background runs in through the breaks: the ink alone is left.
    EXPECT_LT(iou(extract(img, off).coverage, kSize, kSize, object), 0.2);
    const SilhouetteResult r = extract(img);
    EXPECT_DOUBLE_EQ(r.close_gaps, 3.0); // 0.4 % of 400 px is under the 3 px floor
    SilhouetteOptions four;
    four.close_gaps = 4;
    EXPECT_GE(iou(extract(img, four).coverage, kSize, kSize, object), 0.99);
}

TEST(RealDrawings, BrokenOutlineWithTwoPixelStrokes) {
    Sketch s;
    s.stroke = 2;
    s.breaks = random_breaks(20, 1, 3, 11);
    EXPECT_GE(iou(extract(sketch(s)).coverage, kSize, kSize, object), 0.99);
}

TEST(RealDrawings, OvershootingStrokesDoNotChangeTheSilhouette) {
    Sketch s;
    s.breaks = random_breaks(10, 1, 4, 5);
    s.overshoot = true;
    SilhouetteOptions opt;
    opt.close_gaps = 4;
    const SilhouetteResult r = extract(sketch(s), opt);
    EXPECT_GE(iou(r.coverage, kSize, kSize, object), 0.99);
    EXPECT_GT(r.spurs_removed, 40u);
    // The overshoots themselves are gone, not only outweighed.
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{{110, 346}, {289, 346}})
        EXPECT_LT(r.coverage[std::size_t(y) * kSize + x], 0.5f) << x << "," << y;
}

TEST(RealDrawings, DoubledStrokesFillBetween) {
    Sketch s;
    s.breaks = random_breaks(10, 1, 4, 21);
    s.doubled = true;
    SilhouetteOptions opt;
    opt.close_gaps = 4;
    EXPECT_GE(iou(extract(sketch(s), opt).coverage, kSize, kSize, object), 0.99);
}

TEST(RealDrawings, LightConstructionLinesDoNotChangeTheSilhouette) {
    Sketch s;
    s.breaks = random_breaks(10, 1, 4, 3);
    s.construction = true;
    SilhouetteOptions opt;
    opt.close_gaps = 4;
    const SilhouetteResult r = extract(sketch(s), opt);
    EXPECT_GE(iou(r.coverage, kSize, kSize, object), 0.99);
    EXPECT_LT(r.coverage[std::size_t(200) * kSize + 20], 0.5f); // a construction line far from the object
}

TEST(RealDrawings, NarrowOpeningWiderThanTheGapStaysOpen) {
    // A U: the box with a slot 10.5 px wide (9 px of paper between the strokes centred on its
    // edges) and 60 px deep cut from its bottom, outlined.
    const auto u_sdf = [](double x, double y) {
        const double bx = std::max(std::abs(x - 200) - 90, std::abs(y - 220) - 80);
        const double slot = std::max(std::abs(x - 200) - 5.25, std::abs(y - 275) - 35); // past the bottom
        return std::min(-bx, slot);
    };
    const auto u = [&](double x, double y) { return u_sdf(x, y) >= 0; };
    const Image img = render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        const double f = u_sdf(x, y);
        return std::abs(f) <= 0.75 ? std::array<float, 3>{0.1f, 0.1f, 0.1f} : std::array<float, 3>{0.97f, 0.97f, 0.95f};
    });
    SilhouetteOptions opt;
    opt.close_gaps = 4;
    const SilhouetteResult r = extract(img, opt);
    EXPECT_GE(iou(r.coverage, kSize, kSize, u), 0.99);
    for (int y = 250; y < 300; y += 10) EXPECT_LT(r.coverage[std::size_t(y) * kSize + 200], 0.5f) << y;
    // A closing wider than the slot bridges it, but both its sides are outlines with the
    // object's paper behind them: a slit drawn between two parts, kept open.
    opt.close_gaps = 12;
    const SilhouetteResult wide = extract(img, opt);
    EXPECT_GT(wide.slits_opened, 0u);
    EXPECT_LT(wide.coverage[std::size_t(280) * kSize + 200], 0.5f);
}

TEST(RealDrawings, TwoColourBorderKeepsTheClothBackground) {
    // A white object on a light backdrop; a textured dark cloth over the lower quarter reaches
    // the bottom and both sides of the frame, and the object stands on it.
    std::mt19937 rng(4);
    std::vector<float> grain(kSize * kSize);
    for (auto& g : grain) g = float(rng() % 1000) / 1000.0f - 0.5f;
    const Image img = render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        if (object(x, y)) return {0.95f, 0.95f, 0.93f};
        const float g = grain[std::size_t(int(y)) * kSize + std::size_t(int(x))];
        if (y > 300 + 6 * std::sin(x / 40)) {
            const float weave = 0.04f * float(std::sin(x * 0.9) * std::sin(y * 0.9)) + 0.05f * g;
            return {0.32f + weave, 0.25f + weave, 0.2f + weave};
        }
        return {0.72f + 0.02f * g, 0.75f + 0.02f * g, 0.8f + 0.02f * g};
    });
    const SilhouetteResult r = extract(img);
    EXPECT_EQ(r.border_colours, 2);
    EXPECT_GE(iou(r.coverage, kSize, kSize, object), 0.99);
    // Given the backdrop's colour, the cloth is object: the clustering is what keeps it out.
    SilhouetteOptions given;
    given.background = "184,191,204";
    EXPECT_LT(iou(extract(img, given).coverage, kSize, kSize, object), 0.9);
}

TEST(RealDrawings, SoftGroundShadowIsBackground) {
    const Image img = render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        if (object(x, y)) return {0.3f, 0.42f, 0.7f};
        const std::array<float, 3> paper{0.96f, 0.95f, 0.92f};
        // An ellipse of shade under the body, darkest (x 0.7) at its middle, fading out.
        const double e = std::hypot((x - 205) / 130, (y - 342) / 14);
        const float shade = e < 1 ? float(1 - 0.3 * (1 - e * e)) : 1.0f;
        return {paper[0] * shade, paper[1] * shade, paper[2] * shade};
    });
    const SilhouetteResult r = extract(img);
    EXPECT_GT(r.shadow_removed, 500u);
    EXPECT_GE(iou(r.coverage, kSize, kSize, object), 0.99);
    SilhouetteOptions keep;
    keep.shadow = "keep";
    EXPECT_LT(iou(extract(img, keep).coverage, kSize, kSize, object), 0.97);
}

TEST(RealDrawings, MaskFileIsTheCoverage) {
    test::TempDir dir("rd_mask");
    // A cluttered photograph no border model explains, and its mask with grey edges.
    std::mt19937 rng(8);
    const Image photo = render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        const float a = float(std::sin(x * 0.05) * std::cos(y * 0.07));
        return object(x, y) ? std::array<float, 3>{0.6f, 0.5f, 0.4f}
                            : std::array<float, 3>{0.5f + 0.4f * a, 0.5f - 0.3f * a, 0.3f + 0.2f * a};
    });
    write_image(photo, dir / "photo.png");
    const Image mask = render(kSize, kSize, [&](double x, double y) -> std::array<float, 3> {
        return object(x, y) ? std::array<float, 3>{1, 1, 1} : std::array<float, 3>{0, 0, 0};
    });
    write_image(mask, dir / "mask.png");
    test::write_text(dir / "views.yaml", "views:\n  front: {image: photo.png, mask: mask.png}\n");
    const Views v = load_views(dir / "views.yaml", {}).value;
    ASSERT_EQ(v.views.size(), 1u);
    EXPECT_GE(iou(v.views[0].coverage, kSize, kSize, object), 0.99);
    EXPECT_EQ(v.views[0].image.width, kSize); // the image is still read
    std::size_t grey = 0;
    for (float c : v.views[0].coverage.full()) grey += c > 0.05f && c < 0.95f;
    EXPECT_GT(grey, 300u);
    // Segmented instead, the clutter defeats the border model (no object, or a wrong one).
    test::write_text(dir / "seg.yaml", "views:\n  front: photo.png\n");
    double seg_iou = 0;
    try {
        seg_iou = iou(load_views(dir / "seg.yaml", {}).value.views[0].coverage, kSize, kSize, object);
    } catch (const Error&) {}
    EXPECT_LT(seg_iou, 0.9);

    // A mask of another size: one line naming both files and both sizes.
    write_image(render(200, 100, [](double, double) { return std::array<float, 3>{1, 1, 1}; }), dir / "small.png");
    test::write_text(dir / "bad.yaml", "views:\n  front: {image: photo.png, mask: small.png}\n");
    const std::string e = error_of([&] { load_views(dir / "bad.yaml", {}); });
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const char* part : {"small.png", "photo.png", "200x100", "400x400", "\"front\""})
        EXPECT_NE(e.find(part), std::string::npos) << part << " in " << e;
}

TEST(RealDrawings, NewKeysRoundTripAndBadValuesAreOneLineErrors) {
    test::TempDir dir("rd_keys");
    write_image(
        render(40, 40,
               [](double x, double y) {
                   return object(x * 10, y * 10) ? std::array<float, 3>{0, 0, 0} : std::array<float, 3>{1, 1, 1};
               }),
        dir / "f.png");
    test::write_text(dir / "views.yaml",
                     "views:\n  front: {image: f.png, close_gaps: 6, mask: f.png, shadow: keep}\n  right: {image: "
                     "f.png, close_gaps: 0}\n  top: {image: f.png, close_gaps: auto}\n");
    const Manifest m = read_manifest(dir / "views.yaml");
    ASSERT_EQ(m.views.size(), 3u);
    EXPECT_EQ(m.views[0].close_gaps.value_or(-1), 6);
    EXPECT_EQ(m.views[0].mask, dir / "f.png");
    EXPECT_EQ(m.views[0].shadow, "keep");
    EXPECT_EQ(m.views[1].close_gaps.value_or(-1), 0);
    EXPECT_FALSE(m.views[2].close_gaps.has_value());
    write_manifest(dir / "back.yaml", m);
    const Manifest b = read_manifest(dir / "back.yaml");
    ASSERT_EQ(b.views.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(b.views[i].close_gaps, m.views[i].close_gaps);
        EXPECT_EQ(b.views[i].mask, m.views[i].mask);
        EXPECT_EQ(b.views[i].shadow, m.views[i].shadow);
    }
    const struct {
        const char* yaml;
        const char* says;
    } bad[] = {{"views:\n  front: {image: f.png,\n    close_gaps: -2}\n", "close_gaps must be"},
               {"views:\n  front: {image: f.png,\n    close_gaps: wide}\n", "\"wide\""},
               {"views:\n  front: {image: f.png,\n    shadow: remove}\n", "shadow must be auto or keep"},
               {"views:\n  front: {image: f.png,\n    mask: [a, b]}\n", "mask must be a single value"}};
    for (const auto& c : bad) {
        test::write_text(dir / "bad.yaml", c.yaml);
        const std::string e = error_of([&] { read_manifest(dir / "bad.yaml"); });
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        EXPECT_NE(e.find("bad.yaml:3"), std::string::npos) << e;
        EXPECT_NE(e.find("view \"front\""), std::string::npos) << e;
        EXPECT_NE(e.find(c.says), std::string::npos) << e;
    }
}

namespace {

// `img` at (x0, y0) on a larger sheet of its paper colour (its corner pixel's).
Image on_sheet(const Image& img, int w, int h, int x0, int y0) {
    Image out;
    out.width = w;
    out.height = h;
    out.channels = 4;
    out.pixels.resize(std::size_t(w) * h * 4);
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
        std::copy_n(img.pixels.begin(), 4, out.pixels.begin() + std::ptrdiff_t(i * 4));
    for (int y = 0; y < img.height; ++y)
        std::copy_n(img.pixels.begin() + std::ptrdiff_t(std::size_t(y) * img.width * 4), img.width * 4,
                    out.pixels.begin() + std::ptrdiff_t((std::size_t(y0 + y) * w + x0) * 4));
    return out;
}

} // namespace

TEST(RealDrawings, TheWindowAroundTheInkGivesTheWholeImagesAnswers) {
    // Drawings much smaller than their sheet are analysed in the window around their ink;
    // every answer must be the one the whole sheet gives.
    Sketch rough;
    rough.breaks = random_breaks(6, 2, 5, 11);
    rough.overshoot = true;
    rough.doubled = true;
    const Image sketchy = on_sheet(sketch(rough), 1100, 900, 420, 300);
    // A filled drawing with a hole through it, a soft ground shadow and a small separate mark.
    Image filled = on_sheet(render(kSize, kSize,
                                   [&](double x, double y) -> std::array<float, 3> {
                                       const bool hole = std::hypot(x - 200, y - 280) < 25;
                                       if (object(x, y) && !hole) return {0.3f, 0.42f, 0.7f};
                                       if (std::hypot(x - 360, y - 60) < 4) return {0.2f, 0.2f, 0.2f};
                                       const double e = std::hypot((x - 205) / 130, (y - 342) / 14);
                                       const float shade = e < 1 ? float(1 - 0.3 * (1 - e * e)) : 1.0f;
                                       return {0.96f * shade, 0.95f * shade, 0.92f * shade};
                                   }),
                            1000, 1000, 80, 530);
    // Grey grainy paper darker at the corners (the background model varies over the sheet).
    Image paper = on_sheet(sketch(Sketch{}), 1200, 1000, 700, 120);
    std::mt19937 rng(5);
    std::normal_distribution<float> grain(0.0f, 0.015f);
    for (int y = 0; y < paper.height; ++y)
        for (int x = 0; x < paper.width; ++x) {
            const double u = (x - 600) / 600.0, v = (y - 500) / 500.0;
            const float vig = float(0.8 - 0.1 * (u * u + v * v)), g = grain(rng);
            float* p = &paper.pixels[(std::size_t(y) * paper.width + x) * 4];
            for (int k = 0; k < 3; ++k) p[k] = std::clamp(p[k] * vig + g, 0.0f, 1.0f);
        }
    for (const Image* img : std::array<const Image*, 3>{&sketchy, &filled, &paper}) {
        SilhouetteOptions whole_sheet;
        whole_sheet.window = false;
        const SilhouetteResult a = extract(*img), b = extract(*img, whole_sheet);
        const std::size_t n = std::size_t(img->width) * img->height;
        EXPECT_LT(a.analysed_pixels, n / 2);
        EXPECT_EQ(b.analysed_pixels, n);
        ASSERT_EQ(a.coverage.size(), b.coverage.size());
        std::size_t differ = 0, inside = 0;
        for (std::size_t i = 0; i < n; ++i) {
            differ += a.coverage[i] != b.coverage[i];
            inside += a.coverage[i] >= 0.5f;
        }
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(inside, 20000u);
        EXPECT_EQ(a.holes_kept, b.holes_kept);
        EXPECT_EQ(a.regions_filled, b.regions_filled);
        EXPECT_EQ(a.shadow_removed, b.shadow_removed);
        EXPECT_EQ(a.spurs_removed, b.spurs_removed);
        EXPECT_EQ(a.components_kept, b.components_kept);
        EXPECT_EQ(a.components_dropped, b.components_dropped);
    }
    // The drawings exercise what the window must keep.
    EXPECT_GT(extract(filled).shadow_removed, 500u);
    EXPECT_GE(extract(filled).holes_kept, 1);
    EXPECT_GT(extract(sketchy).spurs_removed, 0u);
}

TEST(RealDrawings, LineArtHoleOpensOnlyWhenTheOppositeViewShowsIt) {
    // A washer drawn as line art: two circles seen from the front and from the back, a
    // band from the side. The inner circle is an opening only because both the front and
    // the back show it; with the front and the side alone it is surface detail.
    test::TempDir dir("line_art_opposite");
    auto ring = [](double x, double y) -> std::array<float, 3> {
        const double r = std::hypot(x - 100, y - 100);
        const bool line = std::abs(r - 78) < 1.2 || std::abs(r - 30) < 1.2;
        return line ? std::array<float, 3>{0.1f, 0.12f, 0.4f} : std::array<float, 3>{1, 1, 1};
    };
    auto band = [](double x, double y) -> std::array<float, 3> {
        const bool in = x > 90 && x < 110 && y > 22 && y<178, inner = x> 92 && x < 108 && y > 24 && y < 176;
        return in && !inner ? std::array<float, 3>{0.1f, 0.12f, 0.4f} : std::array<float, 3>{1, 1, 1};
    };
    write_image(render(200, 200, ring), dir / "front.png");
    write_image(render(200, 200, ring), dir / "back.png");
    write_image(render(200, 200, band), dir / "right.png");
    test::write_text(dir / "both.yaml", "views:\n  front: front.png\n  back: back.png\n  right: right.png\n");
    test::write_text(dir / "one.yaml", "views:\n  front: front.png\n  right: right.png\n");
    const auto [both, report] = load_views(dir / "both.yaml", {});
    EXPECT_LT(both.views[0].coverage.at(100, 100), 0.5f);
    EXPECT_LT(both.views[1].coverage.at(100, 100), 0.5f);
    EXPECT_GT(both.views[0].coverage.at(100, 40), 0.5f);
    bool noted = false;
    for (const auto& n : report.notes) noted = noted || n.find("both show an opening") != std::string::npos;
    EXPECT_TRUE(noted);
    const Views one = load_views(dir / "one.yaml", {}).value;
    EXPECT_GT(one.views[0].coverage.at(100, 100), 0.5f);
    // The run report names each view's holes with their area: a filled washer has one.
    write_image(
        render(200, 200,
               [](double x, double y) {
                   const double r = std::hypot(x - 100, y - 100);
                   return r < 78 && r > 30 ? std::array<float, 3>{0.3f, 0.4f, 0.7f} : std::array<float, 3>{1, 1, 1};
               }),
        dir / "filled.png");
    test::write_text(dir / "filled.yaml", "views:\n  front: filled.png\n");
    const auto filled = load_views(dir / "filled.yaml", {}).stats;
    std::string note;
    for (const auto& n : filled.notes) note += n;
    EXPECT_NE(note.find("view \"front\": enclosed blank regions: 1 hole(s): "), std::string::npos) << note;
}
