// hull.plausible's output volume in one piece (plausible_pieces.h): a crumb the removal left
// farther from the body than the bridges reach goes; a part as large as that reach, cut off
// its body farther away, is joined however far.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "plausible_state.h"
#include "removal_block.h"

using namespace cm;

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

// 6-connected pieces of the grid's on voxels.
int pieces(const openvdb::BoolGrid& g) {
    auto acc = g.getConstAccessor();
    openvdb::BoolGrid::Ptr seen = openvdb::BoolGrid::create(false);
    auto sacc = seen->getAccessor();
    int n = 0;
    for (auto it = g.cbeginValueOn(); it; ++it) {
        CoordBBox vb;
        it.getBoundingBox(vb);
        for (auto c = vb.begin(); c; ++c) {
            if (sacc.isValueOn(*c)) continue;
            ++n;
            std::vector<Coord> stack{*c};
            sacc.setValueOn(*c, true);
            while (!stack.empty()) {
                const Coord p = stack.back();
                stack.pop_back();
                for (int d = 0; d < 6; ++d) {
                    Coord q = p;
                    q[d / 2] += (d & 1) ? 1 : -1;
                    if (acc.isValueOn(q) && !sacc.isValueOn(q)) sacc.setValueOn(q, true), stack.push_back(q);
                }
            }
        }
    }
    return n;
}

// A bar 80 x 8 x 8 (the bridges reach 10 voxels): the body x 0..39 kept; of the rest, only
// what `kept` says.
struct Bar : test::RemovalBlock {
    template <typename F>
    explicit Bar(F&& kept)
        : RemovalBlock(CoordBBox({0, 0, 0}, {79, 7, 7}),
                       [&](const Coord& c) { return c.x() <= 39 || kept(c) ? -1.0f : 1.0f; }) {}
};

bool in_box(const Coord& c, const Coord& lo, const Coord& hi) {
    return c.x() >= lo.x() && c.y() >= lo.y() && c.z() >= lo.z() && c.x() <= hi.x() && c.y() <= hi.y() &&
           c.z() <= hi.z();
}

} // namespace

TEST(HullPlausiblePieces, ACrumbFarFromTheBodyGoes) {
    // A 2 x 2 x 2 crumb 12 voxels from the body.
    Bar bar([](const Coord& c) { return in_box(c, {52, 3, 3}, {53, 4, 4}); });
    const std::size_t removed = bar.st.removed;
    auto out = bar.run();
    EXPECT_EQ(pieces(*out->occupancy), 1);
    EXPECT_EQ(bar.st.far_dropped, 8u);
    EXPECT_FALSE(out->occupancy->tree().isValueOn({52, 3, 3}));
    EXPECT_EQ(bar.st.removed, removed + 8u);
    // The body as it was.
    EXPECT_EQ(out->occupancy->tree().activeVoxelCount(), openvdb::Index64(40 * 8 * 8));
}

TEST(HullPlausiblePieces, ALargePartCutOffFarAwayIsJoined) {
    // The bar's end, x 66..79 (14 voxels long), 26 voxels from the body.
    Bar bar([](const Coord& c) { return c.x() >= 66; });
    auto out = bar.run();
    EXPECT_EQ(pieces(*out->occupancy), 1);
    EXPECT_EQ(bar.st.far_dropped, 0u);
    EXPECT_EQ(bar.st.pieces_joined, 1u);
    for (const Coord c : {Coord(66, 0, 0), Coord(79, 7, 7)}) EXPECT_TRUE(out->occupancy->tree().isValueOn(c));
    // A bridge, thickened by its face neighbours: no more than 7 voxels per step of the gap.
    EXPECT_LE(out->occupancy->tree().activeVoxelCount(), openvdb::Index64((40 + 14) * 8 * 8 + 7 * 26));
}

TEST(HullPlausiblePieces, ACrumbWithinReachIsJoined) {
    // The same crumb 6 voxels from the body: bridged, not dropped.
    Bar bar([](const Coord& c) { return in_box(c, {46, 3, 3}, {47, 4, 4}); });
    auto out = bar.run();
    EXPECT_EQ(pieces(*out->occupancy), 1);
    EXPECT_EQ(bar.st.far_dropped, 0u);
    EXPECT_TRUE(out->occupancy->tree().isValueOn({46, 3, 3}));
}
