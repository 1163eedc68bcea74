// Hostile input that once crashed or misled a run: each case gives one clear line, a
// non-zero exit and no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "geometry/hull_distance.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

#define EXPECT_HAS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

std::string manifest_error(const test::TempDir& dir, const std::string& yaml) {
    test::write_text(dir / "views.yaml", yaml);
    try {
        read_manifest(dir / "views.yaml");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// The bundled example's drawings under the manifest `yaml`, through the paper pipeline
// (hull-constrained smoothing) at a small resolution.
test::CommandResult paper_run_on(const test::TempDir& dir, const std::string& yaml) {
    for (const char* f : {"front.png", "right.png", "top.png"})
        fs::copy_file(test::source_dir() / "examples" / "spot" / f, dir / f);
    test::write_text(dir / "views.yaml", yaml);
    std::string pipeline = test::read_text(test::source_dir() / "pipelines" / "paper.yaml");
    const std::string from = "examples/spot/views.yaml";
    pipeline.replace(pipeline.find(from), from.size(), "views.yaml");
    test::write_text(dir / "p.yaml", pipeline);
    return test::run_cli("run p.yaml -q --set hull.resolution=48", dir.path());
}

} // namespace

TEST(HostileInput, ASilhouetteSampledAtNaNIsOutsideNotACrash) {
    const SilhouetteSdf sdf = silhouette_sdf(std::vector<float>(16 * 16, 1.0f), 16, 16, "v");
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(sdf.sample(nan, 3), inf);
    EXPECT_EQ(sdf.sample(3, -inf), inf);
    EXPECT_LT(sdf.sample(8, 8), 0); // inside, as before
}

TEST(HostileInput, AScaleNoMeshCanHoldIsRefusedWithTheView) {
    test::TempDir dir("hostile_scale");
    const std::string e =
        manifest_error(dir, "views:\n  front: {image: f.png, scale: 1e-300, origin: [256, 256]}\n  top: t.png\n");
    EXPECT_HAS(e, "views.yaml:2: view \"front\": scale 1e-300 is outside [1e-9, 1e9] pixels per world unit");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: {image: f.png, scale: 1e12, origin: [0, 0]}\n"), "outside");
}

TEST(HostileInput, HugeBoundsAreRefused) {
    test::TempDir dir("hostile_bounds");
    EXPECT_HAS(manifest_error(dir, "bounds: [-1e300, -1, -1, 1e300, 1, 1]\nviews:\n  front: f.png\n"),
               "views.yaml:1: bounds: coordinates beyond 1e12");
}

TEST(HostileInput, ExtremeCamerasEndTheRunWithOneLineAndNoOutput) {
    // Once a segfault in the hull-constrained smoothing.
    test::TempDir dir("hostile_run");
    const auto r = paper_run_on(dir,
                                "views:\n"
                                "  front: {image: front.png, scale: 1e-300, origin: [256, 256]}\n"
                                "  right: {image: right.png, scale: 1e-300, origin: [256, 256]}\n"
                                "  top: top.png\n");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "node \"views\" (views.load)");
    EXPECT_HAS(r.err, "scale 1e-300");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

namespace {

// A pipeline of real stages up to a mesh, then `tail` (more nodes), in `dir`.
void write_pipeline(const test::TempDir& dir, const std::string& tail) {
    test::write_text(dir / "p.yaml",
                     "nodes:\n"
                     "  - {id: views, stage: views.load, params: {manifest: " +
                         (test::source_dir() / "examples" / "spot" / "views.yaml").string() +
                         "}}\n"
                         "  - {id: hull, stage: hull.carve, inputs: {views: views}}\n"
                         "  - {id: surface, stage: extract.marching_cubes, inputs: {volume: hull}}\n" +
                         tail);
}

} // namespace

TEST(HostileInput, AKeyGivenTwiceIsRefusedInManifestsAndPipelines) {
    test::TempDir dir("hostile_duplicates");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: a.png\n  front: b.png\n"),
               "views.yaml:3: \"front\" is given twice in one mapping (first on line 2)");
    EXPECT_HAS(manifest_error(dir, "height: 1\nheight: 2\nviews:\n  front: a.png\n"), "views.yaml:2: \"height\"");
    write_pipeline(dir,
                   "  - {id: w, stage: mesh.write, inputs: {mesh: surface}, params: {path: a.obj, path: b.obj}}\n");
    const auto r = test::run_cli("validate p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_HAS(r.err, "p.yaml:5: \"path\" is given twice in one mapping (first on line 5)");
}

TEST(HostileInput, AnAliasBombIsRefusedBeforeItGrows) {
    test::TempDir dir("hostile_aliases");
    // Nine levels of ten aliases each: a billion values from a few hundred bytes.
    std::string yaml = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
    for (int i = 1; i <= 9; ++i) {
        const std::string prev = "*a" + std::to_string(i - 1);
        yaml += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
        for (int k = 0; k < 10; ++k) yaml += (k ? ", " : "") + prev;
        yaml += "]\n";
    }
    EXPECT_HAS(manifest_error(dir, yaml + "views:\n  front: a.png\n"), "once its aliases (*name) are expanded");
    test::write_text(dir / "p.yaml", yaml + "nodes: []\n");
    const auto r = test::run_cli("validate p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_HAS(r.err, "once its aliases (*name) are expanded");
}

TEST(HostileInput, TwoNodesWritingOneFileAreRefused) {
    test::TempDir dir("hostile_two_writers");
    write_pipeline(dir,
                   "  - {id: a, stage: mesh.write, inputs: {mesh: surface}, params: {path: out/m.obj}}\n"
                   "  - {id: b, stage: mesh.write, inputs: {mesh: surface}, params: {path: ./out/../out/m.obj}}\n");
    const auto r = test::run_cli("validate p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_HAS(r.err, "p.yaml:6: node \"b\" (mesh.write): path \"./out/../out/m.obj\" is also written by node \"a\"");
}

TEST(HostileInput, ValidateRunsTheStagesOwnChecks) {
    test::TempDir dir("hostile_validate");
    test::write_text(dir / "p.yaml", "nodes:\n  - {id: views, stage: views.load, params: {manifest: nowhere.yaml}}\n");
    auto r = test::run_cli("validate p.yaml", dir.path());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_HAS(r.err, "p.yaml:2: node \"views\" (views.load): manifest \"nowhere.yaml\" does not exist");
    // A manifest that is a folder: one line naming it, not a stream error.
    fs::create_directory(dir / "folder.yaml");
    try {
        read_manifest(dir / "folder.yaml");
        ADD_FAILURE() << "a folder was read as a manifest";
    } catch (const Error& e) {
        EXPECT_HAS(e.what(), "folder.yaml\": it is a folder");
    }
}

TEST(HostileInput, ViewNamesCannotWriteOutsideTheReportFolder) {
    test::TempDir dir("hostile_names");
    for (const char* f : {"front.png", "right.png", "top.png"})
        fs::copy_file(test::source_dir() / "examples" / "spot" / f, dir / f);
    fs::create_directories(dir / "a" / "b");
    test::write_text(dir / "a" / "b" / "views.yaml",
                     "views:\n"
                     "  ../../escaped: {image: ../../front.png, view: front}\n"
                     "  /tmp/cm-escaped-abs: {image: ../../right.png, view: right}\n"
                     "  ..: {image: ../../top.png, view: top}\n");
    test::write_text(dir / "p.yaml",
                     "nodes:\n  - {id: views, stage: views.load, params: {manifest: a/b/views.yaml, "
                     "save_silhouettes: true}}\n");
    fs::create_directories(dir / "a" / "b" / "rep");
    const auto r = test::run_cli("run p.yaml -q --report a/b/rep/run.json", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "a" / "escaped.silhouette.png")); // rep/../../escaped
    EXPECT_FALSE(fs::exists("/tmp/cm-escaped-abs.silhouette.png"));
    std::vector<std::string> saved;
    for (const auto& e : fs::directory_iterator(dir / "a" / "b" / "rep")) saved.push_back(e.path().filename().string());
    std::sort(saved.begin(), saved.end());
    EXPECT_EQ(saved, (std::vector<std::string>{".._.._escaped.silhouette.png", "_tmp_cm-escaped-abs.silhouette.png",
                                               "run.json", "view...silhouette.png"}));
}

TEST(HostileInput, NumbersThatMeanNothingAreRefused) {
    test::TempDir dir("hostile_numbers");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: {image: a.png, threshold: .nan}\n"),
               "views.yaml:2: threshold must be a finite number, got .nan");
    EXPECT_HAS(manifest_error(dir, "height: .inf\nviews:\n  front: a.png\n"),
               "views.yaml:1: height must be a finite number, got .inf");
    EXPECT_HAS(manifest_error(dir, "views:\n  q: {image: a.png, azimuth: 1e308}\n"),
               "view \"q\": azimuth must be in [-360, 360] degrees");
}

TEST(HostileInput, ATruncatedImageIsAnErrorNotAGreyDrawing) {
    test::TempDir dir("hostile_truncated");
    const Image front = read_image(test::source_dir() / "examples" / "spot" / "front.png");
    for (const char* name : {"front.jpg", "front.png"}) {
        SCOPED_TRACE(name);
        write_image(front, dir / name);
        ASSERT_NO_THROW(read_image(dir / name)); // whole, it reads
        const std::string bytes = test::read_text(dir / name);
        test::write_text(dir / name, bytes.substr(0, bytes.size() / 2));
        try {
            read_image(dir / name);
            ADD_FAILURE() << "half a file was read as an image";
        } catch (const Error& e) {
            EXPECT_HAS(e.what(), std::string("cannot read image \"") + (dir / name).string() + "\"");
        }
    }
}
