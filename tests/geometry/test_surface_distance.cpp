// The 3D error measure against cases whose answer is known in closed form: concentric
// spheres (every point of one is |r1 - r2| from the other), a mesh against itself, a
// distance beyond the fine grid's band, and the same figure at any scale and placement.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "geometry/surface_distance.h"
#include "support/shapes.h"

namespace cm {
namespace {

const double kDiagUnit = 2.0 * std::sqrt(3.0); // bounding-box diagonal of a unit sphere

TEST(SurfaceDistance, MeshAgainstItselfIsZero) {
    const Mesh s = test::make_sphere({0, 0, 0}, 1.0f, 5);
    const SurfaceDistance d = surface_distance(s, s, 20000);
    EXPECT_LT(d.mean_pct, 1e-4);
    EXPECT_EQ(d.beyond_reach, 0u);
    EXPECT_NEAR(d.diag, kDiagUnit, 1e-3);
}

TEST(SurfaceDistance, ConcentricSpheresAreTheirRadiusApart) {
    const Mesh truth = test::make_sphere({0, 0, 0}, 1.0f, 5);
    for (const double r : {1.05, 0.9, 1.5}) { // 1.05: in the finest band, 0.9: the middle, 1.5: the coarse
        const Mesh recon = test::make_sphere({0, 0, 0}, float(r), 5);
        const SurfaceDistance d = surface_distance(recon, truth, 20000);
        const double want = 100.0 * std::abs(r - 1.0) / kDiagUnit;
        EXPECT_NEAR(d.mean_pct, want, 0.01 * want + 0.005) << "radius " << r;
        EXPECT_NEAR(d.recon_to_true, std::abs(r - 1.0), 0.01 * std::abs(r - 1.0) + 1e-3) << "radius " << r;
        EXPECT_NEAR(d.true_to_recon, std::abs(r - 1.0), 0.01 * std::abs(r - 1.0) + 1e-3) << "radius " << r;
        EXPECT_EQ(d.beyond_reach, 0u);
    }
}

TEST(SurfaceDistance, SameFigureAtAnyScaleAndPlace) {
    // Units of hundreds (pixels) far from the origin: a mix of index and world space
    // would show here.
    const float k = 250.0f;
    const Vec3f c{1000.0f, -300.0f, 40.0f};
    const Mesh truth = test::make_sphere(c, k, 5);
    const Mesh recon = test::make_sphere(c, 1.1f * k, 5);
    const SurfaceDistance d = surface_distance(recon, truth, 20000);
    const double want = 100.0 * 0.1 / kDiagUnit;
    EXPECT_NEAR(d.mean_pct, want, 0.01 * want);
    EXPECT_NEAR(d.mean, 0.1 * k, 0.01 * 0.1 * k);
}

TEST(SurfaceDistance, OneSidedTermsSeeAMissingPart) {
    // A box against the same box with a second box far beside it: the extra part is far
    // from the truth (recon -> truth grows), the truth is all on the reconstruction.
    const Mesh truth = test::make_box({0, 0, 0}, {1, 1, 1});
    Mesh recon = truth;
    test::append_mesh(recon, test::make_box({1.5f, 0, 0}, {2.5f, 1, 1}));
    const SurfaceDistance d = surface_distance(recon, truth, 40000);
    EXPECT_LT(d.true_to_recon, 1e-4);
    // Half the reconstruction's area is the far box: its faces at x = 1.5 and 2.5 are 0.5
    // and 1.5 from the truth, its four sides 1 on average, so 6 faces average 1.
    EXPECT_NEAR(d.recon_to_true, 0.5 * 1.0, 0.02);
    EXPECT_EQ(d.beyond_reach, 0u);
}

TEST(SurfaceDistance, EmptyMeshIsRefused) {
    const Mesh s = test::make_sphere({0, 0, 0}, 1.0f, 2);
    EXPECT_THROW(surface_distance(Mesh{}, s), Error);
    EXPECT_THROW(surface_distance(s, Mesh{}), Error);
}

} // namespace
} // namespace cm
