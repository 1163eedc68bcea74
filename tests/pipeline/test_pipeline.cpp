// Pipeline parsing, validation and execution. Every rejection names the file,
// the line, the node and the stage.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "fixtures/testkit_stages.h"
#include "io/mesh_io.h"
#include "pipeline/pipeline.h"
#include "pipeline/renamed_params.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

const Registry& registry() { return testkit::registry_with_plugins(); }

// A pipeline that makes a box (node "box") and writes it to `path` (node "write"); more
// nodes may follow.
std::string box_written_to(const fs::path& path) {
    return "nodes:\n"
           "  - {id: box, stage: test.box}\n"
           "  - {id: write, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
           path.string() + "}}\n";
}

// Parses and validates; returns the error message ("" when valid).
std::string rejection(const std::string& yaml, const std::vector<std::string>& sets = {}) {
    try {
        Pipeline p = Pipeline::parse(yaml, "p.yaml");
        for (const auto& s : sets) p.apply_override(s);
        p.validate(registry());
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(Pipeline, ValidGraphRunsAndWritesItsOutput) {
    test::TempDir dir("pipeline-valid");
    const std::string yaml =
        "pipeline: t\nnodes:\n"
        "  - id: box\n    stage: test.box\n    params: { size: 2.5 }\n"
        "  - id: slow\n    stage: test.sleep\n    inputs: { mesh: box }\n    params: { seconds: 0.05 }\n"
        "  - id: write\n    stage: mesh.write\n    inputs: { mesh: slow }\n    params: { path: " +
        (dir / "box.ply").string() + " }\n";
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    p.validate(registry());
    ASSERT_EQ(p.order.size(), 3u);
    EXPECT_EQ(p.nodes[p.order[0]].id, "box");
    EXPECT_EQ(p.nodes[p.order[2]].id, "write");
    RunResult r = run_pipeline(p, registry(), {});
    ASSERT_TRUE(fs::exists(dir / "box.ply"));
    const Mesh m = read_mesh(dir / "box.ply");
    Vec3f lo, hi;
    m.bounds(lo, hi);
    EXPECT_FLOAT_EQ(hi.x, 2.5f);
    // Nothing else is left in the folder (no temporary files).
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
    // The report has each node with its time, memory and counts.
    auto j = nlohmann::json::parse(r.to_json(p));
    ASSERT_EQ(j["nodes"].size(), 3u);
    EXPECT_EQ(j["nodes"][0]["id"], "box");
    EXPECT_EQ(j["nodes"][0]["metrics"]["faces"], 12);
    EXPECT_EQ(j["nodes"][0]["params"]["size"], 2.5);
    EXPECT_GE(j["nodes"][1]["seconds"].get<double>(), 0.05);
    EXPECT_GT(j["nodes"][2]["peak_rss_bytes"].get<double>(), 0);
    // CPU time of the process: each node's is part of the whole run's.
    for (const auto& n : j["nodes"]) {
        EXPECT_GE(n["cpu_seconds"].get<double>(), 0.0);
        EXPECT_LE(n["cpu_seconds"].get<double>(), j["cpu_seconds"].get<double>());
    }
    EXPECT_GT(j["cpu_seconds"].get<double>(), 0.0);
    EXPECT_EQ(j["outputs"][0], (dir / "box.ply").string());
}

TEST(Pipeline, IndependentBranchesBothRun) {
    test::TempDir dir("pipeline-branches");
    const std::string yaml =
        "nodes:\n"
        "  - {id: box, stage: test.box}\n"
        "  - {id: a, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
        (dir / "a.obj").string() +
        "}}\n"
        "  - {id: b, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
        (dir / "b.stl").string() + "}}\n";
    // Repeated: every node must run exactly once however the tasks interleave
    // (a node launched twice finds its input already released).
    for (int k = 0; k < 20; ++k) {
        Pipeline p = Pipeline::parse(yaml, "p.yaml");
        ASSERT_NO_THROW(run_pipeline(p, registry(), {})) << "run " << k;
        EXPECT_TRUE(fs::exists(dir / "a.obj"));
        EXPECT_TRUE(fs::exists(dir / "b.stl"));
    }
}

TEST(Pipeline, AFailedRunLeavesNoOutputFile) {
    test::TempDir dir("pipeline-fail");
    const std::string yaml = box_written_to(dir / "out.obj") +
                             "  - {id: slow, stage: test.sleep, inputs: {mesh: box}, params: {seconds: 0.2}}\n"
                             "  - {id: boom, stage: test.fail, inputs: {mesh: slow}}\n";
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    try {
        run_pipeline(p, registry(), {});
        FAIL() << "expected the run to fail";
    } catch (const Error& e) {
        EXPECT_HAS(e.what(), "p.yaml:5: node \"boom\" (test.fail): deliberate failure");
    }
    EXPECT_TRUE(fs::is_empty(dir.path())) << "a failed run left files behind";
}

TEST(Pipeline, CancelStopsTheRunAndLeavesNoOutput) {
    test::TempDir dir("pipeline-cancel");
    const std::string yaml = box_written_to(dir / "out.obj") +
                             "  - {id: slow, stage: test.sleep, inputs: {mesh: box}, params: {seconds: 60}}\n";
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    std::thread canceller([] {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        cancel_requested() = true;
    });
    EXPECT_THROW(run_pipeline(p, registry(), {}), Cancelled);
    canceller.join();
    cancel_requested() = false;
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Pipeline, RejectsUnknownStage) {
    const auto m = rejection("nodes:\n  - id: a\n    stage: test.box\n  - id: hull\n    stage: hull.karve\n");
    EXPECT_HAS(m, "p.yaml:4: node \"hull\" (hull.karve): unknown stage \"hull.karve\"");
    EXPECT_HAS(m, "known stages:");
    EXPECT_HAS(m, "test.box");
}

TEST(Pipeline, RejectsUnknownParameter) {
    const auto m = rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      size: 2\n      sise: 3\n");
    EXPECT_HAS(m, "p.yaml:6: node \"box\" (test.box): unknown parameter \"sise\"");
    EXPECT_HAS(m, "parameters: size, copies, shape");
}

TEST(Pipeline, AFormerParameterNameIsAnsweredWithItsNewName) {
    const auto m = rejection(
        "nodes:\n  - id: box\n    stage: test.box\n  - id: texture\n    stage: texture.project\n"
        "    inputs: {mesh: box}\n    params: {strip_lines: false}\n");
    EXPECT_HAS(m,
               "p.yaml:7: node \"texture\" (texture.project): unknown parameter \"strip_lines\": it is now "
               "\"strokes\" (strip_lines: false is strokes: keep, true is strokes: strip)");
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    // Only that stage's former name: elsewhere the name is just unknown.
    EXPECT_EQ(renamed_param_hint("mesh.write", "strip_lines"), "");
    EXPECT_EQ(renamed_param_hint("texture.project", "strokes"), "");
}

TEST(Pipeline, ARenamingNamesAParameterItsStageDeclaresInsteadOfTheOldOne) {
    const RenamedParam* r = find_renamed_param("texture.project", "strip_lines");
    ASSERT_NE(r, nullptr);
    const StageInfo info = registry().create(r->stage)->info();
    EXPECT_NE(find_param(info.params, r->new_name), nullptr) << r->new_name;
    EXPECT_EQ(find_param(info.params, r->old_name), nullptr) << r->old_name;
}

TEST(Pipeline, RejectsWrongType) {
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      size: big\n"),
               "p.yaml:5: node \"box\" (test.box): size must be a number, got \"big\"");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      copies: 1.5\n"),
               "p.yaml:5: node \"box\" (test.box): copies must be an integer, got \"1.5\"");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      size: \"2\"\n"),
               "size must be a number, got the string \"2\"");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      size: [1, 2]\n"),
               "size must be a number, got a list");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params:\n      shape: sphere\n"),
               "p.yaml:5: node \"box\" (test.box): shape must be one of cube, slab, got \"sphere\"");
}

TEST(Pipeline, RejectsOutOfRangeValue) {
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params: {size: 0}\n"),
               "p.yaml:4: node \"box\" (test.box): size must be in [0.001, 1000] units, got 0");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    params: {copies: 9}\n"),
               "copies must be in [1, 4], got 9");
}

TEST(Pipeline, RejectsMissingInput) {
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n  - id: slow\n    stage: test.sleep\n"),
               "p.yaml:4: node \"slow\" (test.sleep): missing input \"mesh\"");
    EXPECT_HAS(rejection("nodes:\n  - id: slow\n    stage: test.sleep\n    inputs:\n      mesh: nothere\n"),
               "p.yaml:5: node \"slow\" (test.sleep): input \"mesh\" names unknown node \"nothere\"");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n  - id: slow\n    stage: test.sleep\n    inputs:\n "
                         "     mesh: box\n      extra: box\n"),
               "p.yaml:8: node \"slow\" (test.sleep): unknown input port \"extra\" (ports: mesh)");
}

TEST(Pipeline, RejectsPortKindMismatch) {
    EXPECT_HAS(
        rejection("nodes:\n  - id: box\n    stage: test.box\n  - id: nv\n    stage: test.needs_views\n    inputs:\n    "
                  "  views: box\n"),
        "p.yaml:7: node \"nv\" (test.needs_views): input \"views\" needs views but node \"box\" (test.box) gives mesh");
}

TEST(Pipeline, RejectsCycle) {
    const auto m = rejection(
        "nodes:\n  - id: box\n    stage: test.box\n"
        "  - id: a\n    stage: test.sleep\n    inputs: {mesh: b}\n"
        "  - id: b\n    stage: test.sleep\n    inputs: {mesh: a}\n");
    EXPECT_HAS(m, "p.yaml:");
    EXPECT_HAS(m, "(test.sleep): the graph has a cycle: ");
    EXPECT_TRUE(m.find("a -> b -> a") != std::string::npos || m.find("b -> a -> b") != std::string::npos) << m;
}

TEST(Pipeline, RejectsMalformedYaml) {
    const auto m = rejection("nodes:\n  - id: box\n    stage: test.box\n    params: {size: 2\n  - id: x\n");
    EXPECT_HAS(m, "p.yaml:");
    EXPECT_HAS(m, "malformed YAML");
    EXPECT_HAS(rejection("nodes: [\n"), "malformed YAML");
}

TEST(Pipeline, RejectsWhatTheSchemaForbids) {
    EXPECT_HAS(rejection("nodes:\n  - id: box\n    stage: test.box\n    colour: red\n"),
               "p.yaml:2: node \"box\" (test.box): does not match the pipeline schema at [nodes][0]");
    EXPECT_HAS(rejection("nodes:\n  - id: box\n"), "p.yaml:2: ");
    EXPECT_HAS(rejection("nodes: []\n"), "does not match the pipeline schema");
    EXPECT_HAS(rejection("nodez:\n  - id: box\n"), "does not match the pipeline schema");
    EXPECT_HAS(rejection("nodes:\n  - id: 1box\n    stage: test.box\n"), "[nodes][0][id]");
    EXPECT_HAS(rejection("nodes:\n  - {id: box, stage: test.box}\n  - {id: box, stage: test.box}\n"),
               "p.yaml:3: node \"box\" (test.box): the id is used by another node already");
}

TEST(Pipeline, OverridesAreCheckedLikeTheFile) {
    const std::string y = "nodes:\n  - id: box\n    stage: test.box\n";
    EXPECT_EQ(rejection(y, {"box.size=3"}), "");
    EXPECT_HAS(rejection(y, {"box.size=0"}), "size must be in [0.001, 1000] units, got 0 (from --set)");
    EXPECT_HAS(rejection(y, {"box.sizee=3"}), "unknown parameter \"sizee\" (from --set)");
    EXPECT_HAS(rejection(y, {"hull.resolution=3"}), "has no node \"hull\" (nodes: box)");
    EXPECT_HAS(rejection(y, {"box.size"}), "expected NODE.PARAM=VALUE");
    Pipeline p = Pipeline::parse(y, "p.yaml");
    p.apply_override("box.size=7.5");
    p.validate(registry());
    EXPECT_DOUBLE_EQ(p.nodes[0].params.get_float("size"), 7.5);
    EXPECT_TRUE(p.nodes[0].params.explicitly_set("size"));
    EXPECT_EQ(p.nodes[0].params.get_int("copies"), 1); // default filled in
}

TEST(Pipeline, RequiredParameterMustBeGiven) {
    EXPECT_HAS(
        rejection("nodes:\n  - {id: box, stage: test.box}\n  - {id: w, stage: mesh.write, inputs: {mesh: box}}\n"),
        "p.yaml:3: node \"w\" (mesh.write): parameter \"path\" is required");
}

TEST(Pipeline, StagePrepareRejectsBeforeAnythingRuns) {
    test::TempDir dir("pipeline-prepare");
    const std::string yaml =
        "nodes:\n  - {id: box, stage: test.box}\n"
        "  - {id: w, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
        (dir / "x.xyz").string() + "}}\n";
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    try {
        run_pipeline(p, registry(), {});
        FAIL();
    } catch (const Error& e) {
        EXPECT_HAS(e.what(), "p.yaml:3: node \"w\" (mesh.write): path \"");
        EXPECT_HAS(e.what(), "unknown extension");
    }
}

// A pipeline not validated yet: its first node starts as soon as it is checked, while the
// rest is validated (and the later stages' plugins load); the later nodes wait for that.
TEST(Pipeline, TheFirstNodeRunsWhileTheRestIsValidated) {
    test::TempDir dir("pipeline-early");
    const std::string yaml =
        "nodes:\n"
        "  - {id: box, stage: test.slow_box, params: {seconds: 0.3}}\n"
        "  - {id: checked, stage: test.slow_check, inputs: {mesh: box}, params: {seconds: 0.2}}\n"
        "  - {id: write, stage: mesh.write, inputs: {mesh: checked}, params: {path: " +
        (dir / "box.obj").string() + "}}\n";
    auto& order = testkit::start_order();
    order.box_started = 0;
    order.check_ended = 0;
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    const RunResult r = run_pipeline(p, registry(), {});
    ASSERT_NE(order.box_started.load(), 0);
    ASSERT_NE(order.check_ended.load(), 0);
    // The box started before the first check of the later node had ended (0.2 s of sleep).
    EXPECT_LT(order.box_started.load(), order.check_ended.load());
    EXPECT_TRUE(fs::exists(dir / "box.obj"));
    ASSERT_EQ(p.order.size(), 3u); // `p` is validated as run_pipeline always left it
    ASSERT_EQ(r.nodes.size(), 3u);
    EXPECT_EQ(r.nodes[0].id, "box");
    EXPECT_EQ(r.nodes[2].id, "write");
}

// When the rest fails its checks, the started node is stopped, whatever it staged is gone,
// and the error is the validation's, word for word.
TEST(Pipeline, ALaterNodeThatFailsItsChecksStopsTheStartedOnes) {
    test::TempDir dir("pipeline-early-fail");
    const std::string yaml =
        "nodes:\n"
        "  - {id: box, stage: test.slow_box, params: {seconds: 60}}\n"
        "  - {id: checked, stage: test.slow_check, inputs: {mesh: box}, params: {seconds: 0.1}}\n"
        "  - {id: write, stage: mesh.write, inputs: {mesh: checked}, params: {path: " +
        (dir / "box.obj").string() + ", colour: blue}}\n";
    const std::string expected = rejection(yaml);
    ASSERT_FALSE(expected.empty());
    EXPECT_HAS(expected, "p.yaml:4: node \"write\" (mesh.write): unknown parameter \"colour\"");
    auto& order = testkit::start_order();
    order.box_started = 0;
    order.box_stopped = false;
    Pipeline p = Pipeline::parse(yaml, "p.yaml");
    try {
        run_pipeline(p, registry(), {});
        FAIL() << "expected the validation's error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), expected);
    }
    EXPECT_NE(order.box_started.load(), 0) << "the first node did not start early";
    EXPECT_TRUE(order.box_stopped.load()) << "the first node was not stopped";
    EXPECT_TRUE(fs::is_empty(dir.path()));
    EXPECT_FALSE(cancel_requested().load()) << "a run's own stop must not stop the process";
}
