// hull.plausible's lofted prior pairs the parts of two views by their tracks along the slicing
// axis: two legs apart in both the front and the side view make four boxes in the hull, two of
// them ghosts. Where one leg is lifted (its foot higher in both views) the feet tell which runs
// are one leg's, and the prior comes back with two legs; where nothing tells them apart all
// four boxes stay. Every line of sight of the drawn views keeps a voxel either way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "hull_steps.h"
#include "plausible.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
using namespace cm::test;

namespace {

// x lateral, y up, z depth. A round hip over two round legs, one to the left and in front,
// the other to the right and behind, the second's foot `lift` above the first's. From the top
// the hip hides both legs: the view along them does not tell which is where.
struct Legs {
    Vec3d hip{0, 0.5, 0};
    double hip_r = 2.2, leg_r = 0.6;
    Vec3d a{-1, -4, 1}, b{1, -4, -1}; ///< each leg's axis at its foot; both reach up to y 0.5

    bool toes = false; ///< a toe beside each foot, joined to it above the sole (front view)

    explicit Legs(double lift, bool with_toes = false) : toes(with_toes) { b[1] += lift; }

    // A toe beside the foot at f, towards x 0: apart from the foot in the front view up to
    // 0.5 above the sole, joined to it by a bridge above; the side and top views do not see it.
    Outline toe(const Vec3d& f, const Vec3d& d) const {
        const double x = f[0] - std::copysign(leg_r + 0.3, f[0]), w = 0.15, h = 0.5;
        const Outline stub = box_outline({x - w, f[1], f[2] - w}, {x + w, f[1] + h + 0.2, f[2] + w}, d);
        const Outline bridge =
            box_outline({std::min(x, f[0]), f[1] + h, f[2] - w}, {std::max(x, f[0]), f[1] + h + 0.2, f[2] + w}, d);
        return union_outline(stub, bridge);
    }

    // A vertical cylinder seen along d: a disc from the top, a rectangle from the sides.
    Outline leg(const Vec3d& f, const Vec3d& d) const {
        const double r = leg_r, top = hip[1];
        return [f, d, r, top](const Vec3d& q) {
            if (std::abs(d[1]) > 0.5) return r - std::hypot(q[0] - f[0], q[2] - f[2]);
            const int k = std::abs(d[2]) > 0.5 ? 0 : 2;
            return std::min({q[1] - f[1], top - q[1], r - std::abs(q[k] - f[k])});
        };
    }
    Outline ball(const Vec3d& d) const {
        const Vec3d c = hip - d * dot(hip, d);
        const double r = hip_r;
        return [c, r](const Vec3d& q) { return r - length(q - c); };
    }

    std::shared_ptr<const Views> views() const {
        std::vector<View> vs;
        for (const char* n : {"front", "right", "top"}) {
            const Vec3d d = Camera::named(n)->d;
            Outline o = union_outline(union_outline(ball(d), leg(a, d)), leg(b, d));
            if (toes) o = union_outline(o, union_outline(toe(a, d), toe(b, d)));
            vs.push_back(ortho_view(n, 320, 40.0, o));
        }
        return make_views(std::move(vs), Vec3d(-hip_r, a[1], -hip_r), Vec3d(hip_r, hip[1] + hip_r, hip_r));
    }
};

std::shared_ptr<const Volume> lofted(const std::shared_ptr<const Volume>& hull, PlausibleStats* st) {
    PlausibleOptions opt;
    opt.loft = 0.5;
    opt.ghost = 1.0;
    opt.hard_surface = 0.0; // boxes: the rounding wanted all the same
    auto r = make_plausible(*hull, nullptr, opt);
    *st = r.stats;
    return r.value;
}

bool on(const Volume& v, double x, double y, double z) {
    const openvdb::Coord c = v.occupancy->transform().worldToIndexCellCentered(openvdb::Vec3d(x, y, z));
    return v.occupancy->tree().isValueOn(c);
}

void expect_lines_of_sight_kept(const Volume& hull, const Volume& out) {
    for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(columns(out, axis), columns(hull, axis)) << "axis " << axis;
}

// At each height of `ys` the hull holds all four boxes of the two legs, and the result keeps
// the legs' own and drops the two ghosts.
void expect_legs_apart(const Legs& legs, const Volume& hull, const Volume& out, std::initializer_list<double> ys) {
    const double ax = legs.a[0], az = legs.a[2], bx = legs.b[0], bz = legs.b[2];
    for (double y : ys) {
        ASSERT_TRUE(on(hull, ax, y, bz) && on(hull, bx, y, az));
        EXPECT_TRUE(on(out, ax, y, az)) << "leg a at y " << y;
        EXPECT_TRUE(on(out, bx, y, bz)) << "leg b at y " << y;
        EXPECT_FALSE(on(out, ax, y, bz)) << "ghost at y " << y;
        EXPECT_FALSE(on(out, bx, y, az)) << "ghost at y " << y;
    }
}

} // namespace

TEST(HullTracks, TwoLegsApartInBothViewsComeBackAsTwo) {
    const Legs legs(1.0);
    const auto hull = carve_and_refine(legs.views(), 96);
    PlausibleStats st;
    const auto out = lofted(hull, &st);
    EXPECT_GT(st.unpaired_voxels, 0u);
    expect_legs_apart(legs, *hull, *out, {-2.6, -2.3, -2.0});
    // Below the lifted foot only leg a is there, in the hull as in the result.
    EXPECT_TRUE(on(*out, legs.a[0], -3.5, legs.a[2]));
    expect_lines_of_sight_kept(*hull, *out);
}

// Feet at the same height and the hip hiding the legs from the top: nothing tells which run of
// the side view is the left leg's, so every box stays.
TEST(HullTracks, LegsNothingTellsApartKeepEveryBox) {
    const Legs legs(0.0);
    const auto hull = carve_and_refine(legs.views(), 96);
    PlausibleStats st;
    const auto out = lofted(hull, &st);
    EXPECT_EQ(st.unpaired_voxels, 0u);
    EXPECT_TRUE(on(*out, legs.a[0], -2.3, legs.b[2]));
    EXPECT_TRUE(on(*out, legs.b[0], -2.3, legs.a[2]));
    expect_lines_of_sight_kept(*hull, *out);
}

// A toe beside each foot, joined to it a little above the sole, splits each leg's run in the
// front view near the ground: the leg's run above the toe overlaps two runs below it. The
// tracks follow the leg through it (the toe is small beside it), so the lifted foot still
// tells which runs are one leg's.
TEST(HullTracks, ToesBesideTheFeetStillTellTheLegsApart) {
    const Legs legs(1.0, true);
    const auto hull = carve_and_refine(legs.views(), 96);
    PlausibleStats st;
    const auto out = lofted(hull, &st);
    EXPECT_GT(st.unpaired_voxels, 0u);
    expect_legs_apart(legs, *hull, *out, {-2.3, -2.0, -1.7});
    expect_lines_of_sight_kept(*hull, *out);
}
