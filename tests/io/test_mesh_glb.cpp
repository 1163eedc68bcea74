#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

TEST(Glb, RoundTripsPositionsNormalsUvsColoursAndFaces) {
    test::TempDir dir("glb");
    Mesh m = test::make_sphere({0, 1, 0}, 1.0f, 2);
    m.compute_normals();
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        m.uvs.push_back({float(i % 7) / 7.0f, float(i % 5) / 5.0f});
        m.colors.push_back({0.25f, 0.5f, 0.75f, 1.0f});
    }
    const auto f = dir / "sphere.glb";
    write_mesh(m, f);
    ASSERT_TRUE(std::filesystem::exists(f));
    const Mesh r = read_mesh(f);
    ASSERT_EQ(r.positions.size(), m.positions.size());
    ASSERT_EQ(r.triangles, m.triangles);
    ASSERT_EQ(r.normals.size(), m.normals.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_EQ(r.positions[i], m.positions[i]);
        EXPECT_NEAR(length(r.normals[i] - m.normals[i]), 0.0f, 1e-6f);
    }
    ASSERT_EQ(r.uvs.size(), m.uvs.size());
    ASSERT_EQ(r.colors.size(), m.colors.size());
    for (std::size_t i = 0; i < m.uvs.size(); ++i) {
        EXPECT_NEAR(r.uvs[i][0], m.uvs[i][0], 1e-6f);
        EXPECT_NEAR(r.uvs[i][1], m.uvs[i][1], 1e-6f);
        EXPECT_EQ(r.colors[i], m.colors[i]);
    }
    EXPECT_TRUE(check_mesh(r).closed_manifold());
    // The file is glTF binary: magic "glTF", version 2.
    const std::string bytes = test::read_text(f);
    ASSERT_GE(bytes.size(), 12u);
    EXPECT_EQ(bytes.substr(0, 4), "glTF");
    EXPECT_EQ(int(static_cast<unsigned char>(bytes[4])), 2);
}

TEST(Glb, NormalsCanBeLeftOut) {
    test::TempDir dir("glb_nonormals");
    Mesh m = test::make_box({0, 0, 0}, {1, 2, 3});
    m.compute_normals();
    MeshWriteOptions o;
    o.normals = false;
    write_mesh(m, dir / "box.glb", o);
    const Mesh r = read_mesh(dir / "box.glb");
    EXPECT_TRUE(r.normals.empty());
    EXPECT_EQ(r.face_count(), 12u);
    EXPECT_NEAR(check_mesh(r).signed_volume, 6.0, 1e-6);
}

TEST(Glb, BadFileIsAnErrorNamingIt) {
    test::TempDir dir("glb_bad");
    test::write_text(dir / "broken.glb", "not a gltf file at all");
    try {
        read_mesh(dir / "broken.glb");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("broken.glb"), std::string::npos) << e.what();
    }
}
