#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "support/shapes.h"
#include "support/test_support.h"

namespace cm {
Stage* make_volume_write();
}

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

ParamSet params(const std::filesystem::path& path) {
    ParamSet p;
    p.set("path", path.string());
    p.set("grid_name", std::string("surface"));
    p.set("half_width", std::int64_t(3));
    p.set("smoothing_steps", std::int64_t(0));
    p.set("occupancy", true);
    return p;
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
    std::unique_ptr<Stage> st(make_volume_write());
    const auto out = dir / "hull.vdb";
    st->prepare(params(out));
    Inputs in;
    in.set("volume", box_volume());
    Context ctx("vdb", "volume.write", {});
    auto res = std::get<std::shared_ptr<const FileOutput>>(st->run(in, ctx));
    ASSERT_EQ(res->paths.size(), 1u);
    // The host renames the temporary file; here, find it beside the final name.
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
    EXPECT_LT(sample(*grid, 0, 0, 0), 0.0);                   // inside
    EXPECT_GT(sample(*grid, 2, 0, 0), 0.0);                   // outside
    EXPECT_NEAR(sample(*grid, 1.05, 0.2, -0.3), 0.0, 0.06);  // on the face
    EXPECT_NEAR(sample(*grid, 0.85, 0.0, 0.0), -0.2, 0.06);
}

TEST(VolumeWrite, MeshSourceKeepsTheSubVoxelSurface) {
    test::TempDir dir("volume_write_mesh");
    std::unique_ptr<Stage> st(make_volume_write());
    auto p = params(dir / "hull.vdb");
    p.set("occupancy", false);
    st->prepare(p);
    Inputs in;
    in.set("volume", box_volume());
    // A surface between voxel faces: the level set must follow it, not the voxels.
    in.set("mesh", std::make_shared<const Mesh>(test::make_box({-1.02f, -1.02f, -1.02f}, {1.02f, 1.02f, 1.02f})));
    Context ctx("vdb", "volume.write", {});
    st->run(in, ctx);
    std::filesystem::path written;
    for (auto& e : std::filesystem::directory_iterator(dir.path())) written = e.path();
    auto grid = read_level_set(written, false);
    ASSERT_TRUE(grid);
    EXPECT_NEAR(sample(*grid, 1.02, 0.1, 0.1), 0.0, 0.01);
    EXPECT_NEAR(sample(*grid, 0.92, 0.0, 0.0), -0.1, 0.01);
    EXPECT_NEAR(sample(*grid, 1.12, 0.0, 0.0), 0.1, 0.01);
}

TEST(VolumeWrite, RefusesOtherExtensions) {
    std::unique_ptr<Stage> st(make_volume_write());
    EXPECT_THROW(st->prepare(params("hull.obj")), Error);
}
