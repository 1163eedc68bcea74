#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;

namespace {

std::shared_ptr<const Volume> box_volume() {
    openvdb::initialize();
    auto v = std::make_shared<Volume>();
    v->occupancy = openvdb::BoolGrid::create(false);
    v->occupancy->setTransform(openvdb::math::Transform::createLinearTransform(0.1));
    // Grid points -10..10: the inside reaches half a voxel further, to +-1.05.
    v->occupancy->sparseFill(openvdb::CoordBBox(openvdb::Coord(-10), openvdb::Coord(10)), true, true);
    return v;
}

// volume.write with every parameter given.
void set_params(test::StageHarness& h, const std::filesystem::path& path) {
    h.param("path", path);
    h.params("{grid_name: surface, half_width: 3, smoothing_steps: 0, occupancy: true}");
}

openvdb::FloatGrid::Ptr read_level_set(const std::filesystem::path& f, bool expect_occupancy) {
    openvdb::io::File file(f.string());
    file.open();
    auto grids = file.getGrids();
    EXPECT_EQ(grids->size(), expect_occupancy ? 2u : 1u);
    auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
    file.close();
    return g;
}

double sample(const openvdb::FloatGrid& g, double x, double y, double z) {
    openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> s(g);
    return s.wsSample(openvdb::Vec3d(x, y, z));
}

} // namespace

TEST(VolumeWrite, OccupancyBecomesALevelSetThatReadsBack) {
    test::TempDir dir("volume_write");
    test::StageHarness h("volume.write");
    const auto out = dir / "hull.vdb";
    set_params(h, out);
    h.input("volume", box_volume());
    auto res = h.run<FileOutput>();
    ASSERT_EQ(res->paths.size(), 1u);
    // The file the stage wrote, committed under its final name: the only one in the folder.
    std::filesystem::path written;
    for (auto& e : std::filesystem::directory_iterator(dir.path())) written = e.path();
    ASSERT_FALSE(written.empty());
    openvdb::io::File file(written.string());
    file.open();
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
    auto occ = file.readGrid("occupancy");
    file.close();
    ASSERT_TRUE(grid);
    ASSERT_TRUE(occ);
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_NEAR(grid->voxelSize()[0], 0.1, 1e-12);
    EXPECT_LT(sample(*grid, 0, 0, 0), 0.0);                 // inside
    EXPECT_GT(sample(*grid, 2, 0, 0), 0.0);                 // outside
    EXPECT_NEAR(sample(*grid, 1.05, 0.2, -0.3), 0.0, 0.06); // on the face
    EXPECT_NEAR(sample(*grid, 0.85, 0.0, 0.0), -0.2, 0.06);
}

TEST(VolumeWrite, MeshSourceKeepsTheSubVoxelSurface) {
    test::TempDir dir("volume_write_mesh");
    test::StageHarness h("volume.write");
    set_params(h, dir / "hull.vdb");
    h.params("{occupancy: false}");
    h.input("volume", box_volume());
    // A surface between voxel faces: the level set must follow it, not the voxels.
    h.input("mesh", test::make_box({-1.02f, -1.02f, -1.02f}, {1.02f, 1.02f, 1.02f}));
    h.run<FileOutput>();
    std::filesystem::path written;
    for (auto& e : std::filesystem::directory_iterator(dir.path())) written = e.path();
    auto grid = read_level_set(written, false);
    ASSERT_TRUE(grid);
    EXPECT_NEAR(sample(*grid, 1.02, 0.1, 0.1), 0.0, 0.01);
    EXPECT_NEAR(sample(*grid, 0.92, 0.0, 0.0), -0.1, 0.01);
    EXPECT_NEAR(sample(*grid, 1.12, 0.0, 0.0), 0.1, 0.01);
}

TEST(VolumeWrite, RefusesOtherExtensions) {
    test::StageHarness h("volume.write");
    set_params(h, "hull.obj");
    EXPECT_THROW(h.configure(), Error);
}
