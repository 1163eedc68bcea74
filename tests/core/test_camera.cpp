#include <gtest/gtest.h>

#include "core/camera.h"

using namespace cm;

namespace {
void expect_vec(const Vec3d& a, const Vec3d& b) {
    EXPECT_NEAR(a.x, b.x, 1e-12);
    EXPECT_NEAR(a.y, b.y, 1e-12);
    EXPECT_NEAR(a.z, b.z, 1e-12);
}
} // namespace

// The table of docs/conventions.md, row by row.
TEST(Camera, NamedViewsMatchTheConventionsTable) {
    struct Row {
        const char* name;
        Vec3d d, r, u;
        double az, el;
    };
    const Row rows[] = {
        {"front", {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, 0, 0},   {"back", {0, 0, 1}, {-1, 0, 0}, {0, 1, 0}, 180, 0},
        {"right", {-1, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 0}, {"left", {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 270, 0},
        {"top", {0, -1, 0}, {1, 0, 0}, {0, 0, -1}, 0, 90},   {"bottom", {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, 0, -90},
    };
    for (const auto& row : rows) {
        SCOPED_TRACE(row.name);
        auto c = Camera::named(row.name);
        ASSERT_TRUE(c.has_value());
        expect_vec(c->d, row.d);
        expect_vec(c->r, row.r);
        expect_vec(c->u, row.u);
        const Camera ae = Camera::from_azimuth_elevation(row.az, row.el);
        expect_vec(ae.d, c->d);
        expect_vec(ae.r, c->r);
        expect_vec(ae.u, c->u);
    }
    EXPECT_FALSE(Camera::named("diagonal").has_value());
}

TEST(Camera, OrthographicProjectionFollowsPixelConvention) {
    Camera c = *Camera::named("front");
    c.scale = 2;
    c.cx = 100;
    c.cy = 50;
    const Vec2d p = c.project({10, 5, 3});
    EXPECT_DOUBLE_EQ(p.x, 120); // image right is +X
    EXPECT_DOUBLE_EQ(p.y, 40);  // image up is +Y, rows grow downwards
    Vec3d o, d;
    c.ray(p.x, p.y, o, d);
    EXPECT_NEAR(o.x, 10, 1e-12);
    EXPECT_NEAR(o.y, 5, 1e-12);
    expect_vec(d, {0, 0, -1});
}

TEST(Camera, PerspectiveCentreAndRayRoundTrip) {
    // K [R | t] with a camera at (0, 0, 10) looking down -Z.
    const double f = 500, cx = 320, cy = 240;
    // R maps world to camera with camera z = -(world z - 10): R = diag(1, -1, -1), t = -R C.
    const std::array<double, 12> P = {f, 0 * 1.0, -cx, cx * 10, 0, -f, -cy, cy * 10, 0, 0, -1, 10};
    const Camera c = Camera::perspective(P);
    expect_vec(c.center(), {0, 0, 10});
    const Vec3d X{1, 2, 0};
    const Vec2d px = c.project(X);
    EXPECT_NEAR(px.x, cx + f * 1 / 10.0, 1e-9);
    EXPECT_NEAR(px.y, cy - f * 2 / 10.0, 1e-9);
    Vec3d o, d;
    c.ray(px.x, px.y, o, d);
    const Vec3d back = o + d * (length(X - o));
    expect_vec(back, X);
    EXPECT_GT(c.depth(X), 0);
}
