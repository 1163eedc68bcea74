// The mesh stages through their Stage interface: parameters, ports and errors.
#include <gtest/gtest.h>

#include <memory>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "support/shapes.h"
#include "support/test_support.h"

namespace cm {
Stage* make_mesh_laplacian_smooth();
Stage* make_mesh_taubin_smooth();
Stage* make_mesh_reduce();
Stage* make_mesh_quadric_decimate();
Stage* make_mesh_write();
}

using namespace cm;

namespace {

// The declared defaults, as the host fills them in.
ParamSet defaults(const Stage& s) {
    ParamSet p;
    for (const auto& spec : s.info().params)
        if (spec.default_value) p.set(spec.name, *spec.default_value);
    return p;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(MeshStages, HullConstraintWithoutViewsIsAClearError) {
    std::unique_ptr<Stage> s(make_mesh_laplacian_smooth());
    ParamSet p = defaults(*s);
    p.set("constrain", std::string("hull"));
    s->prepare(p);
    Inputs in;
    in.set("mesh", std::make_shared<const Mesh>(test::make_sphere({0, 0, 0}, 1.0f, 2)));
    Context ctx("smooth", "mesh.laplacian_smooth", {});
    const std::string e = error_of([&] { s->run(in, ctx); });
    EXPECT_NE(e.find("views input"), std::string::npos) << e;
}

TEST(MeshStages, HullConstrainedSmoothingThroughTheStage) {
    std::unique_ptr<Stage> s(make_mesh_taubin_smooth());
    ParamSet p = defaults(*s);
    p.set("constrain", std::string("hull"));
    s->prepare(p);
    Inputs in;
    in.set("mesh", std::make_shared<const Mesh>(test::make_grid_box(-1.0f, 1.0f, 8)));
    in.set("views", std::make_shared<const Views>(test::make_box_views(-1.0f, 1.0f, 128)));
    Context ctx("smooth", "mesh.taubin_smooth", {});
    auto out = std::get<std::shared_ptr<const Mesh>>(s->run(in, ctx));
    EXPECT_TRUE(check_mesh(*out).closed_manifold());
    EXPECT_NE(ctx.metrics_json().count("max_hull_distance_px"), 0u);
}

TEST(MeshStages, TaubinRefusesAShrinkingMu) {
    std::unique_ptr<Stage> s(make_mesh_taubin_smooth());
    ParamSet p = defaults(*s);
    p.set("mu", -0.5);
    const std::string e = error_of([&] { s->prepare(p); });
    EXPECT_NE(e.find("mu < -lambda"), std::string::npos) << e;
}

TEST(MeshStages, ReduceRefusesTwoTargetsAndMeetsARatio) {
    std::unique_ptr<Stage> s(make_mesh_reduce());
    ParamSet p = defaults(*s);
    p.set("target_faces", std::int64_t(100));
    p.mark_explicit("target_faces");
    p.set("target_ratio", 0.5);
    p.mark_explicit("target_ratio");
    EXPECT_NE(error_of([&] { s->prepare(p); }).find("not both"), std::string::npos);

    ParamSet q = defaults(*s);
    q.set("target_ratio", 0.25);
    q.mark_explicit("target_ratio");
    q.set("max_angle_deg", 40.0);
    s->prepare(q);
    Inputs in;
    const Mesh sphere = test::make_sphere({0, 0, 0}, 1.0f, 4);
    in.set("mesh", std::make_shared<const Mesh>(sphere));
    Context ctx("reduce", "mesh.reduce", {});
    auto out = std::get<std::shared_ptr<const Mesh>>(s->run(in, ctx));
    EXPECT_LE(out->face_count(), sphere.face_count() / 4);
    EXPECT_TRUE(check_mesh(*out).closed_manifold());
}

TEST(MeshStages, QuadricNeedsATarget) {
    std::unique_ptr<Stage> s(make_mesh_quadric_decimate());
    ParamSet p = defaults(*s);
    p.set("target_ratio", 0.0);
    EXPECT_NE(error_of([&] { s->prepare(p); }).find("give a target"), std::string::npos);
}

TEST(MeshStages, WriteReportsTheOutputRulesAndWarnsWhenOneIsBroken) {
    test::TempDir dir("mesh_write_check");
    std::unique_ptr<Stage> s(make_mesh_write());
    ParamSet p = defaults(*s);
    p.set("path", (dir / "clean.ply").string());
    s->prepare(p);
    Inputs in;
    in.set("mesh", std::make_shared<const Mesh>(test::make_box({0, 0, 0}, {1, 1, 1})));
    Context clean("write", "mesh.write", {});
    s->run(in, clean);
    EXPECT_EQ(std::stod(clean.metrics_json().at("self_intersections")), 0.0);
    EXPECT_EQ(std::stod(clean.metrics_json().at("boundary_edges")), 0.0);
    EXPECT_TRUE(clean.warnings().empty());

    const Mesh two = test::make_crossing_boxes();
    p.set("path", (dir / "crossing.ply").string());
    s->prepare(p);
    in.set("mesh", std::make_shared<const Mesh>(two));
    Context bad("write", "mesh.write", {});
    s->run(in, bad);
    EXPECT_GT(std::stod(bad.metrics_json().at("self_intersections")), 0.0);
    ASSERT_EQ(bad.warnings().size(), 1u);
    EXPECT_NE(bad.warnings()[0].find("self-intersecting face pairs"), std::string::npos) << bad.warnings()[0];
    EXPECT_NE(bad.warnings()[0].find("crossing.ply"), std::string::npos) << bad.warnings()[0];

    p.set("check", false);
    s->prepare(p);
    Context unchecked("write", "mesh.write", {});
    s->run(in, unchecked);
    EXPECT_EQ(unchecked.metrics_json().count("self_intersections"), 0u);
    EXPECT_TRUE(unchecked.warnings().empty());
}
