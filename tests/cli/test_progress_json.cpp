// `conceptmesh run --progress json`: the stream a program (the Blender add-on) reads. Every
// line of stdout is one JSON object; a run that works ends with its outputs and "ok", one
// that fails with the message and the node and stage it names, and a non-zero status.
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::vector<json> lines_of(const std::string& out) {
    std::vector<json> lines;
    std::istringstream in(out);
    std::string line;
    while (std::getline(in, line)) {
        json j;
        EXPECT_NO_THROW(j = json::parse(line)) << "not one JSON object: " << line;
        EXPECT_TRUE(j.is_object()) << line;
        lines.push_back(j);
    }
    return lines;
}

std::string run_args(const fs::path& manifest) {
    return "run " + (test::source_dir() / "pipelines/paper.yaml").string() +
           " --progress json --set views.manifest=" + manifest.string() +
           " --set hull.resolution=64 --set write.path=out/s.obj --set preview.path=out/s.png";
}

} // namespace

TEST(ProgressJson, EveryLineIsAnEventAndTheRunEndsWithItsOutputs) {
    test::TempDir dir("progress-json-ok");
    const auto r = test::run_cli(run_args(test::source_dir() / "examples/spot/views.yaml"), dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<json> lines = lines_of(r.out);
    ASSERT_GE(lines.size(), 3u);
    EXPECT_EQ(lines.front()["event"], "begin");
    EXPECT_EQ(lines.front()["nodes"].size(), 9u);
    // Per node: start, progress rising within [0, 1], finish; the overall figure never falls.
    std::map<std::string, double> last;
    std::map<std::string, int> started, finished;
    double overall = 0;
    std::size_t progress_lines = 0;
    for (const json& j : lines) {
        const std::string event = j["event"];
        if (j.contains("overall")) {
            EXPECT_GE(double(j["overall"]), overall - 1e-12) << j.dump();
            overall = j["overall"];
        }
        if (event == "start") ++started[j["node"]];
        if (event == "finish") ++finished[j["node"]];
        if (event != "progress") continue;
        ++progress_lines;
        const double f = j["fraction"];
        EXPECT_GE(f, 0.0);
        EXPECT_LE(f, 1.0);
        EXPECT_GT(f, last[j["node"]]) << j.dump();
        EXPECT_EQ(started[j["node"]], 1) << "progress before the node started: " << j.dump();
        EXPECT_FALSE(std::string(j["stage"]).empty()) << j.dump();
        last[j["node"]] = f;
    }
    EXPECT_GT(progress_lines, 9u);
    EXPECT_EQ(started.size(), 9u);
    EXPECT_EQ(finished.size(), 9u);
    EXPECT_DOUBLE_EQ(overall, 1.0);
    const json& end = lines.back();
    EXPECT_EQ(end["event"], "end");
    EXPECT_EQ(end["status"], "ok");
    ASSERT_EQ(end["outputs"].size(), 2u);
    EXPECT_EQ(end["outputs"][0], fs::canonical(dir / "out/s.obj").string());
    for (const auto& path : end["outputs"]) EXPECT_TRUE(fs::exists(std::string(path))) << path;
    EXPECT_EQ(lines[lines.size() - 3]["event"], "output");
    // No bars or "done in" lines on stderr: the stream is the progress.
    EXPECT_EQ(r.err.find("done in"), std::string::npos) << r.err;
}

TEST(ProgressJson, AnErrorNamesItsNodeAndStage) {
    test::TempDir dir("progress-json-error");
    test::write_text(dir / "views.yaml", "views:\n  front: missing.png\n");
    const auto r = test::run_cli(run_args(dir / "views.yaml"), dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const std::vector<json> lines = lines_of(r.out);
    ASSERT_FALSE(lines.empty());
    const json& end = lines.back();
    EXPECT_EQ(end["event"], "end");
    EXPECT_EQ(end["status"], "error");
    EXPECT_EQ(end["node"], "views");
    EXPECT_EQ(end["stage"], "views.load");
    const std::string cause = end["cause"];
    EXPECT_NE(cause.find("missing.png"), std::string::npos) << cause;
    EXPECT_EQ(cause.find("node \"views\""), std::string::npos) << "the cause is the message without its prefix";
    EXPECT_NE(std::string(end["message"]).find("node \"views\" (views.load): "), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "out")) << "no partial output";
    // The same one line on stderr, as without the stream.
    EXPECT_NE(r.err.find("conceptmesh: error: "), std::string::npos) << r.err;
}

TEST(ProgressJson, AFailureBeforeThePipelineIsReadStillEndsTheStream) {
    test::TempDir dir("progress-json-nofile");
    const auto r = test::run_cli("run no-such-pipeline.yaml --progress json", dir.path());
    EXPECT_NE(r.exit_code, 0);
    const std::vector<json> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 1u) << r.out;
    EXPECT_EQ(lines[0]["event"], "end");
    EXPECT_EQ(lines[0]["status"], "error");
    EXPECT_NE(std::string(lines[0]["message"]).find("no-such-pipeline.yaml"), std::string::npos);
    EXPECT_FALSE(lines[0].contains("node"));
}

TEST(ProgressJson, AnUnknownFormatIsAUsageError) {
    test::TempDir dir("progress-json-usage");
    const auto r = test::run_cli("run x.yaml --progress xml", dir.path());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("xml"), std::string::npos) << r.err;
}

TEST(ProgressJson, AStoppedRunEndsCancelledAndLeavesNoFile) {
    // The hull node is held (core/progress.h) until the stop comes, so the SIGTERM lands
    // mid-run; the add-on's Esc sends the same signal.
    test::TempDir dir("progress-json-cancel");
    const std::string run =
        "'" + std::string(CM_EXE) + "' " + run_args(test::source_dir() / "examples/spot/views.yaml");
    const std::string script = "cd '" + dir.path().string() + "' && CONCEPTMESH_TEST_HOLD_NODE=hull " + run +
                               " >out.jsonl 2>err.txt & pid=$!; n=0; "
                               "while ! grep -q 'test hold' '" +
                               (dir / "err.txt").string() +
                               "' 2>/dev/null && [ $n -lt 600 ]; do sleep 0.05; n=$((n+1)); done; "
                               "kill -TERM $pid; wait $pid; echo $? >'" +
                               (dir / "status.txt").string() + "'";
    ASSERT_EQ(std::system(script.c_str()), 0);
    EXPECT_EQ(test::read_text(dir / "status.txt"), "143\n") << test::read_text(dir / "err.txt");
    const std::vector<json> lines = lines_of(test::read_text(dir / "out.jsonl"));
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines.back()["event"], "end");
    EXPECT_EQ(lines.back()["status"], "cancelled") << lines.back().dump();
    // The stop is taken at the held node's next look, or by the node after it when the hull
    // had no look left: either way the line names where.
    EXPECT_TRUE(lines.back().contains("node") && lines.back().contains("stage")) << lines.back().dump();
    EXPECT_FALSE(fs::exists(dir / "out")) << "no partial output";
}
