// The smoothing's crease hold (creases): sharp creases stay where they are, the flat sides
// beside them in their planes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh_smooth.h"
#include "support/shapes.h"

using namespace cm;

namespace {

// The largest distance of a vertex from the surface of the cube [-1, 1]^3.
double off_cube(const Mesh& m) {
    double worst = 0;
    for (const auto& p : m.positions)
        worst = std::max(worst, std::fabs(double(std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)})) - 1));
    return worst;
}

} // namespace

TEST(SmoothCreases, ACubeKeepsItsEdgesAndSidesWhenCreasesAreHeld) {
    // The grid made uneven (each coordinate t to t (1 + t^2) / 2, which keeps -1 and 1), so the
    // smoothing has something to move.
    Mesh m0 = test::make_grid_box(-1.0f, 1.0f, 12);
    for (auto& p : m0.positions)
        for (float* t : {&p.x, &p.y, &p.z}) *t = *t * (1 + *t * *t) / 2;
    SmoothOptions o;
    o.iterations = 10;
    const Mesh rounded = smooth_mesh(m0, o).value;
    EXPECT_GT(off_cube(rounded), 0.05) << "the paper's smoothing rounds the cube";
    o.crease_angle_deg = 60;
    const Mesh held = smooth_mesh(m0, o).value;
    EXPECT_LT(off_cube(held), 1e-5) << "every vertex stays on the cube's surface";
    // The vertices still move: along the edges and within the sides.
    double moved = 0;
    for (std::size_t v = 0; v < m0.positions.size(); ++v)
        moved = std::max(moved, double(length(held.positions[v] - m0.positions[v])));
    EXPECT_GT(moved, 0.01);
}

TEST(SmoothCreases, GentleBendsAreSmoothedAsBefore) {
    // A sphere has no edge sharper than 60 degrees: the same result with or without.
    const Mesh m0 = test::make_sphere(Vec3f(0, 0, 0), 1.0f, 3);
    SmoothOptions o;
    o.iterations = 5;
    const Mesh a = smooth_mesh(m0, o).value;
    o.crease_angle_deg = 60;
    const Mesh b = smooth_mesh(m0, o).value;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t v = 0; v < a.positions.size(); ++v) EXPECT_EQ(length(a.positions[v] - b.positions[v]), 0.0f);
}

TEST(SmoothCreases, ShortCreasesOfACarvedSurfaceAreSmoothedLongEdgesHeld) {
    // A cube whose top side has four bumps two steps high and two cells wide, as a hull carved
    // on a grid from many cameras has: each bump's sharp edges are a crease reaching about five
    // edge lengths; the cube's edges reach the whole cube (about eighteen).
    Mesh m0 = test::make_grid_box(-1.0f, 1.0f, 12);
    const float step = 2.0f / 12;
    std::vector<std::size_t> bumps;
    for (std::size_t v = 0; v < m0.positions.size(); ++v) {
        const Vec3f p = m0.positions[v];
        const int i = int(std::lround((p.x + 1) / step)), j = int(std::lround((p.z + 1) / step));
        const auto in_bump = [](int k) { return std::abs(k - 3) <= 1 || std::abs(k - 9) <= 1; };
        if (p.y > 1 - 1e-4f && in_bump(i) && in_bump(j)) {
            m0.positions[v].y += 2 * step;
            bumps.push_back(v);
        }
    }
    ASSERT_EQ(bumps.size(), 36u);
    // The cube's edge vertices (two coordinates at -1 or 1) stay on their edge line.
    const auto edges_moved = [&](const Mesh& m) {
        double worst = 0;
        for (std::size_t v = 0; v < m.positions.size(); ++v) {
            const Vec3f &p = m0.positions[v], &q = m.positions[v];
            const float t0[3] = {p.x, p.y, p.z}, t1[3] = {q.x, q.y, q.z};
            int on = 0;
            for (float t : t0) on += std::fabs(std::fabs(t) - 1) < 1e-5f;
            if (on < 2) continue;
            for (int k = 0; k < 3; ++k)
                if (std::fabs(std::fabs(t0[k]) - 1) < 1e-5f) worst = std::max(worst, double(std::fabs(t1[k] - t0[k])));
        }
        return worst;
    };
    // How far the bumps came down, on average.
    const auto bump_drop = [&](const Mesh& m) {
        double sum = 0;
        for (auto v : bumps) sum += double(m0.positions[v].y - m.positions[v].y);
        return sum / double(bumps.size());
    };
    SmoothOptions o;
    o.iterations = 10;
    const double paper = bump_drop(smooth_mesh(m0, o).value);
    o.crease_angle_deg = 60;
    const auto all = smooth_mesh(m0, o);
    o.crease_reach = 10;
    const auto long_only = smooth_mesh(m0, o);
    EXPECT_GT(paper, 0.2 * step) << "the paper's smoothing lowers the bumps";
    EXPECT_LT(bump_drop(all.value), 0.5 * paper) << "every crease held: the bumps' edges are held";
    EXPECT_GT(bump_drop(long_only.value), 0.8 * paper) << "the bumps' short creases are smoothed as before";
    EXPECT_LT(edges_moved(all.value), 1e-5);
    EXPECT_LT(edges_moved(long_only.value), 1e-5) << "the cube's edges are held";
    EXPECT_EQ(long_only.stats.short_creases, 4u);
    EXPECT_EQ(all.stats.short_creases, 0u);
}
