// test::StageHarness takes the parameters the way a pipeline file does: each refusal
// reads as the pipeline's own message after its "file:line: node ... : " prefix.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh.h"
#include "fixtures/testkit_stages.h"
#include "pipeline/pipeline.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;

namespace {

const Registry& with_testkit() { return testkit::registry_with_plugins(); }

// The message a pipeline file with `nodes` gets from validate() and run_pipeline(),
// after the prefix naming its file, line and node.
std::string pipeline_message(const std::string& nodes) {
    try {
        Pipeline p = Pipeline::parse("nodes:\n" + nodes, "p.yaml");
        run_pipeline(p, with_testkit(), {});
    } catch (const Error& e) {
        const std::string m = e.what();
        const auto after_node = m.find("): ");
        return after_node == std::string::npos ? m : m.substr(after_node + 3);
    }
    return "";
}

std::string harness_message(const std::string& stage, const std::string& params) {
    test::StageHarness h(stage, with_testkit());
    h.params(params);
    h.input("mesh", test::make_box({0, 0, 0}, {1, 1, 1}));
    return h.error();
}

} // namespace

TEST(StageHarness, UnknownParameterReadsAsInAPipelineFile) {
    const std::string m = harness_message("test.box", "{size: 2, sise: 3}");
    EXPECT_EQ(m, "unknown parameter \"sise\" (parameters: size, copies, shape, divisions, textured, fin)");
    EXPECT_EQ(m, pipeline_message("  - {id: box, stage: test.box, params: {size: 2, sise: 3}}\n"));
}

TEST(StageHarness, QuotedNumberIsTheWrongType) {
    const std::string m = harness_message("test.box", "{size: \"2\"}");
    EXPECT_EQ(m, "size must be a number, got the string \"2\"");
    EXPECT_EQ(m, pipeline_message("  - {id: box, stage: test.box, params: {size: \"2\"}}\n"));
}

TEST(StageHarness, OutOfRangeValue) {
    const std::string m = harness_message("mesh.reduce", "{max_angle_deg: 95}");
    EXPECT_EQ(m, "max_angle_deg must be in [0.1, 89] deg, got 95");
    EXPECT_EQ(m,
              pipeline_message("  - {id: box, stage: test.box}\n"
                               "  - {id: r, stage: mesh.reduce, inputs: {mesh: box}, params: {max_angle_deg: 95}}\n"));
}

TEST(StageHarness, MissingRequiredParameter) {
    const std::string m = harness_message("mesh.write", "{binary: false}");
    EXPECT_EQ(m, "parameter \"path\" is required: output file; its extension picks the format");
    EXPECT_EQ(m, pipeline_message("  - {id: box, stage: test.box}\n"
                                  "  - {id: w, stage: mesh.write, inputs: {mesh: box}, params: {binary: false}}\n"));
}

TEST(StageHarness, StageCheckRefusesAsBeforeAPipelineRuns) {
    const std::string m = harness_message("mesh.write", "{path: x.abc}");
    EXPECT_EQ(m, "path \"x.abc\" has an unknown extension (use .obj, .ply, .stl, .off, .glb, .usda or .usdz)");
    EXPECT_EQ(m, pipeline_message("  - {id: box, stage: test.box}\n"
                                  "  - {id: w, stage: mesh.write, inputs: {mesh: box}, params: {path: x.abc}}\n"));
    EXPECT_EQ(harness_message("mesh.reduce", "{target_faces: 10, target_ratio: 0.5}"),
              pipeline_message("  - {id: box, stage: test.box}\n  - {id: r, stage: mesh.reduce, inputs: {mesh: box}, "
                               "params: {target_faces: 10, target_ratio: 0.5}}\n"));
}

TEST(StageHarness, OutputPathRefusesAFileWhereAFolderMustBe) {
    test::TempDir dir("harness-output-path");
    test::write_text(dir / "taken", "a file");
    test::StageHarness h("volume.write");
    h.param("path", dir / "taken" / "hull.vdb");
    try {
        h.configure();
        FAIL() << "expected a refusal";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "path \"" + (dir / "taken" / "hull.vdb").string() + "\": \"" +
                                             (dir / "taken").string() + "\" is not a folder");
    }
}

TEST(StageHarness, RunsAStageAndKeepsItsFiguresAndFiles) {
    test::TempDir dir("harness-run");
    test::StageHarness box("test.box", with_testkit());
    const auto mesh = box.params("{size: 2.5, shape: slab}").run<Mesh>();
    EXPECT_EQ(box.metric("faces"), 12.0);
    Vec3f lo, hi;
    mesh->bounds(lo, hi);
    EXPECT_FLOAT_EQ(hi.y, 1.25f);

    test::StageHarness write("mesh.write");
    write.param("path", dir / "sub" / "box.obj").input("mesh", mesh);
    write.run<FileOutput>();
    ASSERT_EQ(write.outputs().size(), 1u);
    EXPECT_EQ(write.outputs()[0], dir / "sub" / "box.obj"); // the missing folder was made
    EXPECT_TRUE(std::filesystem::exists(dir / "sub" / "box.obj"));
    EXPECT_TRUE(write.warnings().empty());
}
