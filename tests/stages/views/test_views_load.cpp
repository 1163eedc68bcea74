// Loading views: the manifest's forms, cameras, alignment, and errors naming the view.
#include <gtest/gtest.h>

#include <cmath>

#include "align.h"
#include "core/error.h"
#include "core/stage.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "load.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;

namespace {

// Black rectangle [x0, x1) x [y0, y1) on white, as an 8-bit PNG.
void write_rect(const std::filesystem::path& file, int w, int h, int x0, int y0, int x1, int y1) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.assign(std::size_t(w) * h * 3, 1.0f);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int k = 0; k < 3; ++k) img.pixels[(std::size_t(y) * w + x) * 3 + k] = 0.0f;
    write_image(img, file);
}

View rect_view(const std::string& name, int w, int h, int x0, int y0, int x1, int y1) {
    View v;
    v.name = name;
    v.width = w;
    v.height = h;
    v.camera = *Camera::named(name);
    std::vector<float> cov(std::size_t(w) * h, 0.0f);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) cov[std::size_t(y) * w + x] = 1.0f;
    v.coverage = Coverage(cov, w, h);
    return v;
}

} // namespace

TEST(ViewsLoad, EveryNamedViewRendersAsItsAzimuthElevationForm) {
    // Not only the same vectors: the same pixels through the rasteriser.
    const Mesh m = test::make_box({-1, 0, -0.3f}, {0.6f, 2, 0.8f});
    const struct {
        const char* name;
        double az, el;
    } rows[] = {{"front", 0, 0},  {"right", 90, 0}, {"back", 180, 0},
                {"left", 270, 0}, {"top", 0, 90},   {"bottom", 0, -90}};
    for (const auto& r : rows) {
        SCOPED_TRACE(r.name);
        const Camera a = framed_camera(*Camera::named(r.name), {-1, 0, -0.3}, {0.6, 2, 0.8}, 97, 80);
        const Camera b =
            framed_camera(Camera::from_azimuth_elevation(r.az, r.el), {-1, 0, -0.3}, {0.6, 2, 0.8}, 97, 80);
        EXPECT_EQ(render_mask(m, a, 97, 80), render_mask(m, b, 97, 80));
    }
}

TEST(ViewsLoad, AlignmentRecoversKnownScalesAndOffsets) {
    // An object 40 wide (X), 60 high (Y), 30 deep (Z) in units of the front view's pixels.
    // front: 1 px/unit at (10, 20); right: 1.5 px/unit at (5, 7); top: 2 px/unit at (3, 4).
    Views views;
    views.views.push_back(rect_view("front", 100, 100, 10, 20, 50, 80));
    views.views.push_back(rect_view("right", 100, 120, 5, 7, 5 + 45, 7 + 90));
    views.views.push_back(rect_view("top", 100, 100, 3, 4, 3 + 80, 4 + 60));
    std::vector<std::string> warnings;
    align_views(views, {}, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_NEAR(views.bounds_max.x - views.bounds_min.x, 40, 1e-9);
    EXPECT_NEAR(views.bounds_max.y - views.bounds_min.y, 60, 1e-9);
    EXPECT_NEAR(views.bounds_max.z - views.bounds_min.z, 30, 1e-9);
    // Pivot at the bottom centre.
    EXPECT_NEAR(views.bounds_min.y, 0, 1e-9);
    EXPECT_NEAR(views.bounds_min.x + views.bounds_max.x, 0, 1e-9);
    EXPECT_NEAR(views.bounds_min.z + views.bounds_max.z, 0, 1e-9);
    EXPECT_NEAR(views.views[0].camera.scale, 1.0, 1e-9);
    EXPECT_NEAR(views.views[1].camera.scale, 1.5, 1e-9);
    EXPECT_NEAR(views.views[2].camera.scale, 2.0, 1e-9);
    // The box's corners land on the rectangles' edges in every view.
    const int rect[3][4] = {{10, 20, 50, 80}, {5, 7, 50, 97}, {3, 4, 83, 64}};
    for (int i = 0; i < 3; ++i) {
        SCOPED_TRACE(views.views[std::size_t(i)].name);
        double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
        for (int c = 0; c < 8; ++c) {
            const Vec3d p{c & 1 ? views.bounds_max.x : views.bounds_min.x,
                          c & 2 ? views.bounds_max.y : views.bounds_min.y,
                          c & 4 ? views.bounds_max.z : views.bounds_min.z};
            const Vec2d q = views.views[std::size_t(i)].camera.project(p);
            x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
        }
        EXPECT_NEAR(x0, rect[i][0], 1e-9);
        EXPECT_NEAR(y0, rect[i][1], 1e-9);
        EXPECT_NEAR(x1, rect[i][2], 1e-9);
        EXPECT_NEAR(y1, rect[i][3], 1e-9);
    }
    // The box itself re-renders onto the input rectangles exactly.
    const Mesh box = test::make_box(Vec3f(views.bounds_min), Vec3f(views.bounds_max));
    EXPECT_EQ(silhouette_error(box, views).xor_pct, 0.0);
}

TEST(ViewsLoad, RealSizeRescalesTheOutputUnits) {
    Views views;
    views.views.push_back(rect_view("front", 100, 100, 10, 20, 50, 80));
    views.views.push_back(rect_view("right", 100, 100, 30, 20, 60, 80));
    AlignOptions opt;
    opt.height = 1.8;
    std::vector<std::string> warnings;
    align_views(views, opt, warnings);
    EXPECT_NEAR(views.bounds_max.y, 1.8, 1e-12);
    EXPECT_NEAR(views.bounds_max.x - views.bounds_min.x, 1.2, 1e-12);
    EXPECT_NEAR(views.units_per_pixel, 0.03, 1e-12);
    EXPECT_NEAR(views.views[0].camera.scale, 1 / 0.03, 1e-9);
}

TEST(ViewsLoad, DisagreeingViewsWarnNamingViewsAndAxis) {
    Views views;
    // front fixes width and height, top (same scale through the width) fixes the depth, so the
    // right view's scale follows from the depth and its height is 10 % off.
    views.views.push_back(rect_view("front", 100, 100, 10, 20, 50, 80)); // 40 x 60
    views.views.push_back(rect_view("top", 100, 100, 10, 10, 50, 40));   // 40 x 30
    views.views.push_back(rect_view("right", 100, 100, 30, 20, 60, 86)); // 30 x 66
    std::vector<std::string> warnings;
    align_views(views, {}, warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("\"front\""), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("\"right\""), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("height"), std::string::npos) << warnings[0];
}

TEST(ViewsLoad, ManifestShortAndLongFormsAndCameras) {
    test::TempDir dir("vl_manifest");
    write_rect(dir / "f.png", 80, 80, 20, 10, 60, 70);
    write_rect(dir / "r.png", 80, 80, 25, 10, 55, 70);
    write_rect(dir / "q.png", 80, 80, 15, 10, 65, 70);
    test::write_text(dir / "calib.txt", "CONTOUR\n1 0 0 40\n0 -1 0 40\n0 0 0 1\n");
    test::write_text(
        dir / "views.yaml",
        "height: 2.0\n"
        "views:\n"
        "  front: f.png\n"
        "  side: {image: r.png, view: right, background: white, threshold: 0.3, keep: largest, holes: keep}\n"
        "  three_quarter: {image: q.png, azimuth: 45, elevation: 30}\n");
    const Views v = load_views(dir / "views.yaml", {}).value;
    ASSERT_EQ(v.views.size(), 3u);
    EXPECT_EQ(v.views[1].name, "side");
    EXPECT_NEAR(v.views[1].camera.d.x, -1, 1e-12);
    EXPECT_NEAR(v.views[2].camera.azimuth_deg, 45, 1e-12);
    EXPECT_NEAR(v.views[2].camera.elevation_deg, 30, 1e-12);
    EXPECT_NEAR(v.bounds_max.y, 2.0, 1e-9);
    EXPECT_FALSE(v.calibrated);

    // Calibrated views: inline matrix, matrix_file (header words skipped), K/R/t.
    test::write_text(dir / "calib.yaml",
                     "bounds: [-1, -1, -1, 1, 1, 1]\n"
                     "views:\n"
                     "  a: {image: f.png, matrix: [[1, 0, 0, 40], [0, -1, 0, 40], [0, 0, 0, 1]]}\n"
                     "  b: {image: f.png, matrix_file: calib.txt}\n"
                     "  c: {image: f.png, K: [[2, 0, 40], [0, 2, 40], [0, 0, 1]], R: [[1, 0, 0], [0, -1, 0], [0, 0, "
                     "-1]], t: [0, 0, 10]}\n");
    const Views c = load_views(dir / "calib.yaml", {}).value;
    EXPECT_TRUE(c.calibrated);
    EXPECT_TRUE(c.has_bounds);
    EXPECT_EQ(c.views[0].camera.P, c.views[1].camera.P);
    const std::array<double, 12> krt = {2, 0, -40, 400, 0, -2, -40, 400, 0, 0, -1, 10};
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(c.views[2].camera.P[std::size_t(i)], krt[std::size_t(i)], 1e-12) << i;
}

TEST(ViewsLoad, ManifestErrorsNameTheFileLineAndView) {
    test::TempDir dir("vl_errors");
    write_rect(dir / "f.png", 40, 40, 10, 10, 30, 30);
    auto msg = [&](const std::string& yaml) {
        test::write_text(dir / "m.yaml", yaml);
        return error_of([&] { read_manifest(dir / "m.yaml"); });
    };
    std::string e = msg("views:\n  front: {image: f.png, colour: red}\n");
    EXPECT_NE(e.find("m.yaml:2"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key \"colour\""), std::string::npos) << e;
    e = msg("views:\n  sketch: f.png\n");
    EXPECT_NE(e.find("\"sketch\""), std::string::npos) << e;
    e = msg("views:\n  front: {image: f.png, background: pinkish}\n");
    EXPECT_NE(e.find("pinkish"), std::string::npos) << e;
    e = msg("views:\n  a: {image: f.png, matrix: [1, 2, 3]}\n");
    EXPECT_NE(e.find("3x4"), std::string::npos) << e;
    e = msg("views:\n  a: {image: f.png, matrix_file: nowhere.txt}\n");
    EXPECT_NE(e.find("nowhere.txt"), std::string::npos) << e;
    e = msg("views:\n  a: {image: f.png, K: [[1,0,0],[0,1,0],[0,0,1]]}\n");
    EXPECT_NE(e.find("K, R and t go together"), std::string::npos) << e;
    e = msg("views:\n  front: {image: f.png, view: front, azimuth: 10}\n");
    EXPECT_NE(e.find("not both"), std::string::npos) << e;
}

TEST(ViewsLoad, EmptySilhouetteAndUnreadableImageNameTheView) {
    test::TempDir dir("vl_empty");
    write_rect(dir / "f.png", 40, 40, 10, 10, 30, 30);
    write_rect(dir / "blank.png", 40, 40, 0, 0, 0, 0);
    test::write_text(dir / "views.yaml", "views:\n  front: f.png\n  right: blank.png\n");
    std::string e = error_of([&] { load_views(dir / "views.yaml", {}); });
    EXPECT_NE(e.find("view \"right\""), std::string::npos) << e;
    EXPECT_NE(e.find("empty silhouette"), std::string::npos) << e;
    test::write_text(dir / "views.yaml", "views:\n  front: f.png\n  top: missing.png\n");
    e = error_of([&] { load_views(dir / "views.yaml", {}); });
    EXPECT_NE(e.find("view \"top\""), std::string::npos) << e;
    EXPECT_NE(e.find("missing.png"), std::string::npos) << e;
}

TEST(ViewsLoad, TumBunnyCalibratedSilhouettes) {
    // Real calibrated data: black-on-white PGM silhouettes and CONTOUR matrix files.
    const auto data = test::shared_dir() / "data" / "multiview" / "tum_bunny";
    if (!std::filesystem::exists(data / "calib" / "0000.txt")) GTEST_SKIP() << "no " << data;
    test::TempDir dir("vl_tum");
    std::string yaml = "bounds: [-7.5, -10, -7.5, 7.5, 10, 15]\nviews:\n";
    for (const char* id : {"0000", "0010", "0020"})
        yaml += std::string("  v") + id + ": {image: " + (data / "silhouettes" / (std::string(id) + ".pgm")).string() +
                ", matrix_file: " + (data / "calib" / (std::string(id) + ".txt")).string() + "}\n";
    test::write_text(dir / "views.yaml", yaml);
    const Views v = load_views(dir / "views.yaml", {}).value;
    ASSERT_EQ(v.views.size(), 3u);
    EXPECT_TRUE(v.calibrated);
    for (const auto& view : v.views) {
        SCOPED_TRACE(view.name);
        EXPECT_FALSE(view.camera.orthographic());
        // Object = black pixels (threshold 128), as the data set defines it.
        std::size_t inter = 0, uni = 0;
        for (std::size_t i = 0; i < view.coverage.size(); ++i) {
            const bool s = view.coverage[i] >= 0.5f, t = view.image.rgba(i)[0] < 0.5f;
            inter += s && t;
            uni += s || t;
        }
        EXPECT_GT(double(inter) / double(uni), 0.995);
        // The published box projects around the silhouette.
        const Vec2d c = view.camera.project({0, 0, 3.75});
        EXPECT_TRUE(c.x > 0 && c.x < view.width && c.y > 0 && c.y < view.height);
    }
}

TEST(ViewsLoad, ObliqueViewIsPlacedThroughTheHullOfTheAxisViews) {
    // A sphere with a box on its shoulder, framed as render-views frames it; then the views
    // forget their cameras' scale and origin and alignment must find them again.
    const Mesh m = test::make_lopsided();
    Vec3f lo, hi;
    m.bounds(lo, hi);
    Views views;
    for (const char* name : {"front", "right", "top", "az45el30"}) {
        const Camera dir = Camera::named(name) ? *Camera::named(name) : Camera::from_azimuth_elevation(45, 30);
        const Camera cam = framed_camera(dir, Vec3d(lo), Vec3d(hi), 240, 240);
        View v;
        v.name = name;
        v.width = v.height = 240;
        v.camera = dir; // direction only, as views.load sets it
        const auto mask = render_mask(m, cam, 240, 240);
        v.coverage = Coverage(std::vector<float>(mask.begin(), mask.end()), v.width, v.height);
        views.views.push_back(v);
    }
    std::vector<std::string> warnings;
    align_views(views, {}, warnings);
    EXPECT_TRUE(warnings.empty());
    // Map the mesh onto the aligned box, as compare --fit bbox does, and re-render.
    Mesh fitted = m;
    for (auto& p : fitted.positions)
        for (int k = 0; k < 3; ++k)
            p[k] = float(views.bounds_min[k] +
                         (p[k] - lo[k]) / (hi[k] - lo[k]) * (views.bounds_max[k] - views.bounds_min[k]));
    const SilhouetteError e = silhouette_error(fitted, views);
    ASSERT_EQ(e.views.size(), 4u);
    for (const auto& v : e.views) EXPECT_LT(v.xor_pct, 1.5) << v.view;
}

TEST(ViewsLoad, AntiAliasedSilhouettesGiveSubPixelExtents) {
    // A sphere drawn with anti-aliased edges (4 x 4 samples per pixel) at scales that put its
    // outline between pixel edges: the aligned box matches the true diameter to a fraction
    // of a pixel.
    const Mesh s = test::make_sphere({0, 0, 0}, 1.0f, 6);
    Vec3f lo, hi;
    s.bounds(lo, hi);
    for (double size : {200.0, 201.3, 202.7}) {
        SCOPED_TRACE(size);
        Views views;
        const double scale = size / 2.6; // px per unit
        for (const char* name : {"front", "right", "top"}) {
            Camera cam = *Camera::named(name);
            cam.scale = scale;
            cam.cx = 150.37;
            cam.cy = 149.81;
            const auto fine = render_mask(s, resized_camera(cam, 4), 1200, 1200);
            View v;
            v.name = name;
            v.width = v.height = 300;
            v.camera = *Camera::named(name);
            std::vector<float> cov(300 * 300, 0.0f);
            for (int y = 0; y < 1200; ++y)
                for (int x = 0; x < 1200; ++x)
                    cov[std::size_t(y / 4) * 300 + x / 4] += fine[std::size_t(y) * 1200 + x] / 16.0f;
            v.coverage = Coverage(cov, 300, 300);
            views.views.push_back(v);
        }
        std::vector<std::string> warnings;
        align_views(views, {}, warnings);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(views.bounds_max[k] - views.bounds_min[k], scale * (hi[k] - lo[k]), 0.25) << k;
    }
}

TEST(ViewsLoad, StageSavesSilhouettesBesideTheReport) {
    test::TempDir dir("vl_stage");
    write_rect(dir / "f.png", 60, 50, 10, 10, 40, 45);
    write_rect(dir / "r.png", 60, 50, 20, 10, 35, 45);
    test::write_text(dir / "views.yaml", "views:\n  front: f.png\n  right: r.png\n");
    test::StageHarness h("views.load");
    h.param("manifest", dir / "views.yaml").params("{keep: auto, align_tolerance: 0.02, save_silhouettes: true}");
    h.side_output_dir(dir.path()).keep_staged();
    auto views = h.run<Views>();
    const auto& staged = h.staged();
    ASSERT_EQ(views->views.size(), 2u);
    ASSERT_EQ(staged.size(), 2u);
    EXPECT_EQ(staged[0].second, dir / "front.silhouette.png");
    EXPECT_EQ(staged[1].second, dir / "right.silhouette.png");
    const Image sil = read_image(staged[1].first);
    EXPECT_EQ(sil.width, 60);
    EXPECT_EQ(sil.height, 50);
    EXPECT_GT(sil.at(25, 20, 0), 0.99f); // inside the right view's rectangle: white
    EXPECT_LT(sil.at(5, 5, 0), 0.01f);
    EXPECT_TRUE(h.metrics().count("views"));
}

namespace {

// The box X in [-20, 20], Y in [0, 60], Z in [-15, 15] seen through known cameras, as
// rectangles on the pixel grid: front 1.5 px/unit at (70, 100), right 2 px/unit at (50, 130),
// top 1 px/unit at (30, 20), and a second top drawn at 2.5 px/unit at (57, 46.5).
struct KnownView {
    const char* name;
    const char* view;
    int w, h;
    double scale, cx, cy;
    int x0, y0, x1, y1;
};
constexpr KnownView kFront{"front", "front", 150, 120, 1.5, 70, 100, 40, 10, 100, 100};
constexpr KnownView kRight{"right", "right", 100, 140, 2.0, 50, 130, 20, 10, 80, 130};
constexpr KnownView kTop{"top", "top", 60, 40, 1.0, 30, 20, 10, 5, 50, 35};
constexpr KnownView kTopLarge{"top", "top", 120, 100, 2.5, 57, 46.5, 7, 9, 107, 84};

View known_view(const KnownView& k, bool with_camera) {
    View v = rect_view(k.view, k.w, k.h, k.x0, k.y0, k.x1, k.y1);
    v.name = k.name;
    if (with_camera) v.camera.scale = k.scale, v.camera.cx = k.cx, v.camera.cy = k.cy;
    return v;
}

void expect_camera(const Camera& c, const KnownView& k, double tol) {
    EXPECT_NEAR(c.scale, k.scale, tol) << k.name;
    EXPECT_NEAR(c.cx, k.cx, tol) << k.name;
    EXPECT_NEAR(c.cy, k.cy, tol) << k.name;
}

} // namespace

TEST(ViewsLoad, FixedCamerasAreKeptExactly) {
    Views views;
    for (const auto& k : {kFront, kRight, kTop}) views.views.push_back(known_view(k, true));
    AlignOptions opt;
    opt.fixed = {true, true, true};
    std::vector<std::string> warnings;
    align_views(views, opt, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    expect_camera(views.views[0].camera, kFront, 0.0);
    expect_camera(views.views[1].camera, kRight, 0.0);
    expect_camera(views.views[2].camera, kTop, 0.0);
    // The box the silhouettes imply under the fixed cameras, in their world.
    ASSERT_TRUE(views.has_bounds);
    const Vec3d lo{-20, 0, -15}, hi{20, 60, 15};
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(views.bounds_min[k], lo[k], 1e-9) << k;
        EXPECT_NEAR(views.bounds_max[k], hi[k], 1e-9) << k;
    }
    EXPECT_NEAR(views.units_per_pixel, 1 / 1.5, 1e-12);
    EXPECT_EQ(silhouette_error(test::make_box(Vec3f(lo), Vec3f(hi)), views).xor_pct, 0.0);

    // A given box wins over the silhouettes'; the cameras stay.
    opt.bounds = std::array<double, 6>{-21, -1, -16, 21, 61, 16};
    align_views(views, opt, warnings);
    EXPECT_EQ(views.bounds_min.x, -21);
    EXPECT_EQ(views.bounds_max.y, 61);
    expect_camera(views.views[1].camera, kRight, 0.0);

    // A fixed camera that puts its silhouette 3 units off along X is kept, with a warning
    // naming both views and the axis.
    views.views[2].camera.cx = 33;
    opt.bounds.reset();
    align_views(views, opt, warnings);
    EXPECT_EQ(views.views[2].camera.cx, 33);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("\"front\""), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("\"top\""), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("width (X)"), std::string::npos) << warnings[0];

    // A real size cannot go with fixed cameras: they set the units.
    opt.height = 2.0;
    EXPECT_NE(error_of([&] { align_views(views, opt, warnings); }).find("real size"), std::string::npos);
}

TEST(ViewsLoad, FreeViewsAlignToTheFixedOnes) {
    // front and right fixed; top free, drawn at its own scale and placement: alignment finds
    // them through the widths (front) and depths (right) it shares.
    {
        Views views;
        views.views.push_back(known_view(kFront, true));
        views.views.push_back(known_view(kRight, true));
        views.views.push_back(known_view(kTopLarge, false));
        AlignOptions opt;
        opt.fixed = {true, true, false};
        std::vector<std::string> warnings;
        align_views(views, opt, warnings);
        EXPECT_TRUE(warnings.empty()) << warnings.front();
        expect_camera(views.views[0].camera, kFront, 0.0);
        expect_camera(views.views[1].camera, kRight, 0.0);
        expect_camera(views.views[2].camera, kTopLarge, 1e-9);
    }
    // Only the top view fixed, and not first: the height is measured by the free views only,
    // and stands on Y = 0.
    {
        Views views;
        views.views.push_back(known_view(kFront, false));
        views.views.push_back(known_view(kRight, false));
        views.views.push_back(known_view(kTop, true));
        AlignOptions opt;
        opt.fixed = {false, false, true};
        std::vector<std::string> warnings;
        align_views(views, opt, warnings);
        EXPECT_TRUE(warnings.empty()) << warnings.front();
        expect_camera(views.views[0].camera, kFront, 1e-9);
        expect_camera(views.views[1].camera, kRight, 1e-9);
        expect_camera(views.views[2].camera, kTop, 0.0);
        EXPECT_NEAR(views.bounds_min.y, 0, 1e-9);
        EXPECT_NEAR(views.bounds_max.y, 60, 1e-9);
        EXPECT_NEAR(views.units_per_pixel, 1 / 1.5, 1e-9);
    }
    // A free view whose two axes disagree with the fixed ones warns, naming views and axis.
    {
        Views views;
        views.views.push_back(known_view(kFront, true));
        views.views.push_back(known_view(kTop, true));
        View right = known_view(kRight, false);
        std::vector<float> cov(right.coverage.size(), 0.0f); // 30 units deep but 66 high
        for (int y = 0; y < 132; ++y)
            for (int x = 20; x < 80; ++x) cov[std::size_t(y) * 100 + x] = 1.0f;
        right.coverage = Coverage(cov, right.width, right.height);
        views.views.push_back(right);
        AlignOptions opt;
        opt.fixed = {true, true, false};
        std::vector<std::string> warnings;
        align_views(views, opt, warnings);
        // Its scale is the best fit to both axes, so both are off by about 5 %.
        ASSERT_EQ(warnings.size(), 2u);
        EXPECT_NE(warnings[0].find("views \"top\" and \"right\" disagree on the depth (Z)"), std::string::npos)
            << warnings[0];
        EXPECT_NE(warnings[1].find("views \"front\" and \"right\" disagree on the height (Y)"), std::string::npos)
            << warnings[1];
    }
}

TEST(ViewsLoad, ManifestFixesCamerasAndBounds) {
    test::TempDir dir("vl_fixed");
    for (const auto& k : {kFront, kRight, kTopLarge})
        write_rect(dir / (std::string(k.view) + ".png"), k.w, k.h, k.x0, k.y0, k.x1, k.y1);
    test::write_text(dir / "views.yaml",
                     "bounds: [-20, 0, -15, 20, 60, 15]\n"
                     "views:\n"
                     "  front: {image: front.png, scale: 1.5, origin: [70, 100]}\n"
                     "  side: {image: right.png, view: right, scale: 2, origin: [50, 130]}\n"
                     "  top: top.png\n");
    const Manifest m = read_manifest(dir / "views.yaml");
    ASSERT_EQ(m.views.size(), 3u);
    EXPECT_TRUE(m.fixed_cameras());
    EXPECT_EQ(m.views[0].scale, 1.5);
    ASSERT_TRUE(m.views[1].origin.has_value());
    EXPECT_EQ((*m.views[1].origin)[0], 50.0);
    EXPECT_EQ((*m.views[1].origin)[1], 130.0);
    EXPECT_FALSE(m.views[2].scale.has_value());
    const auto [v, report] = load_views(dir / "views.yaml", {});
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    EXPECT_FALSE(v.calibrated);
    expect_camera(v.views[0].camera, kFront, 0.0);
    expect_camera(v.views[1].camera, kRight, 0.0);
    expect_camera(v.views[2].camera, kTopLarge, 1e-6); // the extraction's float coverage
    ASSERT_TRUE(v.has_bounds);
    EXPECT_EQ(v.bounds_min.x, -20);
    EXPECT_EQ(v.bounds_max.y, 60);
    const Mesh box = test::make_box({-20, 0, -15}, {20, 60, 15});
    EXPECT_EQ(silhouette_error(box, v).xor_pct, 0.0);
}

TEST(ViewsLoad, FixedCameraErrorsNameTheFileLineAndView) {
    test::TempDir dir("vl_fixed_errors");
    write_rect(dir / "f.png", 40, 40, 10, 10, 30, 30);
    auto msg = [&](const std::string& yaml) {
        test::write_text(dir / "m.yaml", yaml);
        return error_of([&] { read_manifest(dir / "m.yaml"); });
    };
    auto expect_has = [](const std::string& e, std::initializer_list<const char*> parts) {
        for (const char* p : parts) EXPECT_NE(e.find(p), std::string::npos) << "\"" << p << "\" not in: " << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    };
    expect_has(msg("views:\n  front: {image: f.png, scale: -2, origin: [1, 2]}\n"),
               {"m.yaml:2", "view \"front\"", "scale must be a positive number"});
    expect_has(msg("views:\n  front: {image: f.png, scale: 0, origin: [1, 2]}\n"),
               {"m.yaml:2", "view \"front\"", "positive"});
    expect_has(msg("views:\n  front: {image: f.png, scale: big, origin: [1, 2]}\n"),
               {"m.yaml:2", "view \"front\"", "scale must be a number", "big"});
    expect_has(msg("views:\n  front: f.png\n  right:\n    image: f.png\n    scale: 2\n    origin: [1, 2, 3]\n"),
               {"m.yaml:6", "view \"right\"", "origin must be 2 numbers", "got 3"});
    expect_has(msg("views:\n  front: {image: f.png, scale: 2, origin: [1, x]}\n"),
               {"m.yaml:2", "view \"front\"", "\"x\""});
    expect_has(msg("views:\n  front: {image: f.png, scale: 2}\n"),
               {"m.yaml:2", "view \"front\"", "scale and origin go together"});
    expect_has(msg("views:\n  front: {image: f.png, origin: [1, 2]}\n"),
               {"view \"front\"", "scale and origin go together"});
    expect_has(msg("views:\n  a: {image: f.png, matrix: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 1]], scale: 2, origin: "
                   "[1, 2]}\n"),
               {"m.yaml:2", "view \"a\"", "calibrated view (matrix) takes neither"});
    expect_has(msg("height: 1.8\nviews:\n  front: {image: f.png, scale: 2, origin: [1, 2]}\n"),
               {"m.yaml:1", "height cannot go with fixed cameras"});
    expect_has(msg("bounds: [0, 0, 0, 1, 1, 1]\nviews:\n  front: f.png\n"),
               {"m.yaml:1", "bounds needs calibrated views (matrix) or fixed cameras"});
    expect_has(msg("bounds: [0, 2, 0, 1, 1, 1]\nviews:\n  front: {image: f.png, scale: 2, origin: [1, 2]}\n"),
               {"m.yaml:1", "ymin must not exceed ymax"});
}

TEST(ViewsLoad, FreeObliqueViewIsPlacedAgainstFixedAxisViews) {
    // The lopsided object framed as render-views frames it; the axis views keep their
    // cameras, the oblique one forgets its own and is placed through the hull at the fixed
    // views' scale.
    const Mesh m = test::make_lopsided();
    Vec3f lo, hi;
    m.bounds(lo, hi);
    Views views;
    std::vector<Camera> truth;
    for (const char* name : {"front", "right", "top", "az45el30"}) {
        const Camera dir = Camera::named(name) ? *Camera::named(name) : Camera::from_azimuth_elevation(45, 30);
        truth.push_back(framed_camera(dir, Vec3d(lo), Vec3d(hi), 240, 240));
        View v;
        v.name = name;
        v.width = v.height = 240;
        v.camera = truth.back();
        const auto mask = render_mask(m, truth.back(), 240, 240);
        v.coverage = Coverage(std::vector<float>(mask.begin(), mask.end()), v.width, v.height);
        views.views.push_back(v);
    }
    views.views[3].camera = Camera::from_azimuth_elevation(45, 30); // direction only
    AlignOptions opt;
    opt.fixed = {true, true, true, false};
    std::vector<std::string> warnings;
    align_views(views, opt, warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(views.views[i].camera.cx, truth[i].cx);
        EXPECT_EQ(views.views[i].camera.cy, truth[i].cy);
    }
    const Camera& c = views.views[3].camera;
    EXPECT_EQ(c.scale, truth[3].scale);
    EXPECT_NEAR(c.cx, truth[3].cx, 2.0);
    EXPECT_NEAR(c.cy, truth[3].cy, 2.0);
    // The mesh in the fixed cameras' world (its own) against the views, as it is.
    const SilhouetteError e = silhouette_error(m, views);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(e.views[i].xor_px, 0.0) << e.views[i].view;
    EXPECT_LT(e.views[3].xor_pct, 1.5);
}
