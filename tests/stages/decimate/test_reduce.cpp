#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"
#include "mesh_decimate.h"
#include "metrics/silhouette_error.h"
#include "outline_guard.h"
#include "render/raster.h"
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

// How far the outline of `m` strays from a sphere of radius 1 at the origin drawn in
// `view` (scale px per unit, centred): the deepest pixel of the drawing the mesh leaves
// uncovered, and the farthest pixel outside it that the mesh covers, in pixels.
void outline_strays(const Mesh& m, const View& view, double& missed_px, double& extra_px) {
    const Camera& cam = view.camera;
    const std::vector<std::uint8_t> mask = render_mask(m, cam, view.width, view.height);
    missed_px = extra_px = 0;
    for (int j = 0; j < view.height; ++j)
        for (int i = 0; i < view.width; ++i) {
            const double a = (i + 0.5 - cam.cx) / cam.scale, b = (cam.cy - (j + 0.5)) / cam.scale;
            const double inside_px = (1.0 - std::hypot(a, b)) * cam.scale;
            const bool covered = mask[std::size_t(j) * view.width + i] != 0;
            if (!covered && inside_px > 0) missed_px = std::max(missed_px, inside_px);
            if (covered && inside_px < 0) extra_px = std::max(extra_px, -inside_px);
        }
}

} // namespace

TEST(Reduce, CubeKeepsCornersAndSharpEdgesAt30Degrees) {
    Mesh m = test::make_grid_box(-1.0f, 1.0f, 16);
    ASSERT_EQ(m.face_count(), 12u * 16 * 16);
    ReduceOptions o;
    o.max_angle_deg = 30;
    const DecimateStats st = reduce_mesh_in_place(m, o);
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
    const DecimateStats st = reduce_mesh_in_place(m, o);
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
        reduce_mesh_in_place(m, o);
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
    const DecimateStats st = reduce_mesh_in_place(m, o);
    EXPECT_EQ(st.locked_vertices, 32u);
    const MeshCheck c = check_mesh(m);
    EXPECT_EQ(c.boundary_edges, boundary);
    EXPECT_EQ(c.nonmanifold_edges + c.nonmanifold_vertices + c.inconsistent_edges, 0u);
    EXPECT_LT(m.face_count(), kept.size());
}

// Above a quarter of a million faces the reduction runs in spatial blocks (in parallel),
// then once over the whole mesh: the result must be as clean as one queue's, keep what a
// single queue keeps (corners, sharp edges, attributes of the surviving vertices) and be
// the same from run to run.
TEST(Reduce, LargeMeshInBlocksIsCleanKeepsEdgesAndAttributesAndRepeats) {
    Mesh m0 = test::make_grid_box(-1.0f, 1.0f, 150);
    ASSERT_GT(m0.face_count(), 262144u);
    for (const auto& p : m0.positions) m0.uvs.push_back({0.25f * p.x + 0.5f, 0.25f * p.y + 0.5f * p.z});
    ReduceOptions o;
    o.max_angle_deg = 30;
    Mesh m = m0;
    const DecimateStats st = reduce_mesh_in_place(m, o);
    expect_closed_manifold(m, "blocks");
    EXPECT_EQ(check_mesh(m).euler, 2);
    EXPECT_EQ(st.faces_before, m0.face_count());
    EXPECT_EQ(st.faces_after, m.face_count());
    EXPECT_EQ(st.locked_vertices, 0u);
    EXPECT_EQ(st.collapses, (m0.face_count() - m.face_count()) / 2) << "each collapse removes two faces";
    // One queue over the whole mesh (a face target never reached runs it until no vertex can
    // go, as without a target): the same result but for the order near block borders.
    Mesh one = m0;
    ReduceOptions single = o;
    single.target_faces = 1;
    reduce_mesh_in_place(one, single);
    EXPECT_NEAR(double(m.face_count()), double(one.face_count()), 0.01 * double(one.face_count()));
    EXPECT_LT(m.face_count(), 12u * 150 * 2 + 400) << "the sides go down to the faces their sharp edges need";
    EXPECT_EQ(count_self_intersections(m), 0u);
    // The 12 cube edges stay covered over their whole length; the 8 corners stay.
    const auto cov = cube_edge_coverage(m);
    ASSERT_EQ(cov.size(), 12u);
    for (const auto& [id, len] : cov) EXPECT_NEAR(len, 2.0, 1e-5) << "edge " << id;
    int corners = 0;
    for (const auto& p : m.positions) corners += std::fabs(p.x) == 1 && std::fabs(p.y) == 1 && std::fabs(p.z) == 1;
    EXPECT_EQ(corners, 8);
    // Surviving vertices keep their position and their own attributes.
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3f p = m.positions[v];
        ASSERT_FLOAT_EQ(m.uvs[v][0], 0.25f * p.x + 0.5f) << v;
        ASSERT_FLOAT_EQ(m.uvs[v][1], 0.25f * p.y + 0.5f * p.z) << v;
    }
    Mesh again = m0;
    reduce_mesh_in_place(again, o);
    EXPECT_EQ(again.triangles, m.triangles) << "the blocks run in parallel; the result must not depend on it";
    EXPECT_EQ(again.positions, m.positions);
}

TEST(Reduce, LargeSphereInBlocksStaysRound) {
    Mesh m = test::make_sphere({0, 0, 0}, 1.0f, 7);
    ASSERT_GT(m.face_count(), 262144u);
    ReduceOptions o;
    o.max_angle_deg = 10;
    const DecimateStats st = reduce_mesh_in_place(m, o);
    expect_closed_manifold(m, "sphere");
    EXPECT_EQ(check_mesh(m).euler, 2);
    EXPECT_EQ(count_self_intersections(m), 0u);
    EXPECT_EQ(st.crossings_left, 0u);
    Mesh one = test::make_sphere({0, 0, 0}, 1.0f, 7);
    ReduceOptions single = o;
    single.target_faces = 1; // never reached: one queue until no vertex can go
    reduce_mesh_in_place(one, single);
    // (1438 against 1470 faces when written: a few percent of a result 200 times smaller than the input)
    EXPECT_NEAR(double(m.face_count()), double(one.face_count()), 0.03 * double(one.face_count()));
    EXPECT_LT(m.face_count(), 40000u);
    EXPECT_GT(m.face_count(), 200u);
    // Enclosed volume within 2 % of the sphere's (vertices stay on it; the faces cut inside).
    EXPECT_NEAR(check_mesh(m).signed_volume, 4.0 / 3.0 * 3.14159265358979, 0.02 * 4.19);
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
        reduce_mesh_in_place(m, o);
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
    const QuadricStats st = quadric_decimate_in_place(m, o);
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
    quadric_decimate_in_place(m, o);
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
        quadric_decimate_in_place(m, o);
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
                st = quadric_decimate_in_place(m, o);
            } else {
                ReduceOptions o;
                o.max_angle_deg = 30;
                o.no_crossings = guard;
                st = reduce_mesh_in_place(m, o);
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

// With the views (constrain: silhouette), no collapse may move the outline more than the
// tolerance away from the drawing: on a fine sphere drawn from three sides, the paper's
// rule alone cuts the rim's chords pixels deep; guarded, every view's outline stays
// within the tolerance (plus the pixel-centre sampling of the check), and the reduction
// still removes most faces.
TEST(Reduce, OutlineGuardKeepsTheDrawnSilhouette) {
    const Mesh m0 = test::make_sphere({0, 0, 0}, 1.0f, 5);
    std::vector<View> drawn;
    for (const char* name : {"front", "right", "top"})
        drawn.push_back(test::ortho_view(name, 512, 200.0, test::sphere_outline(1.0)));
    const auto views = test::make_views(std::move(drawn), {-1, -1, -1}, {1, 1, 1});
    const double tolerance_px = 1.0;

    auto reduce = [&](const OutlineGuard* guard, double& missed, double& extra) {
        Mesh m = m0;
        ReduceOptions o;
        o.max_angle_deg = 20;
        o.outline = guard;
        reduce_mesh_in_place(m, o);
        expect_closed_manifold(m, guard ? "guarded" : "unguarded");
        missed = extra = 0;
        for (const View& v : views->views) {
            double mi, ex;
            outline_strays(m, v, mi, ex);
            missed = std::max(missed, mi);
            extra = std::max(extra, ex);
        }
        return m.face_count();
    };
    double missed_free, extra_free, missed, extra;
    const std::size_t free_faces = reduce(nullptr, missed_free, extra_free);
    const OutlineGuard guard(*views, tolerance_px);
    const std::size_t faces = reduce(&guard, missed, extra);
    EXPECT_GT(missed_free, 2 * tolerance_px + 1) << "the unguarded reduction should cut into the outline";
    EXPECT_LE(missed, tolerance_px + 0.75);
    EXPECT_LE(extra, tolerance_px + 0.75);
    EXPECT_LT(faces, m0.face_count() / 4);
    EXPECT_GE(faces, free_faces);
    std::printf(
        "faces %zu -> %zu unguarded (missed %.2f px, extra %.2f px), %zu guarded (missed %.2f px, extra %.2f px)\n",
        m0.face_count(), free_faces, missed_free, extra_free, faces, missed, extra);
}

// Calibrated perspective views (photographs) go through the same guard: the sphere seen by
// four cameras about 6 radii away keeps a lower silhouette error than the unguarded run.
TEST(Reduce, OutlineGuardWorksThroughPerspectiveViews) {
    const Mesh m0 = test::make_sphere({0, 0, 0}, 1.0f, 5);
    Views views;
    views.views = test::perspective_sphere_ring({0, 0, 0}, 1.0, 600.0);
    views.calibrated = true;
    auto reduce = [&](const OutlineGuard* guard) {
        Mesh m = m0;
        ReduceOptions o;
        o.max_angle_deg = 20;
        o.outline = guard;
        reduce_mesh_in_place(m, o);
        expect_closed_manifold(m, guard ? "guarded" : "unguarded");
        EXPECT_LT(m.face_count(), m0.face_count() / 4);
        return silhouette_error(m, views).xor_pct;
    };
    const double free_error = reduce(nullptr);
    const OutlineGuard guard(views, 1.0);
    const double error = reduce(&guard);
    EXPECT_LT(error, 0.75 * free_error);
    std::printf("xor_pct %.3f unguarded, %.3f guarded\n", free_error, error);
}

// The outline guard's shortcut: where it says a collapse leaves a view's coverage as it is,
// the faces around the vertex and the faces replacing them cover the same pixel centres. Fans
// of random rings around a point, some folded over (a ring out of angular order, the vertex
// outside its ring), and stars (a ring winding twice around its vertex), each collapsed into
// each of its neighbours.
TEST(OutlineGuard, SameCoverHoldsOnlyWhereTheCoverIsTheSame) {
    using decimate::ImagePoint;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto covers = [](const ImagePoint& a, const ImagePoint& b, const ImagePoint& c, double x, double y) {
        auto side = [&](const ImagePoint& p, const ImagePoint& q) {
            return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
        };
        const double d0 = side(a, b), d1 = side(b, c), d2 = side(c, a);
        return (d0 > 0 && d1 > 0 && d2 > 0) || (d0 < 0 && d1 < 0 && d2 < 0);
    };
    int said_same = 0, said_not = 0, differ_when_not = 0, stars_same = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const bool star = trial % 5 == 1, folded = trial % 3 == 0;
        const int nr = star ? 5 + 2 * int(unit(rng) * 2) : 3 + int(unit(rng) * 6);
        ImagePoint ring[16];
        for (int i = 0; i < nr; ++i) {
            // A star of 5 or 7 points steps 2 of them at a time: twice around.
            double angle = 2 * 3.14159265358979 * ((star ? 2 * i : i) + 0.3 * unit(rng)) / nr;
            if (folded && i == 1) angle += 3.0 * unit(rng); // out of order: the fan may fold over
            const double radius = 2.0 + 6.0 * unit(rng);
            ring[i] = {100 + radius * std::cos(angle), 100 + radius * std::sin(angle)};
        }
        // The vertex near the middle, or (sometimes) out beyond its ring.
        const ImagePoint pv = trial % 7 == 0 ? ImagePoint{100 + 9 * unit(rng), 100 - 9 * unit(rng)}
                                             : ImagePoint{100 + unit(rng) - 0.5, 100 + unit(rng) - 0.5};
        int next[16];
        double reach2 = 0;
        for (int i = 0; i < nr; ++i) {
            next[i] = (i + 1) % nr;
            reach2 =
                std::max(reach2, (ring[i].x - pv.x) * (ring[i].x - pv.x) + (ring[i].y - pv.y) * (ring[i].y - pv.y));
        }
        for (int w = 0; w < nr; ++w) {
            std::array<int, 3> tris[16];
            int nt = 0;
            for (int i = 0; i < nr; ++i)
                if (i != w && next[i] != w) tris[nt++] = {w, i, next[i]};
            const bool same = decimate::same_cover(pv, ring, next, nr, tris, nt, reach2);
            (same ? said_same : said_not) += 1;
            stars_same += star && same;
            // Both covers over a grid of points 0.125 px apart around the ring.
            bool differ = false;
            for (double y = 90.0625; y < 110 && !(differ && !same); y += 0.125)
                for (double x = 90.0625; x < 110; x += 0.125) {
                    bool before = false, after = false;
                    for (int i = 0; i < nr; ++i) before |= covers(pv, ring[i], ring[next[i]], x, y);
                    for (int i = 0; i < nt; ++i)
                        after |= covers(ring[tris[i][0]], ring[tris[i][1]], ring[tris[i][2]], x, y);
                    if (before != after) {
                        differ = true;
                        if (same)
                            ADD_FAILURE() << "trial " << trial << ", collapse into " << w
                                          << ": said the same, differs at (" << x << ", " << y << ")";
                        break;
                    }
                }
            differ_when_not += !same && differ;
        }
    }
    // Both answers come up, and the cover does change in some of the cases the shortcut leaves
    // to the full test.
    EXPECT_GT(said_same, 200);
    EXPECT_GT(said_not, 100);
    EXPECT_GT(differ_when_not, 50);
    EXPECT_GT(stars_same, 5);
    std::printf("same cover %d (stars %d), not shown %d (of which %d change the cover)\n", said_same, stars_same,
                said_not, differ_when_not);
}
