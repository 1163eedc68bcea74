// The mesh stages through their Stage interface: parameters, ports and errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;

TEST(MeshStages, HullConstraintWithoutViewsIsAClearError) {
    test::StageHarness h("mesh.laplacian_smooth");
    h.params("{constrain: hull}");
    h.input("mesh", test::make_sphere({0, 0, 0}, 1.0f, 2));
    const std::string e = h.error();
    EXPECT_NE(e.find("views input"), std::string::npos) << e;
}

TEST(MeshStages, HullConstrainedSmoothingThroughTheStage) {
    test::StageHarness h("mesh.taubin_smooth");
    h.params("{constrain: hull}");
    h.input("mesh", test::make_grid_box(-1.0f, 1.0f, 8));
    h.input("views", test::make_box_views(-1.0f, 1.0f, 128));
    auto out = h.run<Mesh>();
    EXPECT_TRUE(check_mesh(*out).closed_manifold());
    EXPECT_NE(h.metrics().count("max_hull_distance_px"), 0u);
}

TEST(MeshStages, TaubinRefusesAShrinkingMu) {
    test::StageHarness h("mesh.taubin_smooth");
    h.params("{mu: -0.5}");
    const std::string e = h.error();
    EXPECT_NE(e.find("mu < -lambda"), std::string::npos) << e;
}

TEST(MeshStages, ReduceRefusesTwoTargetsAndMeetsARatio) {
    test::StageHarness two("mesh.reduce");
    two.params("{target_faces: 100, target_ratio: 0.5}");
    EXPECT_NE(two.error().find("not both"), std::string::npos);

    test::StageHarness h("mesh.reduce");
    h.params("{target_ratio: 0.25, max_angle_deg: 40}");
    const Mesh sphere = test::make_sphere({0, 0, 0}, 1.0f, 4);
    h.input("mesh", sphere);
    auto out = h.run<Mesh>();
    EXPECT_LE(out->face_count(), sphere.face_count() / 4);
    EXPECT_TRUE(check_mesh(*out).closed_manifold());
}

TEST(MeshStages, ReduceSilhouetteConstraintNeedsTheViewsAndKeepsTheBoxOutline) {
    test::StageHarness bare("mesh.reduce");
    bare.params("{constrain: silhouette}");
    bare.input("mesh", test::make_grid_box(-1.0f, 1.0f, 8));
    const std::string e = bare.error();
    EXPECT_NE(e.find("views input"), std::string::npos) << e;

    // A box drawn from three sides: its outline is its faces' edges, which every collapse
    // of the flat sides keeps, so the constraint leaves the paper's result as it is.
    test::StageHarness free("mesh.reduce"), kept("mesh.reduce");
    free.params("{max_angle_deg: 30}");
    kept.params("{max_angle_deg: 30, constrain: silhouette}");
    for (auto* h : {&free, &kept}) h->input("mesh", test::make_grid_box(-1.0f, 1.0f, 8));
    kept.input("views", test::make_box_views(-1.0f, 1.0f, 128));
    auto a = free.run<Mesh>(), b = kept.run<Mesh>();
    EXPECT_TRUE(check_mesh(*b).closed_manifold());
    EXPECT_EQ(a->face_count(), b->face_count());
}

TEST(MeshStages, QuadricNeedsATarget) {
    test::StageHarness h("mesh.quadric_decimate");
    h.params("{target_ratio: 0}");
    EXPECT_NE(h.error().find("give a target"), std::string::npos);
}

TEST(MeshStages, WriteReportsTheOutputRulesAndWarnsWhenOneIsBroken) {
    test::TempDir dir("mesh_write_check");
    test::StageHarness h("mesh.write");
    h.param("path", dir / "clean.ply");
    h.input("mesh", test::make_box({0, 0, 0}, {1, 1, 1}));
    h.run<FileOutput>();
    EXPECT_EQ(std::stod(h.metrics().at("self_intersections")), 0.0);
    EXPECT_EQ(std::stod(h.metrics().at("boundary_edges")), 0.0);
    EXPECT_EQ(h.metric("components"), 1.0);
    EXPECT_EQ(h.metric("genus"), 0.0);
    EXPECT_TRUE(h.warnings().empty());

    // A broken rule that a file can hold is a warning: an open box.
    Mesh open = test::make_box({0, 0, 0}, {1, 1, 1});
    open.triangles.pop_back();
    h.param("path", dir / "open.ply");
    h.input("mesh", open);
    h.run<FileOutput>();
    EXPECT_GT(std::stod(h.metrics().at("boundary_edges")), 0.0);
    EXPECT_EQ(h.metrics().count("genus"), 0u); // an open mesh has no genus to report
    ASSERT_EQ(h.warnings().size(), 1u);
    EXPECT_NE(h.warnings()[0].find("boundary edges"), std::string::npos) << h.warnings()[0];
    EXPECT_NE(h.warnings()[0].find("open.ply"), std::string::npos) << h.warnings()[0];

    // Crossing faces are never written: an error naming the file, and no file.
    const Mesh two = test::make_crossing_boxes();
    h.param("path", dir / "crossing.ply");
    h.input("mesh", two);
    try {
        h.run<FileOutput>();
        ADD_FAILURE() << "a mesh with crossing faces was written";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("pairs of crossing faces"), std::string::npos) << what;
        EXPECT_NE(what.find("crossing.ply"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "crossing.ply"));

    // Nor are degenerate faces: a box with a face of zero area.
    Mesh flat = test::make_box({0, 0, 0}, {1, 1, 1});
    flat.triangles.push_back({flat.triangles[0][0], flat.triangles[0][1], flat.triangles[0][1]});
    h.param("path", dir / "flat.ply");
    h.input("mesh", flat);
    EXPECT_THROW(h.run<FileOutput>(), Error);
    EXPECT_FALSE(std::filesystem::exists(dir / "flat.ply"));

    // A flat cap (a corner on the opposite edge: no area) is flipped away, not refused.
    h.param("path", dir / "cap.ply");
    h.input("mesh", test::make_box_with_flat_cap({0, 0, 0}, {1, 1, 1}));
    h.run<FileOutput>();
    EXPECT_EQ(std::stod(h.metrics().at("degenerate_faces")), 0.0);
    EXPECT_EQ(std::stod(h.metrics().at("flat_caps_flipped")), 1.0);
    EXPECT_TRUE(h.warnings().empty());
    EXPECT_EQ(check_mesh(read_mesh(dir / "cap.ply")).degenerate_faces, 0u);

    h.param("path", dir / "crossing.ply");
    h.input("mesh", two);
    h.params("{check: false}");
    h.run<FileOutput>();
    EXPECT_EQ(h.metrics().count("self_intersections"), 0u);
    EXPECT_TRUE(h.warnings().empty());
}

namespace {

// A torus around the Y axis as a closed grid of quads (two triangles each), outward: genus 1.
Mesh torus(float major, float minor, int around, int across, Vec3f centre) {
    Mesh m;
    const float two_pi = 6.2831853f;
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < across; ++j) {
            const float u = two_pi * float(i) / float(around), v = two_pi * float(j) / float(across);
            const float r = major + minor * std::cos(v);
            m.positions.push_back(centre + Vec3f(r * std::cos(u), minor * std::sin(v), r * std::sin(u)));
        }
    auto at = [&](int i, int j) { return std::uint32_t((i % around) * across + j % across); };
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < across; ++j) {
            m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
            m.triangles.push_back({at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
        }
    return m;
}

} // namespace

TEST(MeshStages, WriteReportsTheComponentsAndTunnelsOfWhatItWrites) {
    // A ring beside a box: two components, one tunnel between them (the box alone: 1 and 0,
    // WriteReportsTheOutputRulesAndWarnsWhenOneIsBroken).
    test::TempDir dir("mesh_write_genus");
    test::StageHarness h("mesh.write");
    Mesh both = torus(2.0f, 0.5f, 24, 12, {5, 0, 0});
    const Mesh box = test::make_box({0, 0, 0}, {1, 1, 1});
    const auto first = std::uint32_t(both.positions.size());
    both.positions.insert(both.positions.end(), box.positions.begin(), box.positions.end());
    for (auto t : box.triangles) both.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
    ASSERT_TRUE(check_mesh(both).closed_manifold());
    ASSERT_GT(check_mesh(both).signed_volume, 0.0);
    h.param("path", dir / "ring.ply");
    h.input("mesh", both);
    h.run<FileOutput>();
    EXPECT_EQ(h.metric("components"), 2.0);
    EXPECT_EQ(h.metric("genus"), 1.0);
    EXPECT_TRUE(h.warnings().empty());
}
