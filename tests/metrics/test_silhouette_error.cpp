#include <gtest/gtest.h>

#include <random>

#include <tbb/global_control.h>

#include "core/error.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"
#include "render/shade.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

View view_from_mask(const std::string& name, const Camera& cam, const std::vector<std::uint8_t>& mask, int w, int h) {
    View v;
    v.name = name;
    v.width = w;
    v.height = h;
    v.camera = cam;
    std::vector<float> cov(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) cov[i] = mask[i] ? 1.0f : 0.0f;
    v.coverage = Coverage(cov, w, h);
    return v;
}

// Front camera with scale 1 and the world origin at pixel (0, 0): x = p.x, y = -p.y.
Camera unit_front() {
    Camera c = *Camera::named("front");
    c.scale = 1;
    c.cx = 0;
    c.cy = 0;
    return c;
}

} // namespace

TEST(Raster, RenderedBoxAndSphereCompareToThemselvesWithZeroError) {
    for (int shape = 0; shape < 2; ++shape) {
        SCOPED_TRACE(shape == 0 ? "box" : "sphere");
        const Mesh m =
            shape == 0 ? test::make_box({-1, 0, -0.5f}, {1, 3, 0.5f}) : test::make_sphere({0.3f, 1, 0}, 1.2f, 4);
        Vec3f lo, hi;
        m.bounds(lo, hi);
        Views views;
        for (const char* name : {"front", "right", "top"}) {
            const Camera c = framed_camera(*Camera::named(name), Vec3d(lo), Vec3d(hi), 256, 200);
            views.views.push_back(view_from_mask(name, c, render_mask(m, c, 256, 200), 256, 200));
        }
        const Camera q = framed_camera(Camera::from_azimuth_elevation(45, 30), Vec3d(lo), Vec3d(hi), 256, 200);
        views.views.push_back(view_from_mask("az45el30", q, render_mask(m, q, 256, 200), 256, 200));
        const SilhouetteError e = silhouette_error(m, views);
        ASSERT_EQ(e.views.size(), 4u);
        EXPECT_EQ(e.xor_pct, 0.0);
        EXPECT_EQ(e.mean_iou, 1.0);
        for (const auto& v : e.views) {
            EXPECT_GT(v.input_px, 1000);
            EXPECT_EQ(v.xor_px, 0);
        }
    }
}

TEST(Raster, KnownOffsetGivesTheKnownError) {
    // Input: a 40 x 20 rectangle. Mesh: the same box moved 3 px right.
    const Mesh box = test::make_box({10, -40, -5}, {50, -20, 5});
    const Mesh moved = test::make_box({13, -40, -5}, {53, -20, 5});
    Views views;
    views.views.push_back(view_from_mask("front", unit_front(), render_mask(box, unit_front(), 64, 64), 64, 64));
    const SilhouetteError e = silhouette_error(moved, views);
    ASSERT_EQ(e.views.size(), 1u);
    EXPECT_EQ(e.views[0].input_px, 800);
    EXPECT_EQ(e.views[0].render_px, 800);
    EXPECT_EQ(e.views[0].xor_px, 2 * 3 * 20);
    EXPECT_DOUBLE_EQ(e.xor_pct, 100.0 * 120 / 800);
    EXPECT_DOUBLE_EQ(e.views[0].iou, 37.0 / 43.0);
}

TEST(Raster, ErrorSumsOverViewsBeforeDividing) {
    const Mesh box = test::make_box({10, -40, -5}, {50, -20, 5});   // 800 px from the front
    const Mesh small = test::make_box({10, -30, -5}, {50, -20, 5}); // 400 px
    Views views;
    views.views.push_back(view_from_mask("a", unit_front(), render_mask(box, unit_front(), 64, 64), 64, 64));
    views.views.push_back(view_from_mask("b", unit_front(), render_mask(small, unit_front(), 64, 64), 64, 64));
    const SilhouetteError e = silhouette_error(small, views);
    EXPECT_DOUBLE_EQ(e.views[0].xor_pct, 50.0);
    EXPECT_DOUBLE_EQ(e.views[1].xor_pct, 0.0);
    EXPECT_DOUBLE_EQ(e.xor_pct, 100.0 * 400 / 1200);
    EXPECT_DOUBLE_EQ(e.mean_iou, 0.75);
}
