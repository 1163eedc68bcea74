// The crossing guard of Dual Marching Cubes: where the crossings' normals disagree with the
// surface (a thin part, a wobbly drawn outline), QEF minima stray from their discs and the
// dual mesh crosses itself; the extractor removes those faces itself.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dual_mc.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "sdf_volume.h"

using namespace cm;
using namespace cm::test;

namespace {

/// A gyroid of period `period` cells in a box (thin parts and saddles, cells the surface
/// passes twice), its stored normals turned at random by about `noise` radians (the views'
/// normals at a drawn outline's wobble are off so).
Volume noisy_gyroid(double period, double noise, unsigned seed) {
    const double h = 0.1, k = 2 * M_PI / (period * h);
    const Sdf sdf = [k](const Vec3d& p) {
        const double g = std::sin(k * p.x) * std::cos(k * p.y) + std::sin(k * p.y) * std::cos(k * p.z) +
                         std::sin(k * p.z) * std::cos(k * p.x);
        return std::max({g * 0.1, std::abs(p.x) - 1.0, std::abs(p.y) - 1.0, std::abs(p.z) - 1.0});
    };
    Volume v =
        volume_from_sdf(sdf, openvdb::CoordBBox(openvdb::Coord(-13), openvdb::Coord(13)), h, {0.013, 0.021, 0.0});
    add_sdf_normals(v, sdf);
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, float(noise));
    for (auto& grid : v.extra) {
        auto* n = dynamic_cast<openvdb::Vec3fGrid*>(grid.get());
        for (auto it = n->beginValueOn(); it; ++it) {
            openvdb::Vec3f d = *it + openvdb::Vec3f(g(rng), g(rng), g(rng));
            d.normalize();
            it.setValue(d);
        }
    }
    return v;
}

} // namespace

// Before the guard covered the unmerged extraction (max_error 0, as pipelines/dmc.yaml runs
// it), the gyroid came out with 96 to 233 pairs of crossing faces (exact normals too); the guard puts the vertices of crossing faces
// at their mass point (and splits quads the other way) until none is left, with the mesh
// still closed, manifold and outward.
TEST(DualMarchingCubes, CrossingFacesAreRemovedWhereTheExtractionMakesThem) {
    std::size_t worst_without = 0, relaxed = 0;
    for (double period : {2.5, 3.0})
        for (double noise : {0.0, 0.3})
            for (double e : {0.0, 0.25}) {
                SCOPED_TRACE(testing::Message() << "period " << period << ", noise " << noise << ", max_error " << e);
                const Volume vol = noisy_gyroid(period, noise, 1);
                DualMcOptions o;
                o.max_error = e;
                o.guard = false;
                worst_without = std::max(worst_without, count_self_intersections(dual_marching_cubes(vol, o).value));
                o.guard = true;
                const auto [m, st] = dual_marching_cubes(vol, o);
                EXPECT_EQ(count_self_intersections(m), 0u);
                EXPECT_EQ(st.crossings_left, 0u);
                relaxed += st.relaxed;
                const MeshCheck c = check_mesh(m);
                EXPECT_TRUE(c.closed_manifold());
                EXPECT_EQ(c.degenerate_faces, 0u);
                EXPECT_GT(c.signed_volume, 0.0);
            }
    EXPECT_GT(worst_without, 0u) << "the configuration this test is about no longer arises";
    EXPECT_GT(relaxed, 0u);
}
