// extract.marching_cubes on a real hull: Spot's mask views rendered by the command,
// carved, refined and extracted through the plugins, written, read back and compared.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using json = nlohmann::json;

namespace {

const char* kPipeline =
    "pipeline: phase1\n"
    "nodes:\n"
    "  - id: views\n"
    "    stage: views.load\n"
    "    params: { manifest: views/views.yaml }\n"
    "  - id: hull\n"
    "    stage: hull.carve\n"
    "    inputs: { views: views }\n"
    "    params: { resolution: 64 }\n"
    "  - id: refine\n"
    "    stage: hull.marching_intersections\n"
    "    inputs: { volume: hull, views: views }\n"
    "  - id: surface\n"
    "    stage: extract.marching_cubes\n"
    "    inputs: { volume: refine }\n"
    "  - id: write\n"
    "    stage: mesh.write\n"
    "    inputs: { mesh: surface }\n"
    "    params: { path: out/spot.ply }\n";

} // namespace

TEST(ExtractPipeline, SpotHullIsClosedAndMatchesItsViews) {
    const auto model = test::shared_dir() / "data/models/spot.obj";
    if (!std::filesystem::exists(model)) GTEST_SKIP() << "no " << model;
    test::TempDir dir("extract-spot");
    auto r = test::run_cli("render-views '" + model.string() + "' --style mask --size 256 --front -Z -o views -q",
                           dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    test::write_text(dir / "p.yaml", kPipeline);
    for (const char* res : {"64", "32"}) {
        SCOPED_TRACE(res);
        r = test::run_cli(std::string("run p.yaml -q --report run.json --set hull.resolution=") + res, dir.path());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const Mesh m = read_mesh(dir / "out/spot.ply");
        const MeshCheck c = check_mesh(m);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_EQ(c.degenerate_faces, 0u);
        EXPECT_EQ(c.components, 1u);
        EXPECT_EQ(c.euler, 2); // Spot is genus 0
        EXPECT_GT(c.signed_volume, 0.0);
        // The stage's own check agrees, in the run report.
        const json rep = json::parse(test::read_text(dir / "run.json"));
        for (const auto& n : rep["nodes"])
            if (n["id"] == "surface") {
                EXPECT_EQ(n["metrics"]["boundary_edges"], 0);
                EXPECT_EQ(n["metrics"]["nonmanifold_vertices"], 0);
                EXPECT_EQ(n["metrics"]["faces"], double(m.face_count()));
            }
        // In the output frame already: re-rendered through the input cameras it matches them.
        r = test::run_cli("compare out/spot.ply views/views.yaml --json -q", dir.path());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const double xor_pct = json::parse(r.out)["xor_pct"];
        EXPECT_LT(xor_pct, std::string(res) == "64" ? 1.0 : 2.0);
    }
}
