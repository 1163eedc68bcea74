// hull.plausible's hidden-depth prior (ghost): a thin arm beside a torso, under a shoulder
// plate that hides it from the top, is seen from the side inside the torso's outline; the hull
// gives it the torso's whole depth. With the prior its depth comes back about as deep as it is
// wide, and every line of sight of the drawn views keeps a voxel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "hull_steps.h"
#include "plausible.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;

namespace {

// x lateral, y up, z depth. The torso is 4 wide and 3 deep, the arm 0.8 by 0.8 beside it
// (a gap of 0.5), the shoulder plate above both as deep as the torso.
const Vec3d kTorsoLo(-2, -3, -1.5), kTorsoHi(2, 2, 1.5);
const Vec3d kArmLo(2.5, -2, -0.4), kArmHi(3.3, 2, 0.4);
const Vec3d kPlateLo(-3.5, 2, -1.5), kPlateHi(3.5, 3, 1.5);

// Front, right and top of the torso, the shoulder plate and an arm from `armLo` to `armHi`,
// the views framing everything up to `hi`.
std::shared_ptr<const Views> torso_with_arm(const Vec3d& armLo = kArmLo, const Vec3d& armHi = kArmHi,
                                            const Vec3d& hi = Vec3d(3.5, 3, 1.5)) {
    std::vector<View> vs;
    for (const char* n : {"front", "right", "top"}) {
        const Vec3d d = Camera::named(n)->d;
        vs.push_back(
            ortho_view(n, 320, 40.0,
                       union_outline(union_outline(box_outline(kTorsoLo, kTorsoHi, d), box_outline(armLo, armHi, d)),
                                     box_outline(kPlateLo, kPlateHi, d))));
    }
    return make_views(std::move(vs), Vec3d(-3.5, -3, -1.5), hi);
}

std::shared_ptr<const Volume> plausible_of(const std::shared_ptr<const Volume>& hull, double ghost,
                                           PlausibleStats* st = nullptr) {
    PlausibleOptions opt;
    opt.loft = 0.5;
    opt.ghost = ghost;
    auto r = make_plausible(*hull, nullptr, opt);
    if (st) *st = r.stats;
    return r.value;
}

// The kept depth (world units) along z at the grid column nearest (x, y).
double depth_at(const Volume& v, double x, double y) {
    const auto& xf = v.occupancy->transform();
    const openvdb::Coord c = xf.worldToIndexCellCentered(openvdb::Vec3d(x, y, 0));
    auto acc = v.occupancy->getConstAccessor();
    int n = 0;
    for (int k = c.z() - 200; k <= c.z() + 200; ++k) n += acc.isValueOn(openvdb::Coord(c.x(), c.y(), k));
    return n * v.voxel_size();
}

} // namespace

TEST(HullGhost, ThinArmBeforeTheTorsoComesBackRound) {
    const auto views = torso_with_arm();
    const auto hull = carve_and_refine(views, 96);
    PlausibleStats st;
    const auto before = plausible_of(hull, 0.0);
    const auto after = plausible_of(hull, 1.0, &st);
    const double arm_x = 0.5 * (kArmLo[0] + kArmHi[0]), arm_w = kArmHi[0] - kArmLo[0];
    const double torso_d = kTorsoHi[2] - kTorsoLo[2];
    EXPECT_GT(st.ghost_voxels, 0u);
    for (double y : {-1.0, 0.0, 1.0}) {
        const double d0 = depth_at(*before, arm_x, y), d1 = depth_at(*after, arm_x, y);
        std::cout << "arm depth at y " << y << ": " << d0 << " without the prior, " << d1 << " with it\n";
        // Without it the arm keeps most of the torso's depth; with it about its own width.
        EXPECT_GT(d0, 0.6 * torso_d);
        EXPECT_LT(d1, 1.5 * arm_w);
        EXPECT_GT(d1, 0.5 * arm_w);
    }
    // Every line of sight of the drawn views still holds a voxel: the arm's front view whole.
    const auto& xf = after->occupancy->transform();
    for (double y = kArmLo[1] + 0.1; y < kArmHi[1]; y += 0.1)
        for (double x = kArmLo[0] + 0.05; x < kArmHi[0]; x += 0.05) {
            const openvdb::Coord c = xf.worldToIndexCellCentered(openvdb::Vec3d(x, y, 0));
            if (!hull->occupancy->tree().isValueOn(c)) continue; // a column the hull leaves empty
            EXPECT_GT(depth_at(*after, x, y), 0.0) << "x " << x << " y " << y;
        }
}

// Parts about as deep as they are wide (two legs side by side) are left alone.
TEST(HullGhost, LegsSideBySideAreLeftAlone) {
    std::vector<View> vs;
    const Vec3d aLo(-2, -3, -0.8), aHi(-0.4, 3, 0.8), bLo(0.4, -3, -0.8), bHi(2, 3, 0.8);
    for (const char* n : {"front", "right", "top"}) {
        const Vec3d d = Camera::named(n)->d;
        vs.push_back(ortho_view(n, 320, 40.0, union_outline(box_outline(aLo, aHi, d), box_outline(bLo, bHi, d))));
    }
    const auto hull = carve_and_refine(make_views(std::move(vs), Vec3d(-2, -3, -0.8), Vec3d(2, 3, 0.8)), 96);
    PlausibleStats st;
    plausible_of(hull, 1.0, &st);
    EXPECT_EQ(st.ghost_voxels, 0u);
}

// An arm that reaches behind the torso's back: the side view's depth goes beyond the torso
// there, and only the arm can give it. Its round section is placed to take that stretch in,
// not in the middle of the top view's run (which reaches from the shoulder plate's front to the
// arm's back): otherwise the covering of the side view's lines of sight keeps the arm's back as
// well, and the arm comes out a plate from its section to the back.
TEST(HullGhost, ArmBehindTheTorsoStaysRoundAtItsPlace) {
    const Vec3d armLo(2.5, -2, 1.0), armHi(3.3, 2, 2.0);
    const auto hull = carve_and_refine(torso_with_arm(armLo, armHi, Vec3d(3.5, 3, 2.0)), 96);
    const auto after = plausible_of(hull, 1.0);
    const double arm_x = 0.5 * (armLo[0] + armHi[0]), arm_d = armHi[2] - armLo[2];
    for (double y : {-1.0, 0.0, 1.0}) {
        const double d0 = depth_at(*hull, arm_x, y), d1 = depth_at(*after, arm_x, y);
        std::cout << "arm depth at y " << y << ": " << d0 << " in the hull, " << d1 << " kept\n";
        EXPECT_GT(d0, 2.5 * arm_d);
        EXPECT_LT(d1, 1.5 * arm_d);
    }
}
