// Hostile input that once crashed or misled a run: each case gives one clear line, a
// non-zero exit and no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "geometry/hull_distance.h"
#include "geometry/silhouette_field.h"
#include "io/image_io.h"
#include "io/limits.h"
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
test::CommandResult paper_run_on(const test::TempDir& dir, const std::string& yaml, const std::string& more = "") {
    for (const char* f : {"front.png", "right.png", "top.png"})
        fs::copy_file(test::source_dir() / "examples" / "spot" / f, dir / f, fs::copy_options::overwrite_existing);
    test::write_text(dir / "views.yaml", yaml);
    std::string pipeline = test::read_text(test::source_dir() / "pipelines" / "paper.yaml");
    const std::string from = "examples/spot/views.yaml";
    pipeline.replace(pipeline.find(from), from.size(), "views.yaml");
    test::write_text(dir / "p.yaml", pipeline);
    return test::run_cli("run p.yaml -q --set hull.resolution=48" + more, dir.path());
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

TEST(HostileInput, AJpegWithBrokenPhotoshopMetadataReadsAsItsPixels) {
    // A Photoshop block (APP13) right after the start of a good JPEG, whose 8BIM IPTC resource
    // says it holds 72 bytes and holds 8, or whose IPTC record says 67 bytes and holds 3.
    // OpenImageIO 2.4's reader copies past such a block's end; the metadata is not used, so
    // the JPEG is decoded without it, to the same pixels as without the block. A block that
    // runs past the end of the file leaves the file short, which is an error.
    test::TempDir dir("hostile_iptc");
    const Image front = read_image(test::source_dir() / "examples" / "spot" / "front.png");
    write_image(front, dir / "good.jpg");
    const Image good_pixels = read_image(dir / "good.jpg");
    const std::string good = test::read_text(dir / "good.jpg");
    // "Photoshop 3.0", then one 8BIM resource: id 0x0404 (IPTC), an empty name, a size, and
    // 8 bytes holding one IPTC record (0x1C, record 2, dataset 0x41, a length, 3 bytes).
    // `fill`: 0xFF bytes before the marker (JPEG allows them; the decoder skips them).
    auto jpeg_with = [&](std::uint8_t resource_size, std::uint8_t record_length, std::size_t extra = 0,
                         std::size_t fill = 0) {
        const std::string block = std::string("Photoshop 3.0\0", 14) + "8BIM" + std::string("\x04\x04\0\0", 4) +
                                  std::string("\0\0\0", 3) + char(resource_size) + std::string("\x1c\x02\x41\0", 4) +
                                  char(record_length) + "Ope";
        const std::size_t len = block.size() + 2 + extra;
        return good.substr(0, 2) + std::string(fill, '\xff') + "\xff\xed" + char(len >> 8) + char(len & 0xff) + block +
               good.substr(2);
    };
    for (const auto& [resource, record, fill] :
         {std::tuple{72, 3, 0}, std::tuple{8, 67, 0}, std::tuple{8, 3, 0}, std::tuple{72, 3, 3}}) {
        SCOPED_TRACE(std::to_string(resource) + " " + std::to_string(record) + " " + std::to_string(fill));
        test::write_text(dir / "broken.jpg",
                         jpeg_with(std::uint8_t(resource), std::uint8_t(record), 0, std::size_t(fill)));
        Image img;
        ASSERT_NO_THROW(img = read_image(dir / "broken.jpg"));
        EXPECT_EQ(img.width, good_pixels.width);
        EXPECT_EQ(img.height, good_pixels.height);
        EXPECT_TRUE(img.pixels == good_pixels.pixels) << "the metadata changed the pixels";
        int w = 0, h = 0;
        EXPECT_TRUE(image_size(dir / "broken.jpg", w, h));
        EXPECT_EQ(w, good_pixels.width);
    }
    std::string cut = jpeg_with(8, 3, 4000); // the block says 4000 bytes more than it holds
    cut.resize(200);                         // and the file ends within it
    test::write_text(dir / "short.jpg", cut);
    try {
        read_image(dir / "short.jpg");
        ADD_FAILURE() << "a JPEG whose metadata block runs past its end was read";
    } catch (const Error& e) {
        EXPECT_HAS(e.what(), "cannot read image \"" + (dir / "short.jpg").string() + "\"");
    }
}

namespace {

// A PNG whose header claims width x height, with the pixel data of an all-white RGB image
// compressed (a few hundred kB claims hundreds of megapixels).
void write_white_png(const fs::path& file, int width, int height) {
    Image img;
    img.width = width;
    img.height = height;
    img.channels = 3;
    img.pixels.assign(std::size_t(width) * height * 3, 1.0f);
    write_image(img, file);
}

} // namespace

TEST(HostileInput, AnImageOverThePixelLimitIsRefusedFromItsHeader) {
    test::TempDir dir("hostile_pixels");
    write_white_png(dir / "big.png", 400, 300);
    ResourceLimits& limits = resource_limits();
    const ResourceLimits saved = limits;
    limits.max_image_pixels = 100'000;
    const std::string e = test::error_of([&] { read_image(dir / "big.png"); });
    limits = saved;
    EXPECT_HAS(e, "cannot read image \"" + (dir / "big.png").string() + "\": it is 400 x 300 pixels");
    EXPECT_HAS(e, "over the limit of 0 megapixels (--max-image-pixels)");
    EXPECT_NO_THROW(read_image(dir / "big.png")); // under the default limit it reads

    // From the command line: the limit is an option, and the run names the view and the size.
    for (const char* f : {"front.png", "right.png", "top.png"})
        fs::copy_file(test::source_dir() / "examples" / "spot" / f, dir / f);
    test::write_text(dir / "views.yaml", "views: {front: front.png, right: right.png, top: top.png}\n");
    test::write_text(dir / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const auto r = test::run_cli("compare t.obj views.yaml --max-image-pixels 1000", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "front.png\": it is ");
    EXPECT_HAS(r.err, "(--max-image-pixels)");
}

TEST(HostileInput, EightAndSixteenBitImagesReadAsTheirValues) {
    test::TempDir dir("hostile_depth");
    Image img;
    img.width = 2;
    img.height = 1;
    img.channels = 4;
    img.pixels = {0.0f, 0.5f, 1.0f, 1.0f, 0.25f, 0.75f, 0.1f, 1.0f};
    write_image(img, dir / "a.png"); // 8 bits
    write_image(img, dir / "a.tif"); // float
    // 16 bits: a binary PPM with maxval 65535 (big-endian samples).
    const std::uint16_t samples[6] = {0, 32768, 65535, 16384, 49152, 6554};
    std::string ppm = "P6\n2 1\n65535\n";
    for (const std::uint16_t v : samples) ppm += {char(v >> 8), char(v & 0xff)};
    test::write_text(dir / "a.ppm", ppm);
    ImageInfo info;
    for (const char* name : {"a.png", "a.tif", "a.ppm"}) {
        SCOPED_TRACE(name);
        const Image back = read_image(dir / name, &info);
        ASSERT_EQ(back.pixels.size(), img.pixels.size());
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            EXPECT_NEAR(back.pixels[i], img.pixels[i], 0.5 / 255 + 1e-6);
        EXPECT_EQ(info.has_alpha, std::string(name) != "a.ppm");
    }
    EXPECT_EQ(info.bits, 16);
}

TEST(HostileInput, AManifestWithTooManyViewsIsRefused) {
    test::TempDir dir("hostile_views");
    std::string yaml = "views:\n";
    for (int i = 0; i < 600; ++i) yaml += "  v" + std::to_string(i) + ": {image: a.png, azimuth: 0}\n";
    EXPECT_HAS(manifest_error(dir, yaml), "holds 600 views, over the limit of 512 (--max-views)");
}

TEST(HostileInput, AMemoryEstimateOverTheLimitIsRefusedWithBothFigures) {
    ResourceLimits& limits = resource_limits();
    const ResourceLimits saved = limits;
    limits.max_memory = 1'000'000'000;
    const std::string e =
        test::error_of([] { check_memory_estimate(3'500'000'000, "the work", "lower the resolution"); });
    EXPECT_NO_THROW(check_memory_estimate(900'000'000, "the work", "lower the resolution"));
    limits = saved;
    EXPECT_HAS(
        e, "the work would need about 3.5 GB, over the memory limit of 1.0 GB (--max-memory); lower the resolution");
    EXPECT_GT(default_max_memory(), 0u);
}

TEST(HostileInput, OneThreadAndTwoGiveTheSameBytes) {
    test::TempDir one("threads_one"), two("threads_two");
    const std::string views = "views: {front: front.png, right: right.png, top: top.png}\n";
    const auto a = paper_run_on(one, views, " --threads 1 --set hull.resolution=96 --report run.json");
    const auto b = paper_run_on(two, views, " --threads 2 --set hull.resolution=96 --report run.json");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    // Every output of pipelines/paper.yaml, whatever it writes: the same files, byte for byte.
    auto outputs = [](const fs::path& dir) {
        std::vector<std::string> files;
        for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
            if (e.is_regular_file()) files.push_back(fs::relative(e.path(), dir).string());
        std::sort(files.begin(), files.end());
        return files;
    };
    const std::vector<std::string> files = outputs(one.path());
    EXPECT_EQ(files, outputs(two.path()));
    EXPECT_EQ(files, (std::vector<std::string>{"out/spot.obj", "out/spot.preview.png"}));
    for (const auto& f : files) {
        SCOPED_TRACE(f);
        const std::string x = test::read_text(one / f), y = test::read_text(two / f);
        EXPECT_GT(x.size(), 1000u);
        EXPECT_TRUE(x == y) << "the files differ";
    }
    // The run reports differ in their times and memory only: every node's figures agree.
    const auto ra = nlohmann::json::parse(test::read_text(one / "run.json"));
    const auto rb = nlohmann::json::parse(test::read_text(two / "run.json"));
    ASSERT_EQ(ra["nodes"].size(), rb["nodes"].size());
    for (std::size_t i = 0; i < ra["nodes"].size(); ++i) {
        SCOPED_TRACE(ra["nodes"][i]["id"].get<std::string>());
        EXPECT_EQ(ra["nodes"][i]["metrics"], rb["nodes"][i]["metrics"]);
        EXPECT_EQ(ra["nodes"][i]["warnings"], rb["nodes"][i]["warnings"]);
    }
    const auto bad = paper_run_on(one, views, " --threads -3");
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_HAS(bad.err, "--threads");
}

TEST(HostileInput, AResolutionTheMachineCannotHoldIsRefusedBeforeCarving) {
    test::TempDir dir("hostile_memory");
    const std::string views = "views: {front: front.png, right: right.png, top: top.png}\n";
    const auto r = paper_run_on(dir, views, " --set hull.resolution=16384 --max-memory 2G");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "node \"hull\" (hull.carve): the hull at resolution 16384 (about ");
    EXPECT_HAS(r.err, "over the memory limit of 2.0 GB (--max-memory); lower the resolution");
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
    // The estimate follows the surface: the same run at 96 goes through under the same limit.
    EXPECT_EQ(paper_run_on(dir, views, " --set hull.resolution=96 --max-memory 2G").exit_code, 0);
}

TEST(HostileInput, RenderAndPreviewSizesOverTheMemoryLimitAreRefused) {
    test::TempDir dir("hostile_render_size");
    test::write_text(dir / "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    auto r = test::run_cli("render-views t.obj -o views --size 16384 --max-memory 2G", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "render-views at 16384 px (art) would need about ");
    EXPECT_FALSE(fs::exists(dir / "views"));
    r = test::run_cli("preview t.obj -o sheet.png --panel 4096 --max-memory 2G", dir.path());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_HAS(r.err, "a preview of 4096 px panels would need about ");
    EXPECT_FALSE(fs::exists(dir / "sheet.png"));
    EXPECT_EQ(test::run_cli("render-views t.obj -o views --size 64 -q", dir.path()).exit_code, 0);
}

// Defect 10: a NaN or an overflow in a camera was reported as "all cameras sit at one
// point", "the camera matrix is singular" (no view named) or, for a size no mesh can hold,
// as NaN vertices in the smoothing. Each is now refused where it is written.
TEST(HostileInput, ANaNOrOverflowingCameraIsNamedWhereItIsWritten) {
    test::TempDir dir("hostile_nan_camera");
    test::write_text(dir / "f.txt", "CONTOUR\nnan 0 0 256\n0 -1 0 256\n0 0 0 1\n");
    const std::string right = "  right: {image: r.png, matrix: [[0, 0, 1, 256], [0, -1, 0, 256], [1, 0, 0, 10]]}\n";
    EXPECT_HAS(manifest_error(dir,
                              "views:\n  front: {image: f.png, matrix: [[.nan, 0, 0, 256], [0, -1, 0, 256], "
                              "[0, 0, 1, 10]]}\n" +
                                  right),
               "views.yaml:2: a matrix entry must be a finite number, got .nan");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: {image: f.png, matrix_file: f.txt}\n" + right),
               "matrix_file \"" + (dir / "f.txt").string() + "\" line 2: \"nan\" is not a finite number");
    EXPECT_HAS(manifest_error(dir,
                              "views:\n  front: {image: f.png, K: [[1e300, 0, 256], [0, 1e300, 256], [0, 0, 1]], "
                              "R: [[1e10, 0, 0], [0, 1e10, 0], [0, 0, 1e10]], t: [0, 0, 5]}\n" +
                                  right),
               "views.yaml:2: view \"front\": K [R | t] overflows");
    EXPECT_HAS(manifest_error(dir,
                              "views:\n  front: {image: f.png, matrix: [[1e300, 0, 0, 256], [0, -1e300, 0, 256], "
                              "[0, 0, 1e-300, 1]]}\n" +
                                  right),
               "views.yaml:2: view \"front\": the matrix puts the camera centre at infinity or NaN");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: {image: f.png, azimuth: .nan}\n"),
               "views.yaml:2: azimuth must be a finite number, got .nan");
    EXPECT_HAS(manifest_error(dir, "views:\n  front: {image: f.png, elevation: .inf}\n"),
               "views.yaml:2: elevation must be a finite number, got .inf");
    EXPECT_HAS(manifest_error(dir, "height: .inf\nviews:\n  front: f.png\n"),
               "views.yaml:1: height must be a finite number, got .inf");
    EXPECT_HAS(manifest_error(dir, "height: 1e300\nviews:\n  front: f.png\n"),
               "views.yaml:1: height 1e300 is outside [1e-12, 1e9] (metres)");
}

TEST(HostileInput, ACameraWithNaNFromCodeIsNamedByTheHull) {
    // Views made by a program, not read from a manifest: the hull names the view.
    View v;
    v.name = "side";
    v.width = v.height = 8;
    v.coverage = Coverage(std::vector<float>(64, 1.0f), 8, 8);
    std::array<double, 12> P{1, 0, 0, 4, 0, -1, 0, 4, 0, 0, 1, 10};
    P[0] = std::numeric_limits<double>::quiet_NaN();
    v.camera = Camera::perspective(P);
    EXPECT_HAS(test::error_of([&] { SilhouetteField f(v); }),
               "view \"side\": the camera matrix has an entry that is not a finite number");
    Camera ortho = *Camera::named("front");
    ortho.scale = std::numeric_limits<double>::quiet_NaN();
    v.camera = ortho;
    EXPECT_HAS(test::error_of([&] { SilhouetteField f(v); }),
               "view \"side\": the camera's scale (nan) is not a positive finite number");
}
