// hull.plausible's hard-surface detection (hard_surface) and the lofted sections' check
// against the view along their axis: drawings of straight edges meeting at corners keep the
// visual hull, curved ones are still rounded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hull_steps.h"
#include "plausible.h"
#include "plausible_coarse.h"
#include "plausible_hard.h"
#include "plausible_loft.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;

namespace {

std::shared_ptr<Views> three_views(const std::function<Outline(const Camera&)>& outline, Vec3d lo, Vec3d hi) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) vs.push_back(ortho_view(n, 320, 120.0, outline(*Camera::named(n))));
    return make_views(std::move(vs), lo, hi);
}

std::shared_ptr<Views> box_views(Vec3d lo, Vec3d hi) {
    return three_views([lo, hi](const Camera& c) { return box_outline(lo, hi, c.d); }, lo, hi);
}

// A standing cylinder: rectangles from the front and the right, a disc from the top.
std::shared_ptr<Views> cylinder_views(double r, double h) {
    return three_views(
        [r, h](const Camera& c) -> Outline {
            if (std::abs(c.d[1]) > 0.5) return [r](const Vec3d& q) { return r - std::hypot(q[0], q[2]); };
            return box_outline({-r, -h, -r}, {r, h, r}, c.d);
        },
        {-r, -h, -r}, {r, h, r});
}

// Grid points of `a` not in `b`.
openvdb::Index64 missing(const Volume& a, const Volume& b) {
    auto d = a.occupancy->deepCopy();
    d->tree().voxelizeActiveTiles();
    d->tree().topologyDifference(b.occupancy->tree());
    return d->activeVoxelCount();
}

} // namespace

// A box's outlines are straight all along but within a tenth of the side of its corners, a
// disc's and a sphere's nowhere (under the detection's lower bound, 0.06); the hardness
// follows the least straight view.
TEST(HullHard, StraightOutlinesAreFound) {
    const auto box = box_views({-1.0, -0.6, -0.8}, {1.0, 0.6, 0.8});
    std::vector<double> shares;
    EXPECT_EQ(plausible::hard_surface(*box, shares), 1.0);
    ASSERT_EQ(shares.size(), 3u);
    for (double s : shares) EXPECT_GT(s, 0.7);

    const auto sphere = three_views([](const Camera&) { return sphere_outline(1.0); }, {-1, -1, -1}, {1, 1, 1});
    EXPECT_EQ(plausible::hard_surface(*sphere, shares), 0.0);
    for (double s : shares) EXPECT_LT(s, 0.02);

    // The cylinder's top view is a disc: the views do not all say "machined", so it is left to
    // the lofted sections (which keep its faces, test_loft.cpp).
    EXPECT_EQ(plausible::hard_surface(*cylinder_views(0.7, 1.0), shares), 0.0);
    EXPECT_GT(shares[0], 0.7);
    EXPECT_LT(shares[2], 0.06);
}

// With the detection on, a box keeps its hull voxel for voxel at full roundness (the
// profiles alone, organic.yaml's prior, round its edges), and a sphere is rounded as
// without it.
TEST(HullHard, BoxKeepsItsHullSphereIsRounded) {
    const auto box = carve_and_refine(box_views({-1.0, -0.6, -0.8}, {1.0, 0.6, 0.8}), 64);
    PlausibleOptions opt;
    const auto rounded = make_plausible(*box, nullptr, opt);
    EXPECT_GT(missing(*box, *rounded.value), 100u) << "the profiles round a box's edges";
    opt.hard_surface = 1.0;
    const auto kept = make_plausible(*box, nullptr, opt);
    EXPECT_EQ(kept.stats.hardness, 1.0);
    EXPECT_EQ(missing(*box, *kept.value), 0u);
    EXPECT_EQ(kept.stats.removed, 0u);

    const auto sphere =
        carve_and_refine(three_views([](const Camera&) { return sphere_outline(1.0); }, {-1, -1, -1}, {1, 1, 1}), 64);
    opt.hard_surface = 0.0;
    const auto a = make_plausible(*sphere, nullptr, opt);
    opt.hard_surface = 1.0;
    const auto b = make_plausible(*sphere, nullptr, opt);
    EXPECT_EQ(b.stats.hardness, 0.0);
    EXPECT_GT(b.stats.removed, 1000u);
    EXPECT_EQ(missing(*a.value, *b.value) + missing(*b.value, *a.value), 0u);
}

// On a sphere every lofted section is confirmed by the view along its axis (an inscribed
// disc covers pi/4 of its box, the view's disc more): the check leaves round shapes to the
// lofted prior. Across a tall prism with an L-shaped top view, the sections across the
// prism's axis would be boxes of the whole L, which the top view covers under half of: the
// voxels take sections the view along them confirms.
TEST(HullHard, LoftedSectionsAgreeWithTheViewAlongThem) {
    const auto sphere =
        carve_and_refine(three_views([](const Camera&) { return sphere_outline(1.0); }, {-1, -1, -1}, {1, 1, 1}), 64);
    const plausible::HullVoxels sv(*sphere->occupancy);
    std::size_t low = 0;
    for (const auto& v : plausible::loft_field(sv, 2.0)) low += v.fit < 0.99f;
    EXPECT_EQ(low, 0u);

    // An L in the top view (two bars a quarter wide), ellipses from the front and the right
    // (twice as tall as wide): across its height the boxes are the whole L's square, often
    // smaller than those along it, so without the check many voxels of the L would take
    // sections the top view covers under half of.
    const Vec3d lo(-0.5, -1.0, -0.5), hi(0.5, 1.0, 0.5);
    const auto L = three_views(
        [](const Camera& c) -> Outline {
            if (std::abs(c.d[1]) < 0.5)
                return [](const Vec3d& q) {
                    return 0.5 * (1.0 - std::hypot(2.0 * (q[0] + q[2]), q[1])); // |d| picks x or z
                };
            return union_outline(box_outline({-0.5, -1.0, -0.5}, {-0.25, 1.0, 0.5}, c.d),
                                 box_outline({-0.5, -1.0, -0.5}, {0.5, 1.0, -0.25}, c.d));
        },
        lo, hi);
    const auto hull = carve_and_refine(L, 48);
    const plausible::HullVoxels lv(*hull->occupancy);
    std::size_t confirmed = 0;
    const auto field = plausible::loft_field(lv, 2.0);
    for (const auto& v : field) confirmed += v.fit >= 0.5f;
    EXPECT_GT(double(confirmed), 0.97 * double(field.size()));
}

// On finer grids the field is taken every `stride` cells and interpolated: on a sphere the
// grid points on the coarse lattice keep their exact values, and the others stay close to
// the exact field (the lofted prior here, whose section axis changes jump).
TEST(HullHard, CoarseFieldFollowsTheExactOne) {
    const auto sphere =
        carve_and_refine(three_views([](const Camera&) { return sphere_outline(1.0); }, {-1, -1, -1}, {1, 1, 1}), 64);
    const plausible::HullVoxels sv(*sphere->occupancy);
    const auto exact = plausible::loft_field(sv, 2.0);
    const plausible::CoarseLattice lattice(sv.leaves, sv.base, 2);
    UninitVector<float> field(exact.size(), 1e6f);
    std::vector<char> taken(exact.size(), 0), on_lattice(exact.size(), 0);
    sv.for_voxels([&](std::size_t i, const openvdb::Coord& c) {
        const std::size_t l = std::size_t(std::upper_bound(sv.base.begin(), sv.base.end(), i) - sv.base.begin()) - 1;
        const openvdb::Index o = sv.leaves.leaf(l).coordToOffset(c);
        taken[i] = (lattice.exact()[l][o >> 6] >> (o & 63) & 1) != 0;
        if (taken[i]) field[i] = exact[i].field;
        on_lattice[i] = c.x() % 2 == 0 && c.y() % 2 == 0 && c.z() % 2 == 0;
    });
    lattice.interpolate(field, nullptr, 0);
    std::size_t lattice_count = 0, missing = 0, extra = 0, far = 0, over = 0;
    double sum = 0.0;
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const double d = std::abs(double(field[i]) - double(exact[i].field));
        lattice_count += on_lattice[i] != 0;
        missing += on_lattice[i] && !taken[i];
        extra += taken[i] && !on_lattice[i];
        far += taken[i] && d > 1e-5;
        sum += d;
        over += d > 1.0;
    }
    EXPECT_EQ(missing, 0u);
    EXPECT_EQ(far, 0u);
    // A few voxels off the lattice with no lattice point of the hull about them (at the
    // sphere's surface) are taken too.
    EXPECT_LT(double(extra), 0.02 * double(exact.size()));
    // Where the section's axis changes the exact field jumps; the interpolation spreads the
    // jump over two cells.
    EXPECT_LT(sum / double(exact.size()), 0.5);
    EXPECT_LT(double(over), 0.1 * double(exact.size()));
    EXPECT_GT(lattice_count, exact.size() / 10);
}
