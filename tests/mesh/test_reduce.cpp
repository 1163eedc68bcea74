#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/mesh.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"
#include "mesh_decimate.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

namespace {

void expect_closed_manifold(const Mesh& m, const char* what) {
    const MeshCheck c = check_mesh(m);
    EXPECT_TRUE(c.closed_manifold()) << what << ": boundary " << c.boundary_edges << ", non-manifold edges "
                                     << c.nonmanifold_edges << ", vertices " << c.nonmanifold_vertices
                                     << ", inconsistent " << c.inconsistent_edges;
    EXPECT_EQ(c.degenerate_faces, 0u) << what;
    EXPECT_GT(c.signed_volume, 0) << what;
}

// Total length of mesh edges lying on each of the 12 edges of the cube [-1, 1]^3.
std::map<int, double> cube_edge_coverage(const Mesh& m) {
    auto on = [](float x) { return std::fabs(std::fabs(x) - 1.0f) < 1e-6f; };
    std::map<int, double> len;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (a > b) continue; // each undirected edge once (closed mesh: both directions exist)
            const Vec3f p = m.positions[a], q = m.positions[b];
            for (int axis = 0; axis < 3; ++axis) {
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                if (on(p[u]) && on(p[v]) && on(q[u]) && on(q[v]) && p[u] == q[u] && p[v] == q[v]) {
                    const int id = axis * 4 + (p[u] > 0) * 2 + (p[v] > 0);
                    len[id] += std::fabs(double(q[axis]) - double(p[axis]));
                }
            }
        }
    return len;
}

} // namespace

TEST(Reduce, CubeKeepsCornersAndSharpEdgesAt30Degrees) {
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 16);
    ASSERT_EQ(m.face_count(), 12u * 16 * 16);
    ReduceOptions o;
    o.max_angle_deg = 30;
    const DecimateStats st = reduce_mesh(m, o);
    expect_closed_manifold(m, "reduced cube");
    EXPECT_EQ(st.faces_after, m.face_count());
    EXPECT_LT(m.face_count(), st.faces_before / 6) << "flat faces should lose most triangles";
    // The 8 corners are still there.
    int corners = 0;
    for (const auto& p : m.positions)
        corners += std::fabs(std::fabs(p.x) - 1) < 1e-6f && std::fabs(std::fabs(p.y) - 1) < 1e-6f &&
                   std::fabs(std::fabs(p.z) - 1) < 1e-6f;
    EXPECT_EQ(corners, 8);
    // Every vertex stays on the cube and the 12 edges stay covered end to end.
    for (const auto& p : m.positions)
        EXPECT_NEAR(std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}), 1.0f, 1e-6f);
    const auto cover = cube_edge_coverage(m);
    ASSERT_EQ(cover.size(), 12u);
    for (const auto& [id, l] : cover) EXPECT_NEAR(l, 2.0, 1e-5) << "cube edge " << id;
    EXPECT_NEAR(check_mesh(m).signed_volume, 8.0, 1e-4);
}

TEST(Reduce, MeetsTargetFaces) {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 5);
    ReduceOptions o;
    o.max_angle_deg = 40;
    o.target_faces = 2000;
    const DecimateStats st = reduce_mesh(m, o);
    expect_closed_manifold(m, "reduced sphere");
    EXPECT_LE(m.face_count(), 2000u);
    EXPECT_GE(m.face_count(), 1990u);
    EXPECT_EQ(st.faces_before, 20480u);
    // Still a sphere: every vertex is an original one, so on the sphere; the volume stays close.
    EXPECT_NEAR(check_mesh(m).signed_volume, 4.0 / 3.0 * 3.14159265, 0.05);
}

TEST(Reduce, SmallAngleStopsEarlierThanLargeAngle) {
    const Mesh m0 = test::make_sphere({0, 0, 0}, 1.0f, 5);
    std::size_t prev = m0.face_count() + 1;
    for (double angle : {5.0, 15.0, 40.0}) {
        Mesh m = m0;
        ReduceOptions o;
        o.max_angle_deg = angle;
        reduce_mesh(m, o);
        expect_closed_manifold(m, "sphere");
        EXPECT_LT(m.face_count(), prev) << angle;
        prev = m.face_count();
    }
}

TEST(Reduce, BoundaryVerticesStay) {
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 8);
    // Open the cube: drop the +Z side (its triangles have all z == 1).
    std::vector<std::array<std::uint32_t, 3>> kept;
    for (const auto& t : m.triangles)
        if (!(m.positions[t[0]].z == 1 && m.positions[t[1]].z == 1 && m.positions[t[2]].z == 1)) kept.push_back(t);
    m.triangles = kept;
    const std::size_t boundary = check_mesh(m).boundary_edges;
    ASSERT_EQ(boundary, 32u);
    ReduceOptions o;
    o.max_angle_deg = 30;
    const DecimateStats st = reduce_mesh(m, o);
    EXPECT_EQ(st.locked_vertices, 32u);
    const MeshCheck c = check_mesh(m);
    EXPECT_EQ(c.boundary_edges, boundary);
    EXPECT_EQ(c.nonmanifold_edges + c.nonmanifold_vertices + c.inconsistent_edges, 0u);
    EXPECT_LT(m.face_count(), kept.size());
}

TEST(Reduce, RealModelsStayClosedAndManifold) {
    CM_SKIP_WITHOUT(test::shared_dir() / "data/models");
    for (const char* name : {"bunny00.off", "fandisk.off", "bob_tri.obj"}) {
        SCOPED_TRACE(name);
        Mesh m = read_mesh(test::shared_dir() / "data/models" / name);
        const std::size_t before = m.face_count();
        const MeshCheck c0 = check_mesh(m);
        ReduceOptions o;
        o.max_angle_deg = 25;
        o.target_faces = before / 10;
        reduce_mesh(m, o);
        const MeshCheck c = check_mesh(m);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_EQ(c.euler, c0.euler) << "genus must not change";
        EXPECT_LT(m.face_count(), before / 2);
        EXPECT_EQ(count_self_intersections(m), 0u);
    }
}

TEST(QuadricDecimate, SphereToATenthStaysRoundAndManifold) {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 5);
    QuadricOptions o;
    o.target_faces = 2048;
    const DecimateStats st = quadric_decimate(m, o);
    expect_closed_manifold(m, "quadric sphere");
    EXPECT_LE(m.face_count(), 2048u);
    EXPECT_GE(m.face_count(), 2040u);
    EXPECT_GT(st.max_error, 0.0);
    EXPECT_LT(st.max_error, 0.05);
    EXPECT_NEAR(check_mesh(m).signed_volume, 4.0 / 3.0 * 3.14159265, 0.06);
}

TEST(QuadricDecimate, CubeCollapsesToFlatFacesExactly) {
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 16);
    QuadricOptions o;
    o.max_error = 1e-6;
    quadric_decimate(m, o);
    expect_closed_manifold(m, "quadric cube");
    EXPECT_NEAR(check_mesh(m).signed_volume, 8.0, 1e-4);
    EXPECT_LT(m.face_count(), 200u);
    const auto cover = cube_edge_coverage(m);
    ASSERT_EQ(cover.size(), 12u);
}

TEST(QuadricDecimate, RealModelsStayClosedAndManifold) {
    CM_SKIP_WITHOUT(test::shared_dir() / "data/models");
    for (const char* name : {"armadillo.off", "fertility.off"}) {
        SCOPED_TRACE(name);
        Mesh m = read_mesh(test::shared_dir() / "data/models" / name);
        const MeshCheck c0 = check_mesh(m);
        QuadricOptions o;
        o.target_faces = m.face_count() / 10;
        quadric_decimate(m, o);
        const MeshCheck c = check_mesh(m);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_EQ(c.euler, c0.euler);
        EXPECT_LE(m.face_count(), o.target_faces);
    }
}

TEST(SelfIntersections, FoundBetweenTwoCrossingBoxesAndNotInOne) {
    Mesh a = test::make_box({0, 0, 0}, {1, 1, 1});
    EXPECT_EQ(count_self_intersections(a), 0u);
    EXPECT_EQ(count_self_intersections(test::make_sphere({0, 0, 0}, 1.0f, 3)), 0u);
    EXPECT_GT(count_self_intersections(test::make_crossing_boxes()), 0u);
}

namespace {

// A hollow ball: a sphere and, inside it, a small sphere (its surface turned inwards)
// that almost touches the shell at one place. Coarsening either surface there makes
// them cross unless the reduction keeps that region.
Mesh ball_with_near_inner_part() {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 4);
    test::append_mesh(m, test::make_sphere({0.0f, 0.0f, 0.594f}, 0.4f, 4), true);
    return m;
}

} // namespace

TEST(CrossingGuard, ReductionsLeaveNearPartsUncrossed) {
    const Mesh input = ball_with_near_inner_part();
    ASSERT_EQ(count_self_intersections(input), 0u);
    for (const bool quadric : {false, true}) {
        SCOPED_TRACE(quadric ? "quadric" : "reduce");
        auto run = [&](bool guard, DecimateStats& st) {
            Mesh m = input;
            if (quadric) {
                QuadricOptions o;
                o.target_faces = input.face_count() / 100;
                o.no_crossings = guard;
                st = quadric_decimate(m, o);
            } else {
                ReduceOptions o;
                o.max_angle_deg = 30;
                o.no_crossings = guard;
                st = reduce_mesh(m, o);
            }
            return m;
        };
        DecimateStats plain_st, guarded_st;
        const Mesh plain = run(false, plain_st);
        const Mesh guarded = run(true, guarded_st);
        ASSERT_GT(count_self_intersections(plain), 0u) << "the case should make the parts cross without the guard";
        EXPECT_EQ(count_self_intersections(guarded), 0u);
        EXPECT_GT(guarded_st.restarts, 0u);
        EXPECT_GT(guarded_st.frozen_vertices, 0u);
        EXPECT_EQ(guarded_st.crossings_left, 0u);
        EXPECT_TRUE(check_mesh(guarded).closed_manifold());
        // Only the region of the contact is kept (at a hundredth of the faces the coarse
        // faces are large, so the region is too).
        EXPECT_LT(double(guarded_st.frozen_vertices), 0.25 * double(input.vertex_count()))
            << guarded_st.restarts << " restarts";
    }
}
