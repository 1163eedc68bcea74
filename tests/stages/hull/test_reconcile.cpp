// Drawings that disagree, from the manifest to the carved hull: views.load reconciles them
// (stages/views/reconcile.h) and hull.carve carves what every drawing shows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "align.h"
#include "carve.h"
#include "io/image_io.h"
#include "load.h"
#include "support/test_support.h"

using namespace cm;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A drawing: black where `ink(x, y)` (pixel centres) on white, as an 8-bit PNG.
void draw(const std::filesystem::path& file, int w, int h, const std::function<bool(double, double)>& ink) {
    Image img{w, h, 3, std::vector<float>(std::size_t(w) * h * 3, 1.0f), {}};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (ink(x + 0.5, y + 0.5))
                for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * w + x) * 3 + k] = 0.0f;
    write_image(img, file);
}

// A rectangle of w x h px centred at (cx, cy), turned by `deg` degrees.
std::function<bool(double, double)> rect(double cx, double cy, double w, double h, double deg = 0) {
    const double c = std::cos(deg * kPi / 180), s = std::sin(deg * kPi / 180);
    return [=](double x, double y) {
        const double dx = x - cx, dy = y - cy, u = c * dx + s * dy, v = -s * dx + c * dy;
        return std::abs(u) <= w / 2 && std::abs(v) <= h / 2;
    };
}

std::shared_ptr<const Views> load(const std::filesystem::path& manifest, const std::string& reconcile,
                                  const std::string& opposite, std::vector<std::string>* warnings = nullptr,
                                  LoadViewsStats* stats = nullptr, const std::string& stretch = "uniform",
                                  double bend = -1) {
    LoadViewsOptions opt;
    opt.stretch = stretch;
    if (bend >= 0) opt.bend = bend;
    opt.reconcile = reconcile;
    opt.opposite = opposite;
    auto r = load_views(manifest, opt);
    if (warnings) *warnings = r.stats.warnings;
    if (stats) *stats = r.stats;
    return std::make_shared<const Views>(std::move(r.value));
}

// The carved hull's volume, in world units.
double hull_volume(const std::shared_ptr<const Views>& views, int resolution = 96) {
    CarveOptions opt;
    opt.resolution = resolution;
    const auto vol = carve(views, opt).value;
    return double(vol->occupancy->activeVoxelCount()) * std::pow(vol->voxel_size(), 3);
}

// The hull's cells above height y (world), counted.
std::size_t cells_above(const std::shared_ptr<const Views>& views, double y) {
    CarveOptions opt;
    opt.resolution = 96;
    const auto vol = carve(views, opt).value;
    std::size_t n = 0;
    for (auto it = vol->occupancy->cbeginValueOn(); it; ++it) n += vol->transform().indexToWorld(it.getCoord()).y() > y;
    return n;
}

// The carved hull's extent along each world axis (cell centres), in world units.
Vec3d hull_extent(const std::shared_ptr<const Views>& views) {
    CarveOptions opt;
    opt.resolution = 128;
    const auto vol = carve(views, opt).value;
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (auto it = vol->occupancy->cbeginValueOn(); it; ++it) {
        const auto p = vol->transform().indexToWorld(it.getCoord());
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    return hi - lo + Vec3d{1, 1, 1} * vol->voxel_size();
}

// A front box and a right view of it missing a band of rows 2 * half_band px tall across
// its middle, which the front fills.
void front_and_right_with_a_band(const test::TempDir& dir, double half_band) {
    draw(dir / "front.png", 400, 400, rect(200, 200, 200, 300));
    draw(dir / "right.png", 400, 400,
         [half_band](double x, double y) { return rect(200, 200, 150, 300)(x, y) && std::abs(y - 200) > half_band; });
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  right: right.png\n");
}

} // namespace

// A box 200 wide, 300 high, 150 deep: the front and the top as drawn, the right drawn 8 %
// taller and turned by 2 degrees. One scale per view cuts the box where the views disagree;
// reconciled with stretch: axes, the hull is the whole box.
TEST(Reconcile, BoxDrawnApartInScaleAndRollIsWhole) {
    test::TempDir dir("rc_box");
    draw(dir / "front.png", 400, 460, rect(200, 230, 200, 300));
    draw(dir / "right.png", 400, 460, rect(190, 240, 150, 300 * 1.08, 2.0));
    draw(dir / "top.png", 400, 400, rect(200, 200, 200, 150));
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  right: right.png\n  top: top.png\n");
    std::vector<std::string> warnings;
    const auto on = load(dir / "views.yaml", "on", "union", &warnings, nullptr, "axes");
    // The front's width and height as drawn; the depth, drawn by the right and the top
    // alone, between theirs.
    EXPECT_NEAR(on->bounds_max.y - on->bounds_min.y, 300.0, 1.5);
    EXPECT_NEAR(on->bounds_max.x - on->bounds_min.x, 200.0, 1.5);
    const double depth = on->bounds_max.z - on->bounds_min.z;
    EXPECT_GT(depth, 138.0);
    EXPECT_LT(depth, 151.0);
    EXPECT_GT(hull_volume(on), 0.975 * 200.0 * 300.0 * depth);
    // Told what moved: the right view, its height, its turn.
    bool told = false;
    for (const auto& w : warnings)
        told = told || (w.rfind("view \"right\" ", 0) == 0 && w.find("% in height") != std::string::npos &&
                        w.find("turned 2.0 deg to agree with \"front\"") != std::string::npos);
    EXPECT_TRUE(told) << (warnings.empty() ? "no warning" : warnings.front());
    // One scale per view: faces are cut.
    const auto off = load(dir / "views.yaml", "off", "union");
    const Vec3d e = off->bounds_max - off->bounds_min;
    EXPECT_LT(hull_volume(off), 0.96 * e.x * e.y * e.z);
}

// Front and back see along the same lines: a spike only the front draws stays in the model
// with opposite: union and is carved away with intersect.
TEST(Reconcile, SpikeOnlyTheFrontDrawsFollowsTheOppositeMode) {
    test::TempDir dir("rc_spike");
    const auto body = rect(200, 260, 200, 200);
    draw(dir / "front.png", 400, 400, [&](double x, double y) {
        // A spike 80 high above the body's top (y = 160), left of centre.
        return body(x, y) || (y > 80 && y <= 160 && std::abs(x - 150) <= 0.2 * (y - 80));
    });
    draw(dir / "back.png", 400, 400, body);
    draw(dir / "right.png", 400, 400, [&](double x, double y) { return rect(200, 220, 160, 280)(x, y); });
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  back: back.png\n  right: right.png\n");
    const auto uni = load(dir / "views.yaml", "on", "union");
    const auto inter = load(dir / "views.yaml", "on", "intersect");
    // The body's top in world units: 200 high above the bottom of the box (the spike's tip).
    const double top = uni->bounds_max.y - 80.0;
    EXPECT_GT(cells_above(uni, top + 10), 10u);
    EXPECT_EQ(cells_above(inter, top + 10), 0u);
}

// The right view leaves a band of rows empty that the front fills: bridging 30 px is far
// beyond a bend tolerance of 1 % of 300 px, so it is refused and the view is named.
TEST(Reconcile, BendBeyondTheToleranceIsRefusedWithAWarning) {
    test::TempDir dir("rc_bend");
    front_and_right_with_a_band(dir, 15);
    std::vector<std::string> warnings;
    LoadViewsStats stats;
    load(dir / "views.yaml", "on", "union", &warnings, &stats, "uniform", 0.01);
    bool refused = false;
    for (const auto& w : warnings)
        refused = refused || (w.find("view \"right\" would have to bend") == 0 &&
                              w.find("to agree with \"front\"") != std::string::npos);
    EXPECT_TRUE(refused) << (warnings.empty() ? "no warning" : warnings.front());
    ASSERT_EQ(stats.reconciled.size(), 2u);
    EXPECT_GT(stats.reconciled[0].missing_pct, 5.0); // the band: 30 of 300 rows of the front
    EXPECT_LT(stats.reconciled[0].missing_pct, 15.0);
}

// A gap within the tolerance is bent over: nothing of the front is missing, and no warning.
TEST(Reconcile, BendWithinTheToleranceClosesTheGap) {
    test::TempDir dir("rc_bend_small");
    front_and_right_with_a_band(dir, 1);
    std::vector<std::string> warnings;
    LoadViewsStats stats;
    const auto v = load(dir / "views.yaml", "on", "union", &warnings, &stats);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    ASSERT_EQ(stats.reconciled.size(), 2u);
    EXPECT_LT(stats.reconciled[0].missing_pct, 0.1);
    EXPECT_GT(stats.reconciled[1].warp_px, 0.0);
    EXPECT_NEAR(hull_volume(v), 200.0 * 300.0 * 150.0, 0.02 * 200.0 * 300.0 * 150.0);
}

// The box below drawn front (on paper `fw` x `fh`, the box centred), right and top, the top
// drawing its width 8 % longer, with their manifest.
namespace {
void draw_box_drawn_longer_on_top(const std::filesystem::path& dir, int fw, int fh) {
    draw(dir / "front.png", fw, fh, rect(fw / 2, fh / 2, 200, 300));
    draw(dir / "right.png", 400, 400, rect(200, 200, 150, 300));
    draw(dir / "top.png", 400, 400, rect(200, 200, 216, 150));
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  right: right.png\n  top: top.png\n");
}
} // namespace

// A box 200 wide, 300 high, 150 deep whose top view draws the width 8 % longer: one scale
// for the top puts its width beyond the front's and its depth short of the right's. The
// model keeps what every drawing shows: it grows to the longer of the two along each axis
// (the fitted box does not cut it), so no drawing is missing any of itself.
TEST(Reconcile, AxisDrawnLongerInOneViewIsKept) {
    test::TempDir dir("rc_longer");
    draw_box_drawn_longer_on_top(dir.path(), 400, 400);
    std::vector<std::string> warnings;
    LoadViewsStats stats;
    const auto on = load(dir / "views.yaml", "on", "union", &warnings, &stats);
    ASSERT_EQ(stats.reconciled.size(), 3u);
    for (const auto& r : stats.reconciled) EXPECT_LT(r.missing_pct, 0.5) << r.name;
    // The top's scale: the geometric mean of its width against the front's and its depth
    // against the right's (sqrt(1.08) = 1.039); the width as the top draws it, the depth as
    // the right does, the height as the front and the right.
    const Vec3d e = hull_extent(on);
    EXPECT_GT(e.x, 205.0);
    EXPECT_GT(e.z, 148.0);
    EXPECT_NEAR(e.y, 300.0, 4.0);
    // The box holds the hull and its bottom is the output frame's floor.
    EXPECT_NEAR(on->bounds_min.y, 0.0, 1e-9);
    EXPECT_NEAR(on->bounds_min.x + on->bounds_max.x, 0.0, 1e-9);
    EXPECT_GE(on->bounds_max.x - on->bounds_min.x, e.x - 2.0);
    // Each grown view is told by how much it bent.
    EXPECT_GT(stats.reconciled[0].warp_px, 2.0);
}

// As above with the front drawn on paper cropped 2 px from the box: keeping the top's longer
// width grows the front beyond its paper, which grows with it.
TEST(Reconcile, GrowingBeyondACroppedDrawingGrowsItsPaper) {
    test::TempDir dir("rc_cropped");
    draw_box_drawn_longer_on_top(dir.path(), 204, 304);
    LoadViewsStats stats;
    const auto on = load(dir / "views.yaml", "on", "union", nullptr, &stats);
    ASSERT_EQ(stats.reconciled.size(), 3u);
    for (const auto& r : stats.reconciled) EXPECT_LT(r.missing_pct, 0.5) << r.name;
    EXPECT_GT(on->views[0].width, 204);
    EXPECT_EQ(on->views[0].image.width, on->views[0].width);
    EXPECT_GT(hull_extent(on).x, 205.0);
}

// reconcile: off is the alignment alone: the silhouettes as extracted, the cameras and the
// box as the alignment sets them, and its warnings, whatever the views disagree on.
TEST(Reconcile, OffIsTheAlignmentAlone) {
    test::TempDir dir("rc_off");
    draw(dir / "front.png", 400, 460, rect(200, 230, 200, 300));
    draw(dir / "right.png", 400, 460, rect(190, 240, 150, 300 * 1.12, 2.0));
    draw(dir / "top.png", 400, 400, rect(200, 200, 200, 150));
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  right: right.png\n  top: top.png\n");
    std::vector<std::string> warnings;
    LoadViewsStats stats;
    const auto off = load(dir / "views.yaml", "off", "union", &warnings, &stats);
    EXPECT_TRUE(stats.reconciled.empty());
    // The same silhouettes aligned afresh.
    Views again = *off;
    for (auto& v : again.views) v.camera = *Camera::named(v.name);
    std::vector<std::string> again_warnings;
    align_views(again, {}, again_warnings);
    EXPECT_EQ(warnings, again_warnings);
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings[0].find("disagree on the"), std::string::npos) << warnings[0];
    for (std::size_t i = 0; i < off->views.size(); ++i) {
        EXPECT_EQ(off->views[i].camera.scale, again.views[i].camera.scale);
        EXPECT_EQ(off->views[i].camera.cx, again.views[i].camera.cx);
        EXPECT_EQ(off->views[i].camera.cy, again.views[i].camera.cy);
    }
    EXPECT_EQ(off->bounds_max.z, again.bounds_max.z);
    // Reconciled, the right view is resampled; off, it is as drawn (400 x 460).
    const auto on = load(dir / "views.yaml", "on", "union");
    EXPECT_EQ(off->views[1].width, 400);
    EXPECT_EQ(off->views[1].height, 460);
    EXPECT_NE(on->views[1].coverage.full(), off->views[1].coverage.full());
}

// An egg drawn front, right and top at 1000 px, the top drawing its width 8 % longer: the
// front grows at both ends of its width to let the top's lines of sight through. The bend is
// a smooth warp, not whole cells of the reconciliation's grid (2 px each here): along the
// front's outline its growth, measured along the outline's normal from every point of the
// drawn ellipse a pixel from the next, changes by less than a pixel from one point to the
// next, and nothing of any drawing is left out.
TEST(Reconcile, BendIsASmoothWarpOfTheOutline) {
    test::TempDir dir("rc_smooth");
    const double a = 250, b = 375; // the front's half width and half height
    auto ellipse = [](double cx, double cy, double rx, double ry) {
        return [=](double x, double y) { return std::pow((x - cx) / rx, 2) + std::pow((y - cy) / ry, 2) <= 1; };
    };
    draw(dir / "front.png", 1000, 1000, ellipse(500, 500, a, b));
    draw(dir / "right.png", 1000, 1000, ellipse(500, 500, 190, b));
    draw(dir / "top.png", 1000, 1000, ellipse(500, 500, a * 1.08, 190));
    test::write_text(dir / "views.yaml", "views:\n  front: front.png\n  right: right.png\n  top: top.png\n");
    LoadViewsStats stats;
    const auto on = load(dir / "views.yaml", "on", "union", nullptr, &stats);
    const auto off = load(dir / "views.yaml", "off", "union");
    ASSERT_EQ(stats.reconciled.size(), 3u);
    for (const auto& r : stats.reconciled) EXPECT_LT(r.missing_pct, 0.5) << r.name;
    // The front stays as drawn (the primary) on its own paper: its pixels are the drawing's.
    const View& v = on->views[0];
    ASSERT_EQ(v.width, 1000);
    ASSERT_EQ(v.height, 1000);
    // How far the silhouette reaches beyond point p of the drawn outline along its normal n.
    // (Coverage bilinear between pixel centres, so that a pixel's staircase counts a fraction.)
    auto reach = [](const Coverage& c, double px, double py, double nx, double ny) {
        auto at = [&](double x, double y) {
            const int i = int(std::floor(x - 0.5)), j = int(std::floor(y - 0.5));
            const double u = x - 0.5 - i, w = y - 0.5 - j;
            return (1 - w) * ((1 - u) * c.at(i, j) + u * c.at(i + 1, j)) +
                   w * ((1 - u) * c.at(i, j + 1) + u * c.at(i + 1, j + 1));
        };
        double t = -3;
        while (t < 60 && at(px + t * nx, py + t * ny) >= 0.5) t += 0.05;
        return t;
    };
    const int n = 2000; // about one point per pixel of the outline
    std::vector<double> grown(n);
    for (int i = 0; i < n; ++i) {
        const double t = 2 * kPi * i / n, px = 500 + a * std::cos(t), py = 500 + b * std::sin(t);
        const double nx = std::cos(t) / a, ny = std::sin(t) / b, len = std::hypot(nx, ny);
        grown[std::size_t(i)] =
            reach(v.coverage, px, py, nx / len, ny / len) - reach(off->views[0].coverage, px, py, nx / len, ny / len);
    }
    double most = 0, step = 0;
    for (int i = 0; i < n; ++i) {
        most = std::max(most, grown[std::size_t(i)]);
        step = std::max(step, std::abs(grown[std::size_t(i)] - grown[std::size_t((i + 1) % n)]));
    }
    EXPECT_GT(most, 3.0);
    EXPECT_LE(stats.reconciled[0].warp_px, 1.5 * most + 2);
    EXPECT_GE(stats.reconciled[0].warp_px, most - 1);
    EXPECT_LT(step, 1.0) << "the outline grows by " << most << " px at most";
}
