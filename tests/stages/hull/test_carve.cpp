// hull.carve on analytic shapes whose visual hull is known exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "carve.h"
#include "core/stage.h"
#include "support/shapes.h"
#include "support/stage_harness.h"

using namespace cm;
using namespace cm::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::shared_ptr<Views> sphere_views(double r, int size, double scale) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) vs.push_back(ortho_view(n, size, scale, sphere_outline(r)));
    return make_views(std::move(vs), {-r, -r, -r}, {r, r, r});
}

std::shared_ptr<Views> box_views(Vec3d lo, Vec3d hi, int size, double scale) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) {
        const Camera c = *Camera::named(n);
        vs.push_back(ortho_view(n, size, scale, box_outline(lo, hi, c.d)));
    }
    return make_views(std::move(vs), lo, hi);
}

// Every grid point agrees with the analytic test (away from the boundary by `margin`).
template <typename Inside>
void expect_points_match(const Volume& v, Inside inside, double margin, std::size_t& checked) {
    const auto& xf = v.transform();
    auto acc = v.occupancy->getConstAccessor();
    openvdb::CoordBBox box;
    v.occupancy->tree().evalActiveVoxelBoundingBox(box);
    box.expand(2);
    const int step = std::max(1, box.dim().x() / 40);
    for (int i = box.min().x(); i <= box.max().x(); i += step)
        for (int j = box.min().y(); j <= box.max().y(); j += step)
            for (int k = box.min().z(); k <= box.max().z(); ++k) {
                const auto w = xf.indexToWorld(openvdb::Coord(i, j, k));
                const int truth = inside(Vec3d{w.x(), w.y(), w.z()}, margin);
                if (truth == 0) continue; // too close to the boundary to call
                ++checked;
                ASSERT_EQ(acc.isValueOn(openvdb::Coord(i, j, k)), truth > 0) << "at " << i << "," << j << "," << k;
            }
}

} // namespace

// Sphere of radius r seen from three axis views: the hull is the Steinmetz tricylinder,
// volume 8 (2 - sqrt 2) r^3.
TEST(HullCarve, SphereFromThreeAxisViewsIsTheTricylinder) {
    const double r = 1.0;
    auto views = sphere_views(r, 320, 150.0);
    const double exact = 8.0 * (2.0 - std::sqrt(2.0)) * r * r * r;
    for (int res : {32, 64, 128}) {
        CarveOptions opt;
        opt.resolution = res;
        auto vol = carve(views, opt).value;
        const double h = vol->voxel_size();
        EXPECT_NEAR(h, 2.0 * r / res, 1e-12);
        // Counting grid points: the error is a layer of about half a cell over the surface.
        const double area = 3 * 8 * (2 - std::sqrt(2.0)) * r * r; // tricylinder surface 24 (2 - sqrt 2) r^2
        EXPECT_NEAR(counted_volume(*vol), exact, 0.5 * area * h) << "resolution " << res;
        std::size_t checked = 0;
        expect_points_match(
            *vol,
            [&](const Vec3d& p, double m) {
                const double d = std::max({std::hypot(p.y, p.z), std::hypot(p.x, p.z), std::hypot(p.x, p.y)});
                return d < r - m ? 1 : (d > r + m ? -1 : 0);
            },
            0.01 * r, checked);
        EXPECT_GT(checked, 1000u);
    }
}

TEST(HullCarve, BoxIsExact) {
    const Vec3d lo{-1.0, -0.5, -0.25}, hi{1.0, 0.75, 0.5};
    auto views = box_views(lo, hi, 300, 120.0);
    CarveOptions opt;
    opt.resolution = 40; // h = 0.05: the faces fall between grid points
    auto vol = carve(views, opt).value;
    std::size_t checked = 0;
    expect_points_match(
        *vol,
        [&](const Vec3d& p, double m) {
            bool in = true, out = false;
            for (int k = 0; k < 3; ++k) {
                in = in && p[k] > lo[k] + m && p[k] < hi[k] - m;
                out = out || p[k] < lo[k] - m || p[k] > hi[k] + m;
            }
            return in ? 1 : (out ? -1 : 0);
        },
        1e-3, checked);
    EXPECT_GT(checked, 1000u);
}

// An L extruded along Z: the front view shows the notch, so the hull keeps it.
TEST(HullCarve, VisibleConcavityOfAnLShapeIsCarved) {
    const Vec3d a0{-1, -1, -0.5}, a1{1, 0, 0.5}, b0{-1, 0, -0.5}, b1{0, 1, 0.5};
    std::vector<View> vs;
    vs.push_back(ortho_view("front", 320, 120.0,
                            union_outline(box_outline(a0, a1, {0, 0, -1}), box_outline(b0, b1, {0, 0, -1}))));
    vs.push_back(ortho_view("right", 320, 120.0, box_outline({-1, -1, -0.5}, {1, 1, 0.5}, {-1, 0, 0})));
    vs.push_back(ortho_view("top", 320, 120.0, box_outline({-1, -1, -0.5}, {1, 1, 0.5}, {0, -1, 0})));
    auto views = make_views(std::move(vs), {-1, -1, -0.5}, {1, 1, 0.5});
    CarveOptions opt;
    opt.resolution = 64;
    auto vol = carve(views, opt).value;
    const double h = vol->voxel_size();
    EXPECT_NEAR(counted_volume(*vol), 3.0, 0.5 * 14.0 * h); // area of the L prism: 14
    auto acc = vol->occupancy->getConstAccessor();
    const auto inside = [&](double x, double y, double z) {
        const auto ijk = vol->transform().worldToIndexNodeCentered(openvdb::Vec3d(x, y, z));
        return acc.isValueOn(ijk);
    };
    EXPECT_TRUE(inside(-0.5, 0.5, 0.0));
    EXPECT_TRUE(inside(0.5, -0.5, 0.0));
    EXPECT_FALSE(inside(0.5, 0.5, 0.0)); // the notch
}

// A cube with one octant removed: every axis view still shows a full square, so the
// hull fills the notch (a visual hull cannot see a concavity no view shows).
TEST(HullCarve, HiddenConcavityIsFilled) {
    const Vec3d lo{-1, -1, -1}, hi{1, 1, 1};
    auto views = box_views(lo, hi, 300, 120.0); // the notched cube's three silhouettes are squares
    CarveOptions opt;
    opt.resolution = 32;
    auto vol = carve(views, opt).value;
    auto acc = vol->occupancy->getConstAccessor();
    const auto ijk = vol->transform().worldToIndexNodeCentered(openvdb::Vec3d(0.5, 0.5, 0.5));
    EXPECT_TRUE(acc.isValueOn(ijk)); // inside the removed octant
    const double h = vol->voxel_size();
    EXPECT_NEAR(counted_volume(*vol), 8.0, 0.5 * 24.0 * h); // the cube, not the 7 of the object
}

// Interior as tiles, leaves only at the surface: leaf voxels grow like N^2, not N^3.
TEST(HullCarve, LeavesGrowWithTheSurface) {
    auto views = sphere_views(1.0, 600, 280.0);
    std::vector<double> leaves;
    for (int res : {64, 128, 256}) {
        CarveOptions opt;
        opt.resolution = res;
        auto vol = carve(views, opt).value;
        const auto& tree = vol->occupancy->tree();
        EXPECT_GT(tree.activeTileCount(), 0u) << res;
        const double leaf_voxels = double(tree.leafCount()) * 512.0;
        // A leaf is 8^3 voxels, so each leaf voxel of the surface band costs about 8 of its
        // neighbours: a dozen leaf voxels per unit of surface (in cells) at most.
        const double area_cells = 24 * (2 - std::sqrt(2.0)) * (res / 2.0) * (res / 2.0);
        EXPECT_LT(leaf_voxels, 12 * area_cells) << res;
        leaves.push_back(leaf_voxels);
        // Every inside point with an outside neighbour is a leaf voxel (volume.h).
        std::size_t in_tiles_at_surface = 0;
        for (auto it = tree.cbeginValueOn(); it; ++it) {
            if (it.isVoxelValue()) continue;
            openvdb::CoordBBox b;
            it.getBoundingBox(b);
            b.expand(1);
            const openvdb::Coord mid((b.min().x() + b.max().x()) / 2, (b.min().y() + b.max().y()) / 2,
                                     (b.min().z() + b.max().z()) / 2);
            for (int a = 0; a < 3; ++a)
                for (int e : {b.min()[a], b.max()[a]}) {
                    openvdb::Coord c = mid; // face centres
                    c[a] = e;
                    in_tiles_at_surface += !tree.isValueOn(c);
                }
            for (int k = 0; k < 8; ++k) // corners
                in_tiles_at_surface += !tree.isValueOn(openvdb::Coord((k & 1) ? b.max().x() : b.min().x(),
                                                                      (k & 2) ? b.max().y() : b.min().y(),
                                                                      (k & 4) ? b.max().z() : b.min().z()));
        }
        EXPECT_EQ(in_tiles_at_surface, 0u) << res;
    }
    EXPECT_GT(leaves[1] / leaves[0], 2.5);
    EXPECT_LT(leaves[1] / leaves[0], 5.5);
    EXPECT_GT(leaves[2] / leaves[1], 2.5);
    EXPECT_LT(leaves[2] / leaves[1], 5.5);
}

TEST(HullCarve, PerspectiveViewsOfASphere) {
    const Vec3d c{0.2, -0.1, 0.3};
    const double r = 1.0, f = 500;
    std::vector<View> vs = perspective_sphere_ring(c, r, f);
    auto views = std::make_shared<Views>();
    views->views = std::move(vs);
    views->calibrated = true; // no bounds: the box is estimated from the cameras
    CarveOptions opt;
    opt.resolution = 64;
    const auto carved_vol = carve(views, opt);
    const auto& vol = carved_vol.value;
    const CarveStats& st = carved_vol.stats;
    EXPECT_TRUE(st.box_estimated);
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(st.box_min[a], c[a] - r);
        EXPECT_GT(st.box_max[a], c[a] + r);
        EXPECT_LT(st.box_max[a] - st.box_min[a], 4 * r); // not the whole camera rig
    }
    // The hull holds the sphere and is bounded by the cones.
    std::size_t checked = 0;
    expect_points_match(
        *vol,
        [&](const Vec3d& p, double m) {
            if (length(p - c) < r - m) return 1;
            for (const auto& v : views->views) {
                const Vec3d e = v.camera.center();
                const double ang = std::acos(std::clamp(dot(normalize(p - e), normalize(c - e)), -1.0, 1.0));
                if (ang > std::asin(r / length(c - e)) + m / length(c - e)) return -1;
            }
            return 0;
        },
        0.03, checked);
    EXPECT_GT(checked, 1000u);
    EXPECT_GT(counted_volume(*vol), 4.0 / 3.0 * kPi * 0.9);
}

// resolution and voxel_ratio are two ways to say one thing: they give the same grid.
TEST(HullCarve, ResolutionParametersAgree) {
    const double scale = 150.0; // px per unit; the box is 2 units: 300 px
    auto views = sphere_views(1.0, 320, scale);
    for (double ratio : {4.0, 8.0, 2.5}) {
        CarveOptions a;
        a.voxel_ratio = ratio;
        const auto carved_va = carve(views, a);
        const auto& va = carved_va.value;
        const CarveStats& sa = carved_va.stats;
        EXPECT_EQ(sa.resolution, int(std::lround(2.0 * scale / ratio)));
        CarveOptions b;
        b.resolution = sa.resolution;
        auto vb = carve(views, b).value;
        EXPECT_DOUBLE_EQ(va->voxel_size(), vb->voxel_size());
        EXPECT_EQ(va->occupancy->activeVoxelCount(), vb->occupancy->activeVoxelCount());
    }
    EXPECT_EQ(resolution_from_ratio(*views, {-1, -1, -1}, {1, 1, 1}, 4.0), 75);
}

// voxel_ratio decides when both are given (a pipeline file may name a resolution and
// the command line add --set hull.voxel_ratio=...), and the stage says so.
TEST(HullCarve, StageLetsVoxelRatioDecide) {
    test::StageHarness st("hull.carve");
    st.params("{resolution: 128, voxel_ratio: 4}");
    st.input("views", sphere_views(1.0, 320, 150.0));
    st.run<Volume>();
    EXPECT_EQ(std::stod(st.metrics().at("resolution")), 75.0); // 300 px / 4
    ASSERT_EQ(st.warnings().size(), 1u);
    EXPECT_NE(st.warnings()[0].find("voxel_ratio"), std::string::npos) << st.warnings()[0];
}

TEST(HullCarve, StageReportsMetrics) {
    test::StageHarness st("hull.carve");
    st.params("{resolution: 48}");
    st.input("views", sphere_views(1.0, 200, 90.0));
    auto vol = st.run<Volume>();
    ASSERT_TRUE(vol && vol->occupancy);
    const auto& m = st.metrics();
    for (const char* k : {"resolution", "voxel_size", "active_voxels", "active_tiles", "leaf_count", "grid_bytes"})
        EXPECT_TRUE(m.count(k)) << k;
    EXPECT_EQ(std::stod(m.at("resolution")), 48.0);
}

TEST(HullCarve, EmptyInputIsAClearError) {
    auto empty = std::make_shared<Views>();
    try {
        carve(empty, {});
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no view"), std::string::npos) << e.what();
    }
    // Two views whose silhouettes cannot both hold one object: an empty hull.
    std::vector<View> vs;
    vs.push_back(ortho_view("front", 200, 50.0, box_outline({-1.8, -1, -1}, {-1.2, 1, 1}, {0, 0, -1})));
    vs.push_back(ortho_view("top", 200, 50.0, box_outline({1.2, -1, -1}, {1.8, 1, 1}, {0, -1, 0})));
    try {
        carve(make_views(std::move(vs), {-2, -1, -1}, {2, 1, 1}), {});
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("hull is empty"), std::string::npos) << e.what();
    }
}

TEST(HullCarve, CancelStopsTheCarve) {
    auto views = sphere_views(1.0, 200, 90.0);
    CarveOptions opt;
    opt.resolution = 128;
    int calls = 0;
    EXPECT_THROW(carve(views, opt, nullptr, Progress([&](double) {
                           if (++calls == 2) throw Cancelled();
                       })),
                 Cancelled);
}
