// mesh.write's USD files, written through the stage and opened by two readers that are not
// conceptmesh's, from npm (as the glTF validator is): TinyUSDZ and three.js's USDLoader, run
// in node by tests/support/usd_readers/. Those tests skip with a message when node or the
// packages are missing. The layer's content is checked in C++ in tests/io/test_mesh_usd.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/data.h"
#include "core/mesh.h"
#include "core/views.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"
#include "support/usd_layer.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

// The textured box with vertex colours too, standing on Y = 0.
std::shared_ptr<const Mesh> crate() {
    Mesh m = test::make_textured_box({-1, 0, -1}, {1, 2, 1});
    for (std::size_t i = 0; i < m.positions.size(); ++i) m.colors.push_back({0.5f, 0.25f, float(i) / 8.0f, 1.0f});
    return std::make_shared<Mesh>(std::move(m));
}

std::shared_ptr<const FileOutput> write(test::StageHarness& h, const std::shared_ptr<const Mesh>& m,
                                        const fs::path& path, const std::string& extra = {}) {
    h.param("path", path).input("mesh", m);
    if (!extra.empty()) h.params(extra);
    return h.run<FileOutput>();
}

// The side a face of the crate belongs to, from its outward normal: the make_box order.
int side_of(const nlohmann::json& n) {
    const double x = n[0], y = n[1], z = n[2];
    if (z < -0.99) return 0;
    if (z > 0.99) return 1;
    if (y < -0.99) return 2;
    if (y > 0.99) return 3;
    if (x < -0.99) return 4;
    if (x > 0.99) return 5;
    return -1;
}

} // namespace

TEST(MeshWriteUsd, UsdaCommitsItsTextureBesideItUnderItsFinalName) {
    test::TempDir dir("write_usda");
    test::StageHarness h("mesh.write");
    const auto out = write(h, crate(), dir / "crate.usda");
    ASSERT_EQ(out->paths.size(), 2u);
    EXPECT_EQ(out->paths[0], dir / "crate.usda");
    EXPECT_EQ(out->paths[1], dir / "crate_basecolor.png");
    EXPECT_EQ(test::listing(dir.path()), (std::vector<std::string>{"crate.usda", "crate_basecolor.png"}));
    const std::string layer = test::read_text(dir / "crate.usda");
    // Named after the file, not after the temporary one it was written to.
    EXPECT_EQ(test::usd_value(layer, "asset inputs:file"), "@./crate_basecolor.png@");
    EXPECT_EQ(test::usd_value(layer, "defaultPrim"), "\"crate\"");
    EXPECT_EQ(h.metric("faces"), 12);
    EXPECT_EQ(h.metric("vertices"), 8);
    EXPECT_EQ(h.metric("bytes"), double(fs::file_size(dir / "crate.usda")));
    EXPECT_TRUE(h.warnings().empty());
}

TEST(MeshWriteUsd, UsdzIsOneFileHoldingTheLayerAndTexture) {
    test::TempDir dir("write_usdz");
    test::StageHarness h("mesh.write");
    const auto out = write(h, crate(), dir / "crate.usdz");
    ASSERT_EQ(out->paths.size(), 1u);
    EXPECT_EQ(test::listing(dir.path()), std::vector<std::string>{"crate.usdz"});
    const auto files = test::read_zip(test::read_text(dir / "crate.usdz"));
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files[0].name, "crate.usda");
    EXPECT_EQ(files[1].name, "crate_basecolor.png");
    EXPECT_EQ(test::usd_value(files[0].data, "asset inputs:file"), "@./crate_basecolor.png@");
}

// The file is in metres, as a glTF is: `height` scales the model to it, `unit_scale` converts.
TEST(MeshWriteUsd, HeightAndUnitScaleSizeTheModelInMetres) {
    test::TempDir dir("write_usd_height");
    test::StageHarness h("mesh.write");
    write(h, crate(), dir / "tall.usda", "{height: 2.5}");
    const std::string layer = test::read_text(dir / "tall.usda");
    EXPECT_EQ(test::usd_value(layer, "metersPerUnit"), "1");
    EXPECT_EQ(test::usd_value(layer, "upAxis"), "\"Y\"");
    const auto e = test::usd_numbers(layer, "float3[] extent");
    ASSERT_EQ(e.size(), 6u);
    EXPECT_NEAR(e[4] - e[1], 2.5, 1e-6);
    EXPECT_EQ(h.metric("scale"), 1.25);
    test::StageHarness cm("mesh.write");
    write(cm, crate(), dir / "cm.usda", "{unit_scale: 0.01}");
    const auto c = test::usd_numbers(test::read_text(dir / "cm.usda"), "float3[] extent");
    ASSERT_EQ(c.size(), 6u);
    EXPECT_NEAR(c[4] - c[1], 0.02, 1e-8);
}

TEST(UsdReaders, TinyUsdzLoadsEveryWrittenLayerAndPackageWithItsTexture) {
    std::string why;
    const fs::path modules = test::usd_readers(why);
    if (modules.empty()) GTEST_SKIP() << why;
    test::TempDir dir("usd_tinyusdz");
    Mesh ball = test::make_sphere({0, 1, 0}, 1.0f, 2);
    ball.colors.assign(ball.positions.size(), {0.2f, 0.4f, 0.6f, 1.0f});
    ball.colors[0][3] = 0.5f; // and a displayOpacity
    const auto plain = std::make_shared<const Mesh>(std::move(ball));
    for (const auto& [mesh, name] : {std::pair{crate(), "crate"}, std::pair{plain, "ball"}})
        for (const char* ext : {".usda", ".usdz"}) {
            test::StageHarness h("mesh.write");
            const fs::path file = dir / (std::string(name) + ext);
            write(h, mesh, file);
            const auto r = test::run_usd_reader(modules, "tinyusdz_load.mjs", file, "TINYUSDZ");
            EXPECT_EQ(r.value("ok", false), true) << file << ": " << r.dump();
            EXPECT_EQ(r.value("error", "?"), "") << file;
            ASSERT_EQ(r["meshes"].size(), 1u) << r.dump();
            EXPECT_EQ(r["meshes"][0]["faces"], mesh->triangles.size());
            EXPECT_EQ(r["layer"]["metersPerUnit"], "1");
            EXPECT_EQ(r["layer"]["upAxis"], "\"Y\"");
            EXPECT_EQ(r["layer"]["defaultPrim"], "\"" + std::string(name) + "\"");
            if (mesh != plain) {
                ASSERT_EQ(r["images"].size(), 1u) << r.dump();
                EXPECT_EQ(r["images"][0]["decoded"], true) << r.dump();
                EXPECT_EQ(r["images"][0]["width"], mesh->texture->width);
                EXPECT_EQ(r["images"][0]["height"], mesh->texture->height);
                EXPECT_EQ(r["texture"], 0);
            } else {
                EXPECT_TRUE(r["images"].empty()) << r.dump();
            }
        }
}

// three.js builds the mesh with its texture, and every side of the crate samples its own
// colour block as three.js reads textures (flipY: v up, as USD's st): a flipped V would put
// the top row's colours on the bottom row's sides.
TEST(UsdReaders, ThreeBuildsTheMeshWithItsTextureTheRightWayUp) {
    std::string why;
    const fs::path modules = test::usd_readers(why);
    if (modules.empty()) GTEST_SKIP() << why;
    test::TempDir dir("usd_three");
    const auto m = crate();
    const Image& tex = *m->texture;
    for (const char* name : {"crate.usda", "crate.usdz"}) {
        test::StageHarness h("mesh.write");
        write(h, m, dir / name);
        const auto r = test::run_usd_reader(modules, "three_load.mjs", dir / name, "THREE", "faces");
        ASSERT_EQ(r["meshes"].size(), 1u) << r.dump();
        const auto& got = r["meshes"][0];
        EXPECT_EQ(got["faces"], 12);
        EXPECT_EQ(got["vertices"], 8);
        EXPECT_EQ(got["uvs"], 36);
        EXPECT_EQ(got["roughness"], 1);
        EXPECT_EQ(got["metalness"], 0);
        ASSERT_TRUE(got["map"].is_object()) << name << ": no texture: " << r.dump();
        EXPECT_EQ(got["map"]["width"], tex.width);
        EXPECT_EQ(got["map"]["height"], tex.height);
        EXPECT_EQ(got["map"]["colorSpace"], "srgb");
        const bool flip_y = got["map"]["flipY"];
        ASSERT_EQ(got["triangles"].size(), 12u);
        for (const auto& t : got["triangles"]) {
            const int side = side_of(t);
            ASSERT_GE(side, 0) << t.dump();
            // Where three.js samples: row 0 of the image is v = 1 when it flips Y on upload.
            const double u = t[3], v = t[4];
            const int x = int(std::floor(u * tex.width));
            const int y = int(std::floor((flip_y ? 1.0 - v : v) * tex.height));
            const auto want = test::textured_box_colour(side);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(tex.at(x, y, k), want[std::size_t(k)], 1e-6) << name << " side " << side;
        }
        EXPECT_NEAR(r["max"][1].get<double>() - r["min"][1].get<double>(), 2.0, 1e-6);
    }
}

namespace {

// The bundled example through pipelines/textured.yaml in `dir`, its model written to `out`
// (and its preview to out/spot.png); `extra` goes on the command line after.
test::CommandResult run_textured_example(const fs::path& dir, const std::string& out, const std::string& extra = {}) {
    return test::run_cli("run " + (test::source_dir() / "pipelines/textured.yaml").string() +
                             " -q --set views.manifest=" + (test::source_dir() / "examples/spot/views.yaml").string() +
                             " --set write.path=" + out + " --set preview.path=out/spot.png" + extra,
                         dir);
}

} // namespace

// The issue's end to end: the bundled example written as .usdz loads in both readers with
// its texture, as many faces and vertices as mesh.write reports.
TEST(UsdReaders, TheBundledExampleAsUsdzLoadsInBothWithItsTexture) {
    std::string why;
    const fs::path modules = test::usd_readers(why);
    if (modules.empty()) GTEST_SKIP() << why;
    test::TempDir dir("usd_spot");
    const auto run = run_textured_example(dir.path(), "out/spot.usdz", " --report run.json");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    double faces = 0, vertices = 0;
    const auto report = nlohmann::json::parse(test::read_text(dir / "run.json"));
    for (const auto& n : report["nodes"])
        if (n["id"] == "write") {
            faces = n["metrics"]["faces"];
            vertices = n["metrics"]["vertices"];
        }
    ASSERT_GT(faces, 1000);
    const fs::path usdz = dir / "out/spot.usdz";
    const auto tiny = test::run_usd_reader(modules, "tinyusdz_load.mjs", usdz, "TINYUSDZ");
    EXPECT_EQ(tiny.value("ok", false), true) << tiny.dump();
    ASSERT_EQ(tiny["meshes"].size(), 1u);
    EXPECT_EQ(tiny["meshes"][0]["faces"], faces);
    ASSERT_EQ(tiny["images"].size(), 1u);
    EXPECT_EQ(tiny["images"][0]["width"], 2048);
    EXPECT_EQ(tiny["images"][0]["decoded"], true);
    const auto three = test::run_usd_reader(modules, "three_load.mjs", usdz, "THREE");
    ASSERT_EQ(three["meshes"].size(), 1u) << three.dump();
    EXPECT_EQ(three["meshes"][0]["faces"], faces);
    EXPECT_EQ(three["meshes"][0]["vertices"], vertices);
    EXPECT_EQ(three["meshes"][0]["uvs"], 3 * faces);
    EXPECT_EQ(three["meshes"][0]["map"]["width"], 2048);
    // 1.5 m tall, as the pipeline asks.
    EXPECT_NEAR(three["max"][1].get<double>() - three["min"][1].get<double>(), 1.5, 1e-5);
}

// A round trip of the bundled example: every corner of every face TinyUSDZ reads from the
// package sits where the same run's .obj puts it, in metres with Y up (the layer says so), and
// the faces' winding as read (USD's right-handed orientation) points out of the closed model:
// its signed volume is positive.
TEST(UsdReaders, TheBundledExamplesPointsReadBackAsWrittenWoundOutward) {
    std::string why;
    const fs::path modules = test::usd_readers(why);
    if (modules.empty()) GTEST_SKIP() << why;
    test::TempDir dir("usd_spot_points");
    for (const char* out : {"out/spot.usdz", "out/spot.obj"}) {
        const auto run = run_textured_example(dir.path(), out);
        ASSERT_EQ(run.exit_code, 0) << run.err;
    }
    const auto tiny = test::run_usd_reader(modules, "tinyusdz_load.mjs", dir / "out/spot.usdz", "TINYUSDZ", "points");
    ASSERT_EQ(tiny["meshes"].size(), 1u) << tiny.value("error", "");
    EXPECT_EQ(tiny["layer"]["metersPerUnit"], "1");
    EXPECT_EQ(tiny["layer"]["upAxis"], "\"Y\"");
    const auto& points = tiny["meshes"][0]["points"];
    const auto& indices = tiny["meshes"][0]["indices"];
    // The .obj's `v` lines and its faces (1-based `v/vt/vn` corners).
    std::vector<std::array<double, 3>> obj;
    std::vector<std::size_t> corners;
    std::istringstream in(test::read_text(dir / "out/spot.obj"));
    for (std::string line; std::getline(in, line);) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            std::array<double, 3> p{};
            ls >> p[0] >> p[1] >> p[2];
            obj.push_back(p);
        } else if (tag == "f") {
            for (int c = 0; c < 3; ++c) {
                std::string corner;
                ls >> corner;
                corners.push_back(std::stoul(corner.substr(0, corner.find('/'))) - 1);
            }
        }
    }
    ASSERT_GT(corners.size(), 3000u);
    ASSERT_EQ(indices.size(), corners.size());
    const auto at = [&](std::size_t c, int k) {
        return points[3 * indices[c].get<std::size_t>() + std::size_t(k)].get<double>();
    };
    double worst = 0;
    for (std::size_t c = 0; c < corners.size(); ++c)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(at(c, k) - obj[corners[c]][std::size_t(k)]));
    EXPECT_LT(worst, 1e-6) << "the largest difference between a corner read from the package and the .obj's";
    double volume = 0;
    for (std::size_t c = 0; c < corners.size(); c += 3)
        volume += (at(c, 0) * (at(c + 1, 1) * at(c + 2, 2) - at(c + 1, 2) * at(c + 2, 1)) -
                   at(c, 1) * (at(c + 1, 0) * at(c + 2, 2) - at(c + 1, 2) * at(c + 2, 0)) +
                   at(c, 2) * (at(c + 1, 0) * at(c + 2, 1) - at(c + 1, 1) * at(c + 2, 0))) /
                  6.0;
    EXPECT_GT(volume, 0.01) << "a cow 1.5 m tall holds well over 10 litres";
}
