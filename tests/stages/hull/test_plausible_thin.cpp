// hull.plausible's thin parts after the removal (plausible_thin.h): a chain of thin-part
// edges whose hold on the body the removal took goes whole, one still held by the body stays,
// and a wire the hull itself holds apart stays as the hull has it.
#include <gtest/gtest.h>

#include "plausible_thin.h"

using namespace cm;

namespace {

using openvdb::Coord;

// A thin part along y from grid point p (entering at 0.4 of the edge, leaving at 0.6).
void thin_edge(openvdb::Vec3fGrid& enter, openvdb::Vec3fGrid& leave, Coord p) {
    enter.tree().setValueOn(p, openvdb::Vec3f(-1.0f, 0.4f, -1.0f));
    leave.tree().setValueOn(p, openvdb::Vec3f(-1.0f, 0.6f, -1.0f));
}

bool has_thin(const Volume& v, Coord p) {
    auto g = openvdb::GridBase::grid<openvdb::Vec3fGrid>(v.find_extra("thin_enter"));
    return g && g->tree().isValueOn(p) && g->tree().getValue(p)[1] >= 0;
}

} // namespace

TEST(HullPlausibleThin, AChainWhoseHoldWasRemovedGoesWhole) {
    Volume in;
    in.occupancy = openvdb::BoolGrid::create(false);
    in.occupancy->tree().denseFill(openvdb::CoordBBox({0, 0, 0}, {9, 9, 9}), true, true);
    auto enter = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    auto leave = openvdb::Vec3fGrid::create(openvdb::Vec3f(-1.0f));
    enter->setName("thin_enter");
    leave->setName("thin_leave");
    // Held by the block's far side (x = 9), which the removal takes; then 5 edges on.
    for (int x = 10; x <= 15; ++x) thin_edge(*enter, *leave, {x, 4, 4});
    // Held by the block's near side (x = 0), which stays.
    for (int x = -4; x <= -1; ++x) thin_edge(*enter, *leave, {x, 4, 4});
    // A wire the hull holds apart from the block.
    for (int x = 30; x <= 32; ++x) thin_edge(*enter, *leave, {x, 4, 4});
    in.extra = {enter, leave};
    // The removal takes the slab x = 8, 9.
    openvdb::BoolGrid::Ptr now = openvdb::BoolGrid::create(false);
    now->tree().denseFill(openvdb::CoordBBox({0, 0, 0}, {7, 9, 9}), true, true);

    Volume out;
    const std::size_t dropped = plausible::keep_hanging_thin_parts(in, *now, out);
    EXPECT_EQ(dropped, 6u);
    for (int x = 10; x <= 15; ++x) EXPECT_FALSE(has_thin(out, {x, 4, 4})) << "x " << x << " floats free";
    for (int x = -4; x <= -1; ++x) EXPECT_TRUE(has_thin(out, {x, 4, 4})) << "x " << x << " still held";
    for (int x = 30; x <= 32; ++x) EXPECT_TRUE(has_thin(out, {x, 4, 4})) << "x " << x << " the hull's own";
    // The leave grid matches the enter grid edge for edge.
    auto l2 = openvdb::GridBase::grid<openvdb::Vec3fGrid>(out.find_extra("thin_leave"));
    ASSERT_TRUE(l2);
    EXPECT_FLOAT_EQ(l2->tree().getValue({-2, 4, 4})[1], 0.6f);
    EXPECT_FALSE(l2->tree().isValueOn({12, 4, 4}));
}
