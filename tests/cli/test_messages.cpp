// Messages a user can act on, tried as a new user would: every command-line mistake exits 2
// with a plain sentence, whatever the sub-command; what a library throws is said in the
// project's words; the user's own path, never a temporary one; a pasted megabyte of path
// shortened; `check` names the line of a broken mesh file.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>

#include "support/test_support.h"
#include "testkit_cli.h"

using namespace cm;
namespace fs = std::filesystem;
using test::cli_with_testkit;
using test::kFixtures;

namespace {

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

struct Mistake {
    std::string args, says;
};

// Each mistake, on the sub-command it is made on: exit 2, one line naming what is wrong.
void expect_usage_errors(const std::vector<Mistake>& mistakes, const fs::path& cwd) {
    for (const auto& m : mistakes) {
        SCOPED_TRACE(m.args);
        const auto r = test::run_cli(m.args, cwd);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_HAS(r.err, m.says);
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        EXPECT_EQ(r.err.find("conceptmesh: error: "), 0u) << r.err;
    }
}

} // namespace

TEST(Messages, UnknownOptionMissingArgumentAndBadNumberExit2ForEverySubCommand) {
    test::TempDir dir("messages-usage");
    const std::string p = (test::source_dir() / "pipelines" / "paper.yaml").string();
    expect_usage_errors(
        {
            {"run " + p + " --bogus", "--bogus"},
            {"run", "pipeline is required"},
            {"run " + p + " --report", "--report"},
            {"run " + p + " --threads abc", "--threads: \"abc\" is not a number; give a number in [0, 4096]"},
            {"run " + p + " --threads 5000", "--threads: 5000 is out of range; give a number in [0, 4096]"},
            {"validate", "pipeline is required"},
            {"validate " + p + " --nope", "--nope"},
            {"stages --describe", "--describe"},
            {"stages --describe hull.karve", "--describe: unknown stage \"hull.karve\""},
            {"schema", "dir is required"},
            {"render-views", "mesh is required"},
            {"render-views m.obj --size abc", "--size: \"abc\" is not a number"},
            {"render-views m.obj --size 10", "--size: 10 is out of range"},
            {"compare", "mesh is required"},
            {"preview", "mesh is required"},
            {"preview m.obj", "--output is required"},
            {"check", "mesh is required"},
            {"check m.obj --list abc", "--list: \"abc\" is not a number; give a number >= 0"},
            {"batch", "name the ASSETS.yaml to run"},
            {"--max-memory 5Q run " + p, "--max-memory"},
            {"silhouette front.png", "unknown command \"silhouette\"; the commands are run, validate, stages"},
            {"", "no command; the commands are run, validate"},
            {"--bogus", "unknown option \"--bogus\" before the command; the commands are run"},
            {"--bogus run " + p, "not expected: --bogus"},
        },
        dir.path());
}

TEST(Messages, BadSetSyntaxUnknownNodeParameterAndValueExit2) {
    test::TempDir dir("messages-set");
    const std::string p = (test::source_dir() / "pipelines" / "paper.yaml").string();
    expect_usage_errors(
        {
            {"run " + p + " --set", "--set"},
            {"run " + p + " --set foo", "--set \"foo\": expected NODE.PARAM=VALUE"},
            {"run " + p + " --set hull.resolution", "expected NODE.PARAM=VALUE"},
            {"validate " + p + " --set hull=3", "expected NODE.PARAM=VALUE"},
            {"run " + p + " --set nonode.x=1", "has no node \"nonode\""},
            {"run " + p + " --set hull.nope=1", "node \"hull\" (hull.carve): unknown parameter \"nope\" (from --set)"},
            {"run " + p + " --set hull.resolution=abc", "resolution must be an integer, got \"abc\" (from --set)"},
            {"run " + p + " --set hull.resolution=3", "(from --set)"},
            {"validate " + p + " --set write.height=.inf", "(from --set)"},
        },
        dir.path());
    // The same mistake in the file is not a command-line one.
    std::string yaml = test::read_text(p);
    yaml.replace(yaml.find("resolution: 256"), 15, "resolution: abc");
    test::write_text(dir / "bad.yaml", yaml);
    const auto r = test::run_cli("validate bad.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "bad.yaml:15: node \"hull\" (hull.carve): resolution must be an integer");
}

TEST(Messages, AParameterThatWasRenamedNamesItsNewName) {
    // texture.project's boolean strip_lines became the choice strokes: a pipeline written
    // before is told, on one line naming the node, what to write instead.
    test::TempDir dir("messages-renamed");
    const std::string p = (test::source_dir() / "pipelines" / "textured.yaml").string();
    std::string yaml = test::read_text(p);
    const std::string params = "params: { texture_size: 2048, padding: 4 }";
    ASSERT_NE(yaml.find(params), std::string::npos);
    yaml.replace(yaml.find(params), params.size(), "params: { texture_size: 2048, strip_lines: false }");
    test::write_text(dir / "old.yaml", yaml);
    const auto r = test::run_cli("validate old.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err,
               "old.yaml:34: node \"texture\" (texture.project): unknown parameter \"strip_lines\": it is "
               "now \"strokes\" (strip_lines: false is strokes: keep, true is strokes: strip)");
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    expect_usage_errors({{"validate " + p + " --set texture.strip_lines=false",
                          "node \"texture\" (texture.project): unknown parameter \"strip_lines\" (from --set): it "
                          "is now \"strokes\""}},
                        dir.path());
}

TEST(Messages, OpenVdbArithmeticErrorIsSaidInTheProjectsWords) {
    test::TempDir dir("messages-vdb");
    test::write_text(dir / "p.yaml", "nodes:\n  - {id: grid, stage: test.fail, params: {raise: openvdb_arithmetic}}\n");
    const auto r = cli_with_testkit("run p.yaml -q", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err,
               "p.yaml:2: node \"grid\" (test.fail): a grid computation went out of range (OpenVDB: Tried to "
               "initialize an affine transform from a nearly singular matrix): the voxel size");
    EXPECT_EQ(r.err.find("ArithmeticError"), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
}

TEST(Messages, ABareBadAllocIsSaidAsOutOfMemory) {
    test::TempDir dir("messages-alloc");
    test::write_text(dir / "p.yaml", "nodes:\n  - {id: big, stage: test.fail, params: {raise: bad_alloc}}\n");
    const auto r = cli_with_testkit("run p.yaml -q", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "node \"big\" (test.fail): out of memory");
    EXPECT_EQ(r.err.find("std::bad_alloc"), std::string::npos) << r.err;
}

TEST(Messages, AWriterThatFailsNamesTheUsersPathNotTheTemporary) {
    test::TempDir dir("messages-tmpname");
    test::write_text(dir / "p.yaml",
                     "nodes:\n"
                     "  - {id: box, stage: test.box, params: {fin: true}}\n"
                     "  - {id: write, stage: mesh.write, inputs: {mesh: box}, "
                     "params: {path: out/m.ply, check: false}}\n");
    const auto r = cli_with_testkit("run p.yaml -q", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "node \"write\" (mesh.write): cannot write mesh \"out/m.ply\": the mesh is not 2-manifold");
    EXPECT_EQ(r.err.find(".part-"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Messages, AMegabytePathIsShortenedToItsEndsAndLength) {
    test::TempDir dir("messages-longpath");
    const std::string longname(1'000'000, 'a');
    test::write_text(dir / "p.yaml",
                     "nodes:\n"
                     "  - {id: box, stage: test.box}\n"
                     "  - {id: write, stage: mesh.write, inputs: {mesh: box}, params: {path: " +
                         longname + ".obj}}\n");
    const auto r = cli_with_testkit("run p.yaml -q", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err.substr(0, 2000);
    EXPECT_LT(r.err.size(), 2000u) << r.err.substr(0, 2000);
    EXPECT_HAS(r.err, "node \"write\" (mesh.write)");
    EXPECT_HAS(r.err, "node \"write\" (mesh.write): ");
    // The quoted path and the colon after it: 1,000,004 characters and three more.
    EXPECT_TRUE(std::regex_search(r.err, std::regex(R"(a\.\.\.\(100000[0-9] characters\)\.\.\.a)"))) << r.err;
    EXPECT_HAS(r.err, "File name too long");
    EXPECT_HAS(r.err, "aaaa.obj");
    EXPECT_EQ(lines(r.err), 1u);
    EXPECT_EQ(std::vector<fs::path>(fs::directory_iterator(dir.path()), fs::directory_iterator()).size(), 1u);
}

TEST(Messages, CheckNamesTheLineOfANaNVertexOrAFaceOutOfRange) {
    test::TempDir dir("messages-check");
    const std::string box = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    const std::string faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    test::write_text(dir / "nan.obj", "# a tetrahedron\nv 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\n" + faces);
    test::write_text(dir / "inf.obj", box + "v 1e999 0 0\n" + faces);
    test::write_text(dir / "range.obj", box + "f 1 3 2\nf 1 2 4\nf 1 4 9\nf 2 3 4\n");
    test::write_text(dir / "range.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 7\n3 1 2 3\n");
    test::write_text(dir / "nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"nan.obj", "\"nan.obj\": line 3: vertex coordinate \"nan\" is not a finite number"},
        {"inf.obj", "\"inf.obj\": line 5: vertex coordinate \"1e999\" is not a finite number"},
        {"range.obj", "\"range.obj\": line 7: face index 9 is out of range (the file has 4 vertices)"},
        {"range.off", "\"range.off\": line 9: face index 7 is out of range (the file has 4 vertices, numbered from 0)"},
        {"nan.off", "\"nan.off\": line 4: vertex coordinate \"nan\" is not a finite number"},
    };
    for (const auto& [file, says] : cases) {
        SCOPED_TRACE(file);
        const auto r = test::run_cli("check " + file, dir.path());
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_HAS(r.err, says);
        EXPECT_EQ(lines(r.err), 1u) << r.err;
    }
    // The same tetrahedron, whole, is read and checked.
    test::write_text(dir / "good.obj", box + faces);
    const auto ok = test::run_cli("check good.obj", dir.path());
    EXPECT_EQ(ok.err.find("cannot read"), std::string::npos) << ok.err;
}
