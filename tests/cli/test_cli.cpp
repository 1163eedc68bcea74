// The conceptmesh command end to end: runs the built binary.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <cstdlib>

#include <chrono>

#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"
#include "testkit_cli.h"

using namespace cm;
namespace fs = std::filesystem;
using nlohmann::json;
using test::cli_with_testkit;
using test::kFixtures;

namespace {

std::size_t line_count(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

const char* kBoxPipeline =
    "pipeline: box\n"
    "nodes:\n"
    "  - id: box\n"
    "    stage: test.box\n"
    "    params: {size: 1.0}\n"
    "  - id: write\n"
    "    stage: mesh.write\n"
    "    inputs: {mesh: box}\n"
    "    params: {path: box.obj}\n";

} // namespace

TEST(Cli, VersionAndHelp) {
    auto r = test::run_cli("--version");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("conceptmesh " CONCEPTMESH_VERSION_STRING), std::string::npos) << r.out;
    r = test::run_cli("--help");
    EXPECT_EQ(r.exit_code, 0);
    for (const char* cmd : {"run", "validate", "stages", "schema"})
        EXPECT_NE(r.out.find(cmd), std::string::npos) << cmd;
    r = test::run_cli("frobnicate");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
}

// The command allocates through mimalloc on huge pages, with its options set before the
// libraries' first allocation (src/cli/main.cpp); where the environment names an option, it decides.
TEST(Cli, AllocatorOptionsAreSetBeforeAnythingIsAllocatedAndTheEnvironmentDecides) {
#if !defined(CONCEPTMESH_MIMALLOC)
    GTEST_SKIP() << "this build's command uses glibc's malloc (CONCEPTMESH_MIMALLOC off, or no libmimalloc-dev)";
#else
    ::setenv("MIMALLOC_VERBOSE", "1", 1);
    auto r = test::run_cli("--version");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.err.find("option 'large_os_pages': 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("option 'eager_commit_delay': 0"), std::string::npos) << r.err;
    ::setenv("MIMALLOC_LARGE_OS_PAGES", "0", 1);
    ::setenv("MIMALLOC_EAGER_COMMIT_DELAY", "2", 1);
    r = test::run_cli("--version");
    ::unsetenv("MIMALLOC_VERBOSE");
    ::unsetenv("MIMALLOC_LARGE_OS_PAGES");
    ::unsetenv("MIMALLOC_EAGER_COMMIT_DELAY");
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.err.find("option 'large_os_pages': 0"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("option 'eager_commit_delay': 2"), std::string::npos) << r.err;
#endif
}

// mimalloc's blocks of more than 16 MB come on huge pages (the command's mmap advises them):
// a whole run at a resolution whose faces and adjacency tables are such blocks (spot at 640)
// takes an order of magnitude fewer page faults than with that advice off, which naming
// MIMALLOC_LARGE_OS_PAGES in the environment does (large pages stay on for everything else).
TEST(Cli, LargeBlocksComeOnHugePages) {
#if !defined(CONCEPTMESH_MIMALLOC)
    GTEST_SKIP() << "this build's command uses glibc's malloc (CONCEPTMESH_MIMALLOC off, or no libmimalloc-dev)";
#else
    // Only where huge pages are given on advice does the advice make the difference: with
    // "always" every block gets them anyway, with "never" none does.
    const std::string thp = test::read_text("/sys/kernel/mm/transparent_hugepage/enabled");
    if (thp.find("[madvise]") == std::string::npos)
        GTEST_SKIP() << "this system gives transparent huge pages " +
                            (thp.empty() ? std::string("no setting") : "\"" + thp.substr(0, thp.find('\n')) + "\"") +
                            ", not on advice";
    test::TempDir dir("cli-hugepages");
    const std::string args = "run " + (test::source_dir() / "pipelines/paper.yaml").string() +
                             " -q --set views.manifest=" + (test::source_dir() / "examples/spot/views.yaml").string() +
                             " --set hull.resolution=640 --set write.path=s.obj --set preview.path=s.png";
    auto faults = [&] {
        rusage before{}, after{};
        ::getrusage(RUSAGE_CHILDREN, &before);
        const auto r = test::run_cli(args, dir.path());
        ::getrusage(RUSAGE_CHILDREN, &after);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return after.ru_minflt - before.ru_minflt;
    };
    const long advised = faults();
    ::setenv("MIMALLOC_LARGE_OS_PAGES", "1", 1);
    const long plain = faults();
    ::unsetenv("MIMALLOC_LARGE_OS_PAGES");
    EXPECT_GT(plain, 10000); // the blocks are there to be faulted in: the test measures something
    EXPECT_LT(advised * 4, plain) << advised << " faults with the advice, " << plain << " without";
#endif
}

TEST(Cli, SetOverridesReachTheStage) {
    test::TempDir dir("cli-set");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("run p.yaml --set box.size=4 --set write.path=big.ply -q", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "box.obj"));
    const Mesh m = read_mesh(dir / "big.ply");
    Vec3f lo, hi;
    m.bounds(lo, hi);
    EXPECT_FLOAT_EQ(hi.x - lo.x, 4.0f);
}

TEST(Cli, GlbObjectIsNamedAfterTheOutputFile) {
    // Blender's outliner shows the glTF node name: the output's name, not the temporary file's.
    test::TempDir dir("cli-glbname");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("run p.yaml --set write.path=crate.glb -q", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string bytes = test::read_text(dir / "crate.glb");
    EXPECT_NE(bytes.find("\"name\":\"crate\""), std::string::npos);
    EXPECT_EQ(bytes.find(".part-"), std::string::npos);
}

TEST(Cli, UnknownSetTargetIsAnErrorAndWritesNothing) {
    test::TempDir dir("cli-badset");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("run p.yaml --set hull.resolution=512", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("has no node \"hull\""), std::string::npos) << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    r = cli_with_testkit("run p.yaml --set box.colour=red", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("p.yaml:3: node \"box\" (test.box): unknown parameter \"colour\" (from --set)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "box.obj"));
}

TEST(Cli, StagesJsonListsEveryStageWithItsParameters) {
    test::TempDir dir("cli-stages");
    auto r = cli_with_testkit("stages --json", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_TRUE(j.is_array());
    std::map<std::string, json> by_name;
    for (const auto& s : j) by_name[s["name"]] = s;
    for (const char* s : {"views.load", "mesh.write", "test.box", "test.sleep"}) EXPECT_TRUE(by_name.count(s)) << s;
    // Every stage the plain listing shows is in the JSON too.
    auto plain = cli_with_testkit("stages", dir.path());
    for (const auto& [name, s] : by_name) EXPECT_NE(plain.out.find(name), std::string::npos) << name;
    const json& box = by_name["test.box"];
    EXPECT_EQ(box["output"], "mesh");
    ASSERT_EQ(box["params"].size(), 6u);
    EXPECT_EQ(box["params"][0]["name"], "size");
    EXPECT_EQ(box["params"][0]["type"], "float");
    EXPECT_EQ(box["params"][0]["default"], 1.0);
    EXPECT_EQ(box["params"][0]["min"], 0.001);
    EXPECT_EQ(box["params"][0]["unit"], "units");
    EXPECT_EQ(box["params"][2]["choices"], json({"cube", "slab"}));
    const json& write = by_name["mesh.write"];
    EXPECT_EQ(write["params"][0]["name"], "path");
    EXPECT_EQ(write["params"][0]["required"], true);
    EXPECT_EQ(write["inputs"][0]["kind"], "mesh");
}

TEST(Cli, DescribeOneStage) {
    auto r = test::run_cli("stages --describe mesh.write");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("mesh.write"), std::string::npos);
    EXPECT_NE(r.out.find("binary"), std::string::npos);
    EXPECT_NE(r.out.find("its extension picks the format"), std::string::npos);
    r = test::run_cli("stages --describe mesh.wright");
    EXPECT_EQ(r.exit_code, 2); // a name mistyped on the command line
    EXPECT_NE(r.err.find("unknown stage \"mesh.wright\""), std::string::npos) << r.err;
}

TEST(Cli, ValidateReportsOneLineWithFileAndLine) {
    test::TempDir dir("cli-validate");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("validate p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("valid"), std::string::npos);
    test::write_text(dir / "bad.yaml", "nodes:\n  - id: box\n    stage: test.box\n    params: {size: -1}\n");
    r = cli_with_testkit("validate bad.yaml", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(r.err,
              "conceptmesh: error: bad.yaml:4: node \"box\" (test.box): size must be in [0.001, 1000] units, got -1\n");
    r = test::run_cli("validate missing.yaml", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("cannot open pipeline \"missing.yaml\""), std::string::npos) << r.err;
}

TEST(Cli, ReportHasEveryNode) {
    test::TempDir dir("cli-report");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("run p.yaml --report out/run.json -q", dir.path());
    EXPECT_NE(r.exit_code, 0) << "a report in a missing folder must fail";
    fs::create_directories(dir / "out");
    r = cli_with_testkit("run p.yaml --report out/run.json -q", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(test::read_text(dir / "out/run.json"));
    ASSERT_EQ(j["nodes"].size(), 2u);
    for (const auto& n : j["nodes"]) {
        EXPECT_TRUE(n.contains("seconds"));
        EXPECT_TRUE(n.contains("peak_rss_bytes"));
        EXPECT_TRUE(n.contains("params"));
        EXPECT_TRUE(n.contains("metrics"));
    }
    EXPECT_EQ(j["nodes"][1]["metrics"]["faces"], 12);
}

TEST(Cli, PlainProgressLinesWhenNotATerminal) {
    test::TempDir dir("cli-progress");
    test::write_text(dir / "p.yaml", kBoxPipeline);
    auto r = cli_with_testkit("run p.yaml", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find('\r'), std::string::npos) << "no carriage returns in logs";
    EXPECT_NE(r.err.find("[box] test.box done in"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("wrote box.obj"), std::string::npos) << r.err;
}

TEST(Cli, CtrlCStopsPromptlyAndLeavesNoOutput) {
    test::TempDir dir("cli-cancel");
    test::write_text(dir / "p.yaml",
                     std::string(kBoxPipeline) +
                         "  - id: slow\n    stage: test.sleep\n    inputs: {mesh: box}\n    params: {seconds: 120}\n");
    // Interrupt once the slow stage is running (not during start-up, before the handler exists),
    // then time how long the process takes to stop.
    const std::string script =
        "cd '" + dir.path().string() +
        "' || exit 1; '" CM_EXE
        "' run p.yaml 2>err.txt & pid=$!; "
        "for i in $(seq 1 600); do grep -q 'slow] test.sleep started' err.txt 2>/dev/null && break; sleep 0.1; done; "
        "date +%s%N > t0.txt; kill -INT $pid; wait $pid; code=$?; date +%s%N > t1.txt; echo $code > code.txt";
    ::setenv("CONCEPTMESH_PLUGIN_PATH", (kFixtures / "good").c_str(), 1);
    const int status = std::system(script.c_str());
    ::unsetenv("CONCEPTMESH_PLUGIN_PATH");
    ASSERT_EQ(WEXITSTATUS(status), 0);
    EXPECT_EQ(std::stoi(test::read_text(dir / "code.txt")), 130);
    const double secs =
        double(std::stoll(test::read_text(dir / "t1.txt")) - std::stoll(test::read_text(dir / "t0.txt"))) * 1e-9;
    EXPECT_LT(secs, 30.0) << "took " << secs << " s to stop"; // about 0.01 s here; generous for a loaded machine
    EXPECT_FALSE(fs::exists(dir / "box.obj"));
    const std::string err = test::read_text(dir / "err.txt");
    EXPECT_NE(err.find("(SIGINT); no output was written"), std::string::npos) << err;
    for (const auto& e : fs::directory_iterator(dir.path()))
        EXPECT_EQ(e.path().string().find(".part"), std::string::npos) << e.path();
}

// The checked-in schemas are exactly what the binary generates.
TEST(Cli, CheckedInSchemasMatchTheBinary) {
    test::TempDir dir("cli-schema");
    auto r = test::run_cli("schema '" + (dir / "s").string() + "' -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fs::path checked = test::source_dir() / "schemas";
    std::set<std::string> generated;
    for (const auto& e : fs::recursive_directory_iterator(dir / "s")) {
        if (!e.is_regular_file()) continue;
        const auto rel = fs::relative(e.path(), dir / "s");
        generated.insert(rel.string());
        ASSERT_TRUE(fs::exists(checked / rel)) << rel << " is missing from schemas/: run `conceptmesh schema schemas`";
        EXPECT_EQ(test::read_text(checked / rel), test::read_text(e.path()))
            << rel << " differs from what the binary generates: run `conceptmesh schema schemas`";
    }
    for (const auto& e : fs::recursive_directory_iterator(checked)) {
        if (e.is_regular_file()) {
            EXPECT_TRUE(generated.count(fs::relative(e.path(), checked).string()))
                << e.path() << " is checked in but no stage generates it";
        }
    }
    EXPECT_TRUE(generated.count("pipeline.schema.json"));
}

TEST(Cli, OpenImageIOIsLoadedOnlyForAnImageThatIsNotPng) {
    // PNG goes through libpng; OpenImageIO and the libraries it needs are opened only when a
    // view is in another format (the loader's own log says what it opened).
    test::TempDir dir("cli_lazy_oiio");
    for (const char* f : {"front.png", "right.png", "top.png"})
        fs::copy_file(test::source_dir() / "examples" / "spot" / f, dir / f);
    test::write_text(dir / "p.yaml",
                     "pipeline: p\nnodes:\n  - {id: views, stage: views.load, params: {manifest: "
                     "views.yaml}}\n");
    auto run = [&](const std::string& front) {
        test::write_text(dir / "views.yaml", "views: {front: " + front + ", right: right.png, top: top.png}\n");
        ::setenv("LD_DEBUG", "files", 1);
        auto r = test::run_cli("run p.yaml -q", dir.path());
        ::unsetenv("LD_DEBUG");
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.err.find("libconceptmesh_io.so"), std::string::npos) << "no loader log";
        return r.err.find("libOpenImageIO") != std::string::npos;
    };
    EXPECT_FALSE(run("front.png"));
    write_image(read_image(dir / "front.png"), dir / "front.jpg");
    EXPECT_TRUE(run("front.jpg"));
}
