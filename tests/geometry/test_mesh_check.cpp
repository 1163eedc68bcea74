#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

TEST(MeshCheck, BoxIsClosedOutwardManifold) {
    const Mesh m = test::make_box({0, 0, 0}, {1, 2, 3});
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(c.degenerate_faces, 0u);
    EXPECT_EQ(c.components, 1u);
    EXPECT_EQ(c.euler, 2);
    EXPECT_NEAR(c.signed_volume, 6.0, 1e-9);
    EXPECT_NEAR(c.area, 2 * (2 + 3 + 6), 1e-9);
}

TEST(MeshCheck, DetectsHolesFlipsAndNonManifoldEdges) {
    Mesh m = test::make_box({0, 0, 0}, {1, 1, 1});
    Mesh hole = m;
    hole.triangles.pop_back();
    EXPECT_EQ(check_mesh(hole).boundary_edges, 3u);
    Mesh flipped = m;
    std::swap(flipped.triangles[0][0], flipped.triangles[0][1]);
    EXPECT_GT(check_mesh(flipped).inconsistent_edges, 0u);
    Mesh fin = m;
    fin.positions.push_back({5, 5, 5});
    fin.triangles.push_back({0, 1, 8}); // a third face on edge 0-1
    EXPECT_GT(check_mesh(fin).nonmanifold_edges, 0u);
    Mesh inside_out = m;
    for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
    EXPECT_LT(check_mesh(inside_out).signed_volume, 0);
}

TEST(MeshCheck, DetectsBowtieVertex) {
    // Two boxes sharing one corner vertex: edges are fine, the vertex is not.
    Mesh a = test::make_box({0, 0, 0}, {1, 1, 1});
    Mesh b = test::make_box({1, 1, 1}, {2, 2, 2});
    const std::uint32_t off = std::uint32_t(a.positions.size());
    for (auto p : b.positions) a.positions.push_back(p);
    for (auto t : b.triangles) {
        for (auto& i : t) i = (i == 0) ? 7 : i + off; // b's corner 0 is a's corner 7
        a.triangles.push_back(t);
    }
    EXPECT_EQ(check_mesh(a).nonmanifold_vertices, 1u);
}

namespace {

// A closed double cone with `sides` faces around each apex (vertices 0 and 1).
Mesh double_cone(int sides, Vec3f centre) {
    Mesh m;
    m.positions.push_back(centre + Vec3f{0, 1, 0});
    m.positions.push_back(centre + Vec3f{0, -1, 0});
    for (int i = 0; i < sides; ++i) {
        const float a = 6.2831853f * float(i) / float(sides);
        m.positions.push_back(centre + Vec3f{std::cos(a), 0, -std::sin(a)});
    }
    for (int i = 0; i < sides; ++i) {
        const std::uint32_t r0 = std::uint32_t(2 + i), r1 = std::uint32_t(2 + (i + 1) % sides);
        m.triangles.push_back({0, r0, r1});
        m.triangles.push_back({1, r1, r0});
    }
    return m;
}

} // namespace

// Fans of more faces than the check's small path takes, and faces with a repeated index.
TEST(MeshCheck, LargeFansAndRepeatedIndices) {
    for (int sides : {5, 40}) {
        SCOPED_TRACE(sides);
        const Mesh one = double_cone(sides, {0, 0, 0});
        MeshCheck c = check_mesh(one);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_EQ(c.euler, 2);
        EXPECT_EQ(c.components, 1u);
        EXPECT_GT(c.signed_volume, 0);
        // Two cones sharing one apex: the apex's faces form two fans.
        Mesh two = one;
        const Mesh other = double_cone(sides, {0, 2, 0});
        const std::uint32_t off = std::uint32_t(two.positions.size());
        for (auto p : other.positions) two.positions.push_back(p);
        for (auto t : other.triangles) {
            for (auto& i : t) i = i == 1 ? 0 : i + off; // its lower apex is the first cone's upper one
            two.triangles.push_back(t);
        }
        c = check_mesh(two);
        EXPECT_EQ(c.nonmanifold_vertices, 1u);
        EXPECT_EQ(c.boundary_edges + c.nonmanifold_edges + c.inconsistent_edges, 0u);
        EXPECT_EQ(c.components, 1u);
        // A face with a repeated index is degenerate and adds no edge.
        Mesh bad = one;
        bad.triangles.push_back({2, 2, 3});
        c = check_mesh(bad);
        EXPECT_EQ(c.degenerate_faces, 1u);
        EXPECT_TRUE(c.closed_manifold());
    }
}

// Large meshes are checked in chunks of faces side by side, with one union-find for the
// components: the counts are those of the mesh, however its faces fall in the chunks.
TEST(MeshCheck, LargeMeshInChunksCountsComponentsHolesAndDegenerateFaces) {
    Mesh m;
    for (int i = 0; i < 4; ++i) { // four spheres apart
        const Mesh s = test::make_sphere({3.0f * float(i), 0, 0}, 1.0f, 5);
        const auto base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), s.positions.begin(), s.positions.end());
        for (auto t : s.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    ASSERT_GT(m.face_count(), 65536u);
    m.triangles.erase(m.triangles.begin() + 10); // a hole of three edges in the first sphere
    m.triangles.push_back({0, 0, 1});            // and a face naming a vertex twice
    std::mt19937 rng(11);                        // the spheres' faces mixed over every chunk
    std::shuffle(m.triangles.begin(), m.triangles.end(), rng);
    const MeshCheck c = check_mesh(m);
    EXPECT_EQ(c.components, 4u);
    EXPECT_EQ(c.boundary_edges, 3u);
    EXPECT_EQ(c.nonmanifold_edges, 0u);
    EXPECT_EQ(c.inconsistent_edges, 0u);
    EXPECT_EQ(c.degenerate_faces, 1u);
    EXPECT_EQ(c.euler, 4 * 2 - 1); // four spheres, one face fewer
    const double sphere = 4.0 / 3.0 * 3.14159265358979;
    EXPECT_NEAR(c.signed_volume, 4 * sphere, 0.01 * 4 * sphere);
}
