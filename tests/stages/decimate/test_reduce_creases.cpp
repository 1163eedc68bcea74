// mesh.reduce's straight creases (crease_straightness): a vertex in the middle of a straight
// crease goes along it and the crease stays; a bent crease keeps its vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <vector>

#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "mesh_decimate.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

// Vertices on the cube's 12 edges (two coordinates at +-1), its 8 corners left out.
int cube_edge_vertices(const Mesh& m) {
    int n = 0;
    for (const auto& p : m.positions) {
        const int at = int(std::fabs(std::fabs(p.x) - 1) < 1e-6f) + int(std::fabs(std::fabs(p.y) - 1) < 1e-6f) +
                       int(std::fabs(std::fabs(p.z) - 1) < 1e-6f);
        n += at == 2;
    }
    return n;
}

} // namespace

TEST(Reduce, StraightCreasesGoAlongThemselvesWhenAsked) {
    const Mesh m0 = test::make_grid_box(-1.0f, 1.0f, 16);
    ASSERT_EQ(cube_edge_vertices(m0), 12 * 15);
    ReduceOptions o;
    o.max_angle_deg = 30;
    Mesh paper = m0;
    reduce_mesh_in_place(paper, o);
    EXPECT_EQ(cube_edge_vertices(paper), 12 * 15) << "the paper's test keeps every vertex of a crease";
    o.crease_straightness_deg = 2;
    Mesh m = m0;
    const DecimateStats st = reduce_mesh_in_place(m, o);
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(c.degenerate_faces, 0u);
    EXPECT_EQ(st.faces_after, m.face_count());
    EXPECT_LT(cube_edge_vertices(m), 12 * 15 / 3) << "most crease vertices go";
    EXPECT_LT(m.face_count(), paper.face_count());
    // The shape is the cube's all the same: corners, edges end to end, every vertex on it.
    int corners = 0;
    for (const auto& p : m.positions) {
        corners += std::fabs(std::fabs(p.x) - 1) < 1e-6f && std::fabs(std::fabs(p.y) - 1) < 1e-6f &&
                   std::fabs(std::fabs(p.z) - 1) < 1e-6f;
        EXPECT_NEAR(std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}), 1.0f, 1e-6f);
    }
    EXPECT_EQ(corners, 8);
    EXPECT_NEAR(c.signed_volume, 8.0, 1e-4);
}

TEST(Reduce, BentCreasesKeepTheirVertices) {
    // The top face bowed (z = 1 + 0.1 x^2 at its edges): its two creases along x turn by about
    // 1.4 degrees at each vertex, more than the 1 degree asked; the others stay straight.
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 16);
    auto on_bent = [](const Vec3f& p) {
        return std::fabs(std::fabs(p.y) - 1) < 1e-6f && std::fabs(p.z - (1 + 0.1f * p.x * p.x)) < 1e-6f &&
               std::fabs(std::fabs(p.x) - 1) > 1e-6f;
    };
    for (auto& p : m.positions)
        if (p.z > 1 - 1e-6f) p.z = 1 + 0.1f * p.x * p.x;
    int before = 0;
    for (const auto& p : m.positions) before += on_bent(p);
    ASSERT_EQ(before, 2 * 15);
    ReduceOptions o;
    o.max_angle_deg = 30;
    o.crease_straightness_deg = 1;
    reduce_mesh_in_place(m, o);
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(c.degenerate_faces, 0u);
    int after = 0;
    for (const auto& p : m.positions) after += on_bent(p);
    EXPECT_EQ(after, before);
}

namespace {

Vec3d face_normal_of(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
    const Vec3d p0(m.positions[t[0]]), p1(m.positions[t[1]]), p2(m.positions[t[2]]);
    return cross(p1 - p0, p2 - p0);
}

// The share of `m`'s area whose face normal is further than `deg` from every face normal `of` had.
double tilted_pct(const Mesh& m, const Mesh& of, double deg) {
    const double c = std::cos(deg * 3.14159265358979 / 180.0);
    std::vector<Vec3d> known;
    for (const auto& t : of.triangles) {
        const Vec3d n = normalize(face_normal_of(of, t));
        if (std::none_of(known.begin(), known.end(), [&](const Vec3d& k) { return dot(k, n) > 1 - 1e-9; }))
            known.push_back(n);
    }
    double tilted = 0, all = 0;
    for (const auto& t : m.triangles) {
        const Vec3d n = face_normal_of(m, t);
        const double len = length(n);
        all += len;
        if (std::none_of(known.begin(), known.end(), [&](const Vec3d& k) { return dot(k, n) >= c * len; }))
            tilted += len;
    }
    return 100.0 * tilted / all;
}

} // namespace

TEST(Reduce, KeepPlanesKeepsFacesInTheirPlanesBesideARoundedCrease) {
    // The cube's four edges around its top rounded a little (their vertices pulled 0.02 in
    // along both sides' normals): the faces beside them lean about 9 degrees, less than the
    // 20 asked, so the vertices beside the crease are candidates, and the paper's collapse of
    // one of them turns faces to normals between the top's and the lean's.
    Mesh m0 = test::make_grid_box(-1.0f, 1.0f, 16);
    for (auto& p : m0.positions)
        if (p.z > 1 - 1e-6f) {
            if (std::fabs(std::fabs(p.x) - 1) < 1e-6f) p.x *= 0.98f, p.z = 0.98f;
            if (std::fabs(std::fabs(p.y) - 1) < 1e-6f) p.y *= 0.98f, p.z = 0.98f;
        }
    ReduceOptions o;
    o.max_angle_deg = 20;
    Mesh paper = m0;
    reduce_mesh_in_place(paper, o);
    o.keep_planes_deg = 1;
    Mesh m = m0;
    reduce_mesh_in_place(m, o);
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed_manifold());
    EXPECT_EQ(c.degenerate_faces, 0u);
    std::cout << "area turned more than 2 deg from every input normal: paper " << tilted_pct(paper, m0, 2.0)
              << " %, keep_planes 1 " << tilted_pct(m, m0, 2.0) << " %; faces " << paper.face_count() << ", "
              << m.face_count() << " of " << m0.face_count() << "\n";
    EXPECT_GT(tilted_pct(paper, m0, 2.0), 1.0) << "the paper's collapses tilt faces";
    EXPECT_LT(tilted_pct(m, m0, 2.0), 0.1) << "with keep_planes they keep their planes";
    EXPECT_LT(m.face_count(), m0.face_count() / 2) << "and the flat sides are still reduced";
}
