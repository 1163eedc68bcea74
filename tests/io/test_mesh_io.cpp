#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "io/mesh_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;

TEST(MeshIO, EveryFormatRoundTrips) {
    test::TempDir dir("meshio");
    Mesh m = test::make_sphere({0, 1, 0}, 1.0f, 2);
    m.compute_normals();
    for (const char* ext : {".obj", ".ply", ".stl", ".off"}) {
        SCOPED_TRACE(ext);
        const auto f = dir / (std::string("sphere") + ext);
        write_mesh(m, f);
        const Mesh r = read_mesh(f);
        EXPECT_EQ(r.face_count(), m.face_count());
        const MeshCheck c = check_mesh(r);
        EXPECT_TRUE(c.closed_manifold());
        EXPECT_NEAR(c.signed_volume, check_mesh(m).signed_volume, 1e-4);
    }
}

// Every text format reads back the very floats written: near an axis plane coordinates are
// small, and fixed notation with nine decimals put three vertices of a sliver (z differing by
// 1e-10) onto one line, so the face read back was degenerate.
TEST(MeshIO, TextFormatsKeepEveryFloatExactly) {
    test::TempDir dir("meshio-exact");
    Mesh m = test::make_box({-1, -1, -1}, {1, 1, 1});
    // Small, close coordinates: a vertex on each side of z = 0, a hair apart.
    m.positions[0] = {-1.0f, 0.828392506f, -0.000444547f};
    m.positions[1] = {std::nextafter(-0.000444547f, 0.0f), 3.1e-12f, std::nextafter(1e-30f, 1.0f)};
    m.compute_normals();
    for (bool binary : {false, true})
        for (const char* ext : {".obj", ".ply", ".off"}) {
            SCOPED_TRACE(std::string(ext) + (binary ? " binary" : " text"));
            const auto f = dir / (std::string("box") + ext);
            MeshWriteOptions wo;
            wo.binary = binary;
            write_mesh(m, f, wo);
            const Mesh r = read_mesh(f);
            ASSERT_EQ(r.positions.size(), m.positions.size());
            for (std::size_t v = 0; v < m.positions.size(); ++v)
                for (int k = 0; k < 3; ++k) EXPECT_EQ(r.positions[v][k], m.positions[v][k]) << "vertex " << v;
        }
}

TEST(MeshIO, ReadsTheSharedModels) {
    CM_SKIP_WITHOUT(test::shared_dir() / "data/models");
    for (const char* name : {"spot.obj", "bunny00.off", "fandisk.off"}) {
        SCOPED_TRACE(name);
        const Mesh m = read_mesh(test::shared_dir() / "data/models" / name);
        EXPECT_GT(m.face_count(), 1000u);
        EXPECT_TRUE(check_mesh(m).closed_manifold());
    }
}

TEST(MeshIO, ClearErrors) {
    test::TempDir dir("meshio-bad");
    try {
        read_mesh(dir / "missing.obj");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.obj"), std::string::npos);
    }
    test::write_text(dir / "junk.off", "this is not a mesh\n");
    EXPECT_THROW(read_mesh(dir / "junk.off"), Error);
    EXPECT_THROW(write_mesh(test::make_box({0, 0, 0}, {1, 1, 1}), dir / "x.xyz"), Error);
}
