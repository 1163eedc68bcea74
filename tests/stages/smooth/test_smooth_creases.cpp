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
