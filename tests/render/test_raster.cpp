#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <numeric>
#include <random>
#include <thread>

#include <tbb/global_control.h>

#include "core/error.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"
#include "render/shade.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

std::size_t count(const std::vector<std::uint8_t>& m) { return std::size_t(std::accumulate(m.begin(), m.end(), 0.0)); }

// Front camera with scale 1 and the world origin at pixel (0, 0): x = p.x, y = -p.y.
Camera unit_front() {
    Camera c = *Camera::named("front");
    c.scale = 1;
    c.cx = 0;
    c.cy = 0;
    return c;
}

} // namespace

TEST(Raster, BoxFaceCoversExactlyThePixelCentresInside) {
    // x in [10, 50], image y in [20, 40]: pixel edges on integers, so no centre is on an edge.
    const Mesh box = test::make_box({10, -40, -5}, {50, -20, 5});
    const auto m = render_mask(box, unit_front(), 64, 64);
    EXPECT_EQ(count(m), 40u * 20u);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i)
            EXPECT_EQ(m[std::size_t(j) * 64 + i] != 0, i >= 10 && i < 50 && j >= 20 && j < 40) << i << "," << j;
}

TEST(Raster, SharedEdgesThroughPixelCentresLeaveNoGap) {
    // The box's diagonal edges run through pixel centres; the inclusive, exactly antisymmetric
    // edge test must still fill every pixel of the face.
    const Mesh box = test::make_box({10.5f, -40.5f, -5}, {50.5f, -20.5f, 5});
    const auto m = render_mask(box, unit_front(), 64, 64);
    EXPECT_EQ(count(m), 41u * 21u); // centres on the boundary count as inside
}

TEST(Raster, MaskRowsAreTheSamePixelsAsThePixelByPixelTest) {
    // render_mask fills a row's run between the first and last pixel the exact test keeps;
    // render_depth tests every pixel. On triangles of every size and slope, many of them
    // thin, with vertices on pixel centres and edges, both keep the same pixels.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> at(-5.0f, 69.0f), small(-3.0f, 3.0f);
    std::uniform_int_distribution<int> grid(0, 64);
    Mesh soup;
    for (int t = 0; t < 3000; ++t) {
        Vec3f a{at(rng), -at(rng), 0.0f};
        if (t % 3 == 0) a = {float(grid(rng)) + 0.5f, -float(grid(rng)) - 0.5f, 0.0f}; // on centres
        const float s = t % 2 ? 1.0f : 8.0f;
        const Vec3f b = t % 5 == 0 ? Vec3f{at(rng), -at(rng), 0.0f} : a + Vec3f{s * small(rng), s * small(rng), 0.0f};
        const Vec3f c =
            t % 7 == 0 ? b + Vec3f{0.01f * small(rng), 20.0f, 0.0f} : a + Vec3f{s * small(rng), s * small(rng), 0.0f};
        const auto k = std::uint32_t(soup.positions.size());
        soup.positions.insert(soup.positions.end(), {a, b, c});
        soup.triangles.push_back({k, k + 1, k + 2});
        Mesh one;
        one.positions = {a, b, c};
        one.triangles = {{0, 1, 2}};
        const auto m = render_mask(one, unit_front(), 64, 64);
        const DepthImage d = render_depth(one, unit_front(), 64, 64);
        for (std::size_t i = 0; i < m.size(); ++i)
            ASSERT_EQ(m[i] != 0, d.face[i] != DepthImage::kNoFace) << "triangle " << t << ", pixel " << i;
    }
    const auto m = render_mask(soup, unit_front(), 64, 64);
    const DepthImage d = render_depth(soup, unit_front(), 64, 64);
    for (std::size_t i = 0; i < m.size(); ++i) EXPECT_EQ(m[i] != 0, d.face[i] != DepthImage::kNoFace) << i;
}

TEST(Raster, SphereAreaMatchesTheDisc) {
    const Mesh s = test::make_sphere({0, 0, 0}, 1.0f, 5);
    const Camera c = framed_camera(*Camera::named("right"), {-1, -1, -1}, {1, 1, 1}, 400, 400);
    const auto m = render_mask(s, c, 400, 400);
    const double r = 0.9 * 400 / 2;
    const double disc = 3.14159265358979 * r * r;
    // An icosphere of level 5 is a little smaller than its circumscribed sphere.
    EXPECT_NEAR(double(count(m)) / disc, 1.0, 0.01);
}

TEST(Raster, FramedCameraFollowsTheConventions) {
    const Vec3d lo{1, 2, 3}, hi{3, 6, 4};
    for (const char* name : {"front", "right", "top", "back", "left", "bottom"}) {
        SCOPED_TRACE(name);
        const Camera c = framed_camera(*Camera::named(name), lo, hi, 300, 200);
        EXPECT_DOUBLE_EQ(c.scale, 0.9 * 200 / 4.0);
        const Vec2d mid = c.project((lo + hi) * 0.5);
        EXPECT_NEAR(mid.x, 150, 1e-9);
        EXPECT_NEAR(mid.y, 100, 1e-9);
    }
    EXPECT_THROW(framed_camera(*Camera::named("front"), lo, lo, 10, 10), Error);
}

TEST(Raster, PerspectiveSquareAndClippingBehindTheCamera) {
    // Camera at (0, 0, 10) looking down -Z, focal 100 px, principal point (64, 64).
    const double f = 100, c0 = 64;
    const std::array<double, 12> P = {f, 0, -c0, c0 * 10, 0, -f, -c0, c0 * 10, 0, 0, -1, 10};
    const Camera cam = Camera::perspective(P);
    // Front face at z = 0 (distance 10): half-size 1 -> 10 px; the far face is smaller.
    const Mesh box = test::make_box({-1, -1, -3}, {1, 1, 0});
    EXPECT_EQ(count(render_mask(box, cam, 128, 128)), 20u * 20u);
    // The same matrix negated projects alike.
    std::array<double, 12> N = P;
    for (double& v : N) v = -v;
    EXPECT_EQ(count(render_mask(box, Camera::perspective(N), 128, 128)), 20u * 20u);

    // A ground plane y = -1 reaching behind the camera: only rows below the horizon, none above.
    Mesh ground;
    ground.positions = {{-100, -1, -100}, {100, -1, -100}, {100, -1, 100}, {-100, -1, 100}};
    ground.triangles = {{0, 2, 1}, {0, 3, 2}};
    const auto g = render_mask(ground, cam, 128, 128);
    for (int j = 0; j < 65; ++j)
        for (int i = 0; i < 128; ++i) ASSERT_EQ(g[std::size_t(j) * 128 + i], 0) << i << "," << j;
    for (int j = 65; j < 128; ++j) EXPECT_EQ(g[std::size_t(j) * 128 + 64], 1) << j;
    for (int i = 0; i < 128; ++i) EXPECT_EQ(g[std::size_t(127) * 128 + i], 1) << i;
}

TEST(Raster, DepthImageCoversTheMaskAndKeepsTheNearestFace) {
    const Mesh s = test::make_sphere({0, 0, 0}, 1.0f, 3);
    const Camera c = framed_camera(*Camera::named("front"), {-1, -1, -1}, {1, 1, 1}, 120, 100);
    const auto m = render_mask(s, c, 120, 100);
    const DepthImage d = render_depth(s, c, 120, 100);
    for (std::size_t i = 0; i < m.size(); ++i) ASSERT_EQ(m[i] != 0, d.face[i] != DepthImage::kNoFace) << i;
    // Front view looks along -Z: depth = p . d = -z, nearest surface z ~ +1 at the centre.
    EXPECT_NEAR(d.depth[std::size_t(50) * 120 + 60], -1.0, 0.02);
    const auto& tri = s.triangles[d.face[std::size_t(50) * 120 + 60]];
    EXPECT_GT(s.positions[tri[0]].z, 0.9f);
    EXPECT_TRUE(std::isinf(d.depth[0]));
}

TEST(Raster, ArtStyleIsTheSameOnOneThreadAndOnMany) {
    // Lines (creases, inner contours) are found in parallel rows; the picture must not
    // depend on how the rows were shared out.
    const Mesh m = test::make_lopsided();
    Vec3f lo, hi;
    m.bounds(lo, hi);
    for (const Camera& direction : {*Camera::named("front"), *Camera::named("right"), *Camera::named("top"),
                                    Camera::from_azimuth_elevation(30, 20)}) {
        SCOPED_TRACE(direction.azimuth_deg);
        const Camera c = framed_camera(direction, Vec3d(lo), Vec3d(hi), 400, 400);
        const Image many = render_art(m, c, 400, 400);
        Image one;
        {
            tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
            one = render_art(m, c, 400, 400);
        }
        ASSERT_EQ(one.pixels.size(), many.pixels.size());
        std::size_t differ = 0;
        for (std::size_t i = 0; i < one.pixels.size(); ++i) differ += one.pixels[i] != many.pixels[i];
        EXPECT_EQ(differ, 0u);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(render_art(m, c, 400, 400).pixels, many.pixels) << "run " << k;
    }
}

TEST(Raster, RejectsBadImageSizes) {
    const Mesh box = test::make_box({0, 0, 0}, {1, 1, 1});
    EXPECT_THROW(render_mask(box, unit_front(), 0, 10), Error);
    EXPECT_THROW(render_depth(box, unit_front(), 10, -1), Error);
}

// A window of the depth render is that part of the whole render: the same pixel centres
// tested, so the same faces and depths, on triangles of every size and slope (thin ones,
// vertices on pixel centres), for windows inside the image and at its edges.
TEST(Raster, DepthWindowIsThatPartOfTheWholeRender) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> at(-5.0f, 69.0f), small(-3.0f, 3.0f), depth(-2.0f, 2.0f);
    std::uniform_int_distribution<int> grid(0, 64);
    Mesh soup;
    for (int t = 0; t < 2000; ++t) {
        Vec3f a{at(rng), -at(rng), depth(rng)};
        if (t % 3 == 0) a = {float(grid(rng)) + 0.5f, -float(grid(rng)) - 0.5f, depth(rng)};
        const Vec3f b = a + Vec3f{8 * small(rng), 8 * small(rng), small(rng)};
        const Vec3f c =
            t % 7 == 0 ? b + Vec3f{0.01f * small(rng), 20.0f, 0.0f} : a + Vec3f{8 * small(rng), 8 * small(rng), 0.0f};
        const auto k = std::uint32_t(soup.positions.size());
        soup.positions.insert(soup.positions.end(), {a, b, c});
        soup.triangles.push_back({k, k + 1, k + 2});
    }
    const DepthImage whole = render_depth(soup, unit_front(), 64, 64);
    for (const PixelWindow& w : {PixelWindow{0, 0, 64, 64}, PixelWindow{10, 7, 31, 40}, PixelWindow{0, 50, 64, 14},
                                 PixelWindow{63, 0, 1, 64}, PixelWindow{5, 5, 1, 1}}) {
        const DepthImage part = render_depth(soup, unit_front(), 64, 64, w);
        ASSERT_EQ(part.width, w.width);
        ASSERT_EQ(part.height, w.height);
        EXPECT_EQ(part.x0, w.x0);
        EXPECT_EQ(part.y0, w.y0);
        std::size_t differ = 0;
        for (int j = 0; j < w.height; ++j)
            for (int i = 0; i < w.width; ++i) {
                const std::size_t p = std::size_t(j) * w.width + i, q = std::size_t(j + w.y0) * 64 + (i + w.x0);
                differ += part.face[p] != whole.face[q] || !(part.depth[p] == whole.depth[q] ||
                                                             (std::isinf(part.depth[p]) && std::isinf(whole.depth[q])));
            }
        EXPECT_EQ(differ, 0u) << w.x0 << "," << w.y0 << " " << w.width << "x" << w.height;
    }
    EXPECT_THROW(render_depth(soup, unit_front(), 64, 64, {60, 0, 5, 10}), Error);
    EXPECT_THROW(render_depth(soup, unit_front(), 64, 64, {0, 0, 0, 10}), Error);
}

// A drawing works over the samples its mesh can cover (the box of the projected vertices)
// and takes the rest for paper: a face added far outside the picture widens that box to the
// whole picture, and the picture stays the same, sample for sample.
TEST(Raster, ArtOverTheMeshsBoxIsTheWholePicturesArt) {
    const Mesh m = test::make_lopsided();
    Vec3f lo, hi;
    m.bounds(lo, hi);
    Mesh wider = m; // with a face far beyond each corner of the box, seen from any side
    const float far = 10 * length(hi - lo);
    for (const Vec3f& corner : {hi + Vec3f(far, far, far), lo - Vec3f(far, far, far)}) {
        const auto k = std::uint32_t(wider.positions.size());
        wider.positions.insert(wider.positions.end(), {corner, corner + Vec3f(1, 0, 0), corner + Vec3f(0, 1, 0)});
        wider.triangles.push_back({k, k + 1, k + 2});
    }
    for (const Camera& direction :
         {*Camera::named("front"), *Camera::named("top"), Camera::from_azimuth_elevation(30, 20)}) {
        const Camera c = framed_camera(direction, Vec3d(lo), Vec3d(hi), 300, 200);
        EXPECT_EQ(render_art(m, c, 300, 200).pixels, render_art(wider, c, 300, 200).pixels) << direction.azimuth_deg;
    }
}

TEST(Raster, BlueprintStyleIsLinesOnPaperOnly) {
    // Line art as render-views --style blueprint draws it: the fill is the paper, flat, so
    // every pixel is paper or a mix of paper and the line colour; a box seen at an angle
    // shows its outline and the crease between its faces.
    const Mesh m = test::make_box({-1, -1, -1}, {1, 1, 1});
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Camera c = framed_camera(Camera::from_azimuth_elevation(30, 20), Vec3d(lo), Vec3d(hi), 200, 200);
    ArtOptions bp;
    bp.paper = bp.fill = {1, 1, 1};
    bp.shade = false;
    bp.grain = bp.vignette = 0;
    bp.ink = {0.1f, 0.2f, 0.6f};
    const Image img = render_art(m, c, 200, 200, bp);
    std::size_t line = 0;
    for (std::size_t i = 0; i < std::size_t(200) * 200; ++i) {
        const float* p = &img.pixels[i * 4];
        // On the segment from paper to ink: the blue channel falls least.
        const float t = (1 - p[0]) / 0.9f;
        EXPECT_NEAR(p[1], 1 - 0.8f * t, 2e-3f);
        EXPECT_NEAR(p[2], 1 - 0.4f * t, 2e-3f);
        line += t > 0.5f;
    }
    // The box's middle (inside a face, away from every line) is paper.
    EXPECT_EQ(img.pixels[(std::size_t(150) * 200 + 60) * 4], 1.0f);
    EXPECT_GT(line, 600u);
    EXPECT_LT(line, 4000u);
}

namespace {
// Black lines on white, no fill, as render-views --style blueprint draws them.
ArtOptions black_lines_on_white(float outline_px, bool centred) {
    ArtOptions bp;
    bp.paper = bp.fill = {1, 1, 1};
    bp.shade = false;
    bp.grain = bp.vignette = 0;
    bp.ink = {0, 0, 0};
    bp.outline_px = outline_px;
    bp.outline_centred = centred;
    return bp;
}

// The ink of the mesh drawn from the front at 200 px, inside and outside its mask.
std::array<double, 2> ink_inside_outside(const Mesh& m, const ArtOptions& bp) {
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Camera c = framed_camera(*Camera::named("front"), Vec3d(lo), Vec3d(hi), 200, 200);
    const std::vector<std::uint8_t> mask = render_mask(m, c, 200, 200);
    const Image img = render_art(m, c, 200, 200, bp);
    std::array<double, 2> ink{0, 0};
    for (std::size_t i = 0; i < mask.size(); ++i) ink[mask[i] ? 0 : 1] += 1.0 - img.pixels[i * 4];
    return ink;
}
} // namespace

TEST(Raster, BlueprintOutlineIsCentredOnTheEdge) {
    // A draughtsman inks an outline on the edge: half the line lies outside the silhouette.
    // Drawn inside (the filled style), none of it does.
    const Mesh m = test::make_box({-1, -1, -1}, {1, 1, 1});
    const auto inside_only = ink_inside_outside(m, black_lines_on_white(4, false));
    const auto centred = ink_inside_outside(m, black_lines_on_white(4, true));
    EXPECT_LT(inside_only[1], 1.0);
    EXPECT_GT(inside_only[0], 4 * 4 * 100.0); // the 4 px outline around a square of 100+ px sides
    // Centred: as much ink outside as inside, the same line in all.
    EXPECT_NEAR(centred[1] / centred[0], 1.0, 0.2);
    EXPECT_NEAR(centred[0] + centred[1], inside_only[0], 0.15 * inside_only[0]);
}

TEST(Raster, BlueprintOutlineOfASmoothSurfaceIsInkedOnce) {
    // A sphere's contour generator lies on its silhouette: drawn as an inner contour too, it
    // would ink the outline again further in. Centred, the outline is one line on the edge.
    ArtOptions bp = black_lines_on_white(3, true);
    bp.crease_px = 3;
    const auto ink = ink_inside_outside(test::make_sphere({0, 0, 0}, 1.0f, 5), bp);
    EXPECT_GT(ink[1], 100.0);
    EXPECT_NEAR(ink[0] / ink[1], 1.0, 0.2);
}
