// The USD writer's layer and package read back without a USD library: the layer's text
// parsed here (support/usd_layer.h), the package's zip by hand and by Python's zipfile. The
// npm readers open the same files in tests/stages/write/test_mesh_write_usd.cpp.
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/error.h"
#include "core/mesh.h"
#include "core/views.h"
#include "geometry/mesh_check.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "io/usd_io.h"
#include "support/shapes.h"
#include "support/test_support.h"
#include "support/usd_layer.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

// A sphere with every per-vertex attribute the layer can hold.
Mesh full_sphere() {
    Mesh m = test::make_sphere({0.25f, 1.0f, -0.5f}, 1.0f, 2);
    m.compute_normals();
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        m.uvs.push_back({float(i % 7) / 7.0f, float(i % 5) / 5.0f});
        m.colors.push_back({0.25f, float(i % 3) / 3.0f, 0.75f, 1.0f});
    }
    return m;
}

} // namespace

TEST(Usd, LayerHoldsThePointsTrianglesNormalsUvsAndColoursAsWritten) {
    test::TempDir dir("usd_layer");
    const Mesh m = full_sphere();
    write_mesh(m, dir / "ball.usda");
    const std::string layer = test::read_text(dir / "ball.usda");
    ASSERT_EQ(layer.substr(0, 10), "#usda 1.0\n");
    // Points and faces read back are the very floats and indices written.
    const Mesh back = test::usd_mesh(layer);
    ASSERT_EQ(back.positions.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) EXPECT_EQ(back.positions[i], m.positions[i]) << i;
    EXPECT_EQ(back.triangles, m.triangles);
    EXPECT_EQ(test::usd_numbers(layer, "int[] faceVertexCounts").size(), m.triangles.size());
    const auto n = test::usd_numbers(layer, "normal3f[] normals");
    ASSERT_EQ(n.size(), 3 * m.normals.size());
    for (std::size_t i = 0; i < m.normals.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(float(n[3 * i + std::size_t(k)]), m.normals[i][k]);
    // Per-vertex UVs stay per vertex and v up, as USD's st.
    const auto st = test::usd_numbers(layer, "texCoord2f[] primvars:st");
    ASSERT_EQ(st.size(), 2 * m.uvs.size());
    for (std::size_t i = 0; i < m.uvs.size(); ++i) {
        EXPECT_EQ(float(st[2 * i]), m.uvs[i][0]);
        EXPECT_EQ(float(st[2 * i + 1]), m.uvs[i][1]);
    }
    EXPECT_TRUE(test::usd_has(layer, "texCoord2f[] primvars:st = [(0, 0), ") &&
                test::usd_has(layer, ")] (\n            interpolation = \"vertex\"\n        )\n"));
    const auto c = test::usd_numbers(layer, "color3f[] primvars:displayColor");
    ASSERT_EQ(c.size(), 3 * m.colors.size());
    for (std::size_t i = 0; i < m.colors.size(); ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(float(c[3 * i + std::size_t(k)]), m.colors[i][std::size_t(k)]);
    EXPECT_FALSE(test::usd_has(layer, "displayOpacity")); // all opaque
    // The extent is the points' box.
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const auto e = test::usd_numbers(layer, "float3[] extent");
    ASSERT_EQ(e.size(), 6u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(float(e[std::size_t(k)]), lo[k]);
        EXPECT_EQ(float(e[3 + std::size_t(k)]), hi[k]);
    }
    // No texture: no material.
    EXPECT_FALSE(test::usd_has(layer, "Material"));
    EXPECT_FALSE(test::usd_has(layer, "material:binding"));
}

TEST(Usd, ColoursNotOpaqueGiveADisplayOpacity) {
    test::TempDir dir("usd_opacity");
    Mesh m = test::make_box({0, 0, 0}, {1, 1, 1});
    for (std::size_t i = 0; i < m.positions.size(); ++i) m.colors.push_back({1, 0, 0, i == 3 ? 0.5f : 1.0f});
    write_mesh(m, dir / "glass.usda");
    const std::string layer = test::read_text(dir / "glass.usda");
    EXPECT_TRUE(test::usd_has(layer,
                              "float[] primvars:displayOpacity = [1, 1, 1, 0.5, 1, 1, 1, 1] (\n"
                              "            interpolation = \"vertex\"\n"));
}

TEST(Usd, LayerStatesItsUnitsUpAxisKindAndNoSubdivision) {
    test::TempDir dir("usd_units");
    write_mesh(test::make_box({0, 0, 0}, {1, 2, 3}), dir / "crate.usda");
    const std::string layer = test::read_text(dir / "crate.usda");
    EXPECT_EQ(test::usd_value(layer, "defaultPrim"), "\"crate\"");
    EXPECT_EQ(test::usd_value(layer, "upAxis"), "\"Y\"");
    EXPECT_EQ(test::usd_value(layer, "metersPerUnit"), "1");
    EXPECT_EQ(test::usd_value(layer, "string creator"), "\"conceptmesh " CONCEPTMESH_VERSION_STRING "\"");
    EXPECT_TRUE(test::usd_has(layer, "def Xform \"crate\" (\n    kind = \"component\"\n)\n{\n    def Mesh \"mesh\""));
    // Catmull-Clark, USD's default, would smooth the mesh and ignore its normals.
    EXPECT_EQ(test::usd_value(layer, "uniform token subdivisionScheme"), "\"none\"");
    EXPECT_EQ(test::usd_value(layer, "uniform token orientation"), "\"rightHanded\"");
}

// USD's rightHanded: a face's vertices go counter-clockwise seen from the side its normal
// points to. Every face of a closed outward mesh must so point away from the inside.
TEST(Usd, EveryFaceIsWoundOutwardInUsdsRightHandedOrientation) {
    test::TempDir dir("usd_winding");
    const Vec3f centre(0.25f, 1.0f, -0.5f);
    write_mesh(test::make_sphere(centre, 1.0f, 3), dir / "ball.usda");
    const Mesh back = test::usd_mesh(test::read_text(dir / "ball.usda"));
    ASSERT_FALSE(back.triangles.empty());
    for (const auto& t : back.triangles) {
        const Vec3f a = back.positions[t[0]], b = back.positions[t[1]], c = back.positions[t[2]];
        const Vec3f winding = cross(b - a, c - a);
        EXPECT_GT(dot(winding, (a + b + c) * (1.0f / 3.0f) - centre), 0.0f);
    }
    EXPECT_GT(check_mesh(back).signed_volume, 0.0);
}

TEST(Usd, PerCornerUvsAreFaceVaryingAndTheTextureABoundPreviewSurface) {
    test::TempDir dir("usd_textured");
    const Mesh m = test::make_textured_box({-1, 0, -1}, {1, 2, 1});
    write_mesh(m, dir / "crate.usda");
    const std::string layer = test::read_text(dir / "crate.usda");
    const auto st = test::usd_numbers(layer, "texCoord2f[] primvars:st");
    ASSERT_EQ(st.size(), 2 * m.corner_uvs.size());
    for (std::size_t i = 0; i < m.corner_uvs.size(); ++i) {
        EXPECT_EQ(float(st[2 * i]), m.corner_uvs[i][0]);
        EXPECT_EQ(float(st[2 * i + 1]), m.corner_uvs[i][1]); // not flipped: v up in both
    }
    EXPECT_TRUE(test::usd_has(layer, ")] (\n            interpolation = \"faceVarying\"\n        )\n"));
    EXPECT_TRUE(test::usd_has(layer, "def Mesh \"mesh\" (\n        prepend apiSchemas = [\"MaterialBindingAPI\"]\n"));
    EXPECT_EQ(test::usd_value(layer, "rel material:binding"), "</crate/mtl/crate>");
    EXPECT_EQ(test::usd_value(layer, "token outputs:surface.connect"), "</crate/mtl/crate/surface.outputs:surface>");
    EXPECT_TRUE(test::usd_has(layer, "uniform token info:id = \"UsdPreviewSurface\""));
    EXPECT_EQ(test::usd_value(layer, "color3f inputs:diffuseColor.connect"), "</crate/mtl/crate/texture.outputs:rgb>");
    EXPECT_EQ(test::usd_value(layer, "float inputs:roughness"), "1");
    EXPECT_EQ(test::usd_value(layer, "float inputs:metallic"), "0");
    EXPECT_TRUE(test::usd_has(layer, "uniform token info:id = \"UsdUVTexture\""));
    EXPECT_EQ(test::usd_value(layer, "asset inputs:file"), "@./crate_basecolor.png@");
    EXPECT_EQ(test::usd_value(layer, "token inputs:sourceColorSpace"), "\"sRGB\"");
    EXPECT_EQ(test::usd_value(layer, "float2 inputs:st.connect"), "</crate/mtl/crate/uv.outputs:result>");
    EXPECT_TRUE(test::usd_has(layer, "uniform token info:id = \"UsdPrimvarReader_float2\""));
    EXPECT_EQ(test::usd_value(layer, "string inputs:varname"), "\"st\"");
    // The texture beside the layer, under the name it refers to.
    const Image png = read_image(dir / "crate_basecolor.png");
    EXPECT_EQ(png.width, m.texture->width);
    EXPECT_EQ(png.height, m.texture->height);
    EXPECT_NEAR(png.at(1, 1, 0), m.texture->at(1, 1, 0), 1.0 / 255);
}

// The package USDZ asks for: the layer first, every file stored and 64-byte aligned; the
// layer in it is the .usda of the same mesh, byte for byte.
TEST(Usdz, PackageHoldsTheLayerThenItsTextureStoredAndAligned) {
    test::TempDir dir("usdz");
    const Mesh m = test::make_textured_box({-1, 0, -1}, {1, 2, 1});
    write_mesh(m, dir / "crate.usdz");
    fs::create_directories(dir / "text");
    write_mesh(m, dir / "text" / "crate.usda");
    const std::string bytes = test::read_text(dir / "crate.usdz");
    const std::vector<test::ZipFile> files = test::read_zip(bytes);
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files[0].name, "crate.usda");
    EXPECT_EQ(files[1].name, "crate_basecolor.png");
    for (const auto& f : files) {
        EXPECT_EQ(f.method, 0) << f.name << " must be stored, not compressed";
        EXPECT_EQ(f.data_offset % 64, 0u) << f.name;
    }
    EXPECT_EQ(files[0].header_offset, 0u);
    EXPECT_EQ(files[0].data, test::read_text(dir / "text" / "crate.usda"));
    EXPECT_EQ(files[1].data, test::read_text(dir / "text" / "crate_basecolor.png"));
    // Equal meshes give equal packages (no timestamps).
    write_mesh(m, dir / "again.usdz");
    const std::vector<test::ZipFile> again = test::read_zip(test::read_text(dir / "again.usdz"));
    ASSERT_EQ(again.size(), 2u);
    EXPECT_EQ(again[0].name, "again.usda");
    EXPECT_EQ(again[1].data, files[1].data);
}

// Python's zipfile, a reader that is not ours, checks every CRC and reads every file.
TEST(Usdz, PythonsZipfileFindsEveryCrcRight) {
    if (std::system("python3 -c 'import zipfile' > /dev/null 2>&1") != 0) GTEST_SKIP() << "python3 is not installed";
    test::TempDir dir("usdz_python");
    write_mesh(test::make_textured_box({-1, 0, -1}, {1, 2, 1}), dir / "crate.usdz");
    write_mesh(full_sphere(), dir / "ball.usdz");
    for (const char* name : {"crate.usdz", "ball.usdz"}) {
        const fs::path out = dir / (std::string(name) + ".txt");
        const std::string cmd =
            "python3 -c 'import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); "
            "print(z.testzip(), [(i.filename, i.compress_type, i.file_size) for i in "
            "z.infolist()])' '" +
            (dir / name).string() + "' > '" + out.string() + "' 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << test::read_text(out);
        EXPECT_EQ(test::read_text(out).substr(0, 5), "None ") << test::read_text(out);
    }
    EXPECT_HAS(test::read_text(dir / "ball.usdz.txt"), "[('ball.usda', 0, ");
}

TEST(Usd, PrimNamesAreIdentifiersMadeFromTheFileName) {
    EXPECT_EQ(usd_identifier("spot"), "spot");
    EXPECT_EQ(usd_identifier("my model-2"), "my_model_2");
    EXPECT_EQ(usd_identifier("3d"), "_3d");
    EXPECT_EQ(usd_identifier(""), "_");
    EXPECT_EQ(usd_identifier("vache\xc3\xa9"), "vache__");
    test::TempDir dir("usd_names");
    write_mesh(test::make_box({0, 0, 0}, {1, 1, 1}), dir / "2 boxes.usda");
    const std::string layer = test::read_text(dir / "2 boxes.usda");
    EXPECT_EQ(test::usd_value(layer, "defaultPrim"), "\"_2_boxes\"");
}

TEST(Usd, IsWrittenNotRead) {
    test::TempDir dir("usd_read");
    write_mesh(test::make_box({0, 0, 0}, {1, 1, 1}), dir / "box.usda");
    EXPECT_TRUE(mesh_format_supported(dir / "box.USDZ"));
    EXPECT_FALSE(mesh_readable(dir / "box.usda"));
    EXPECT_HAS(test::error_of([&] { read_mesh(dir / "box.usda"); }), "unknown format");
}
