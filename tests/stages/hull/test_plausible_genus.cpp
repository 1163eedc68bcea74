// hull.plausible's output volume keeps the hull's genus (plausible_genus.h): a removal that
// would open a tunnel through the kept volume is put back in part (a wall across it), and one
// that only dents it stays whole.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include "leaf_masks.h"
#include "plausible_genus.h"
#include "plausible_genus_checks.h"
#include "plausible_genus_masks.h"
#include "plausible_state.h"
#include "removal_block.h"

using namespace cm;

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

// Euler characteristic of the union of the closed unit cubes of the grid's on voxels
// (vertices - edges + faces - cubes of the cubical complex): 1 - handles for one solid piece
// without cavities.
long euler(const openvdb::BoolGrid& g) {
    CoordBBox box;
    g.tree().evalActiveVoxelBoundingBox(box);
    auto acc = g.getConstAccessor();
    const auto on = [&](int x, int y, int z) { return acc.isValueOn(Coord(x, y, z)); };
    long chi = 0;
    // Every cell of the complex by its lowest corner p and the axes it spans (mask m): it is in
    // the complex when a voxel holding it is on (voxel v holds the cells at corners v..v+1).
    for (int x = box.min().x(); x <= box.max().x() + 1; ++x)
        for (int y = box.min().y(); y <= box.max().y() + 1; ++y)
            for (int z = box.min().z(); z <= box.max().z() + 1; ++z)
                for (int m = 0; m < 8; ++m) {
                    bool in = false;
                    // Voxels holding the cell: offsets -1/0 along the axes it does not span.
                    for (int k = 0; k < 8 && !in; ++k) {
                        if ((k & m) != 0) continue;
                        in = on(x - (k & 1), y - (k >> 1 & 1), z - (k >> 2 & 1));
                    }
                    if (in) chi += (__builtin_popcount(unsigned(m)) % 2) ? -1 : 1;
                }
    return chi;
}

// The handles of the grid's on voxels in the box: pieces (26-connected) + cavities (pieces
// of the rest, 6-connected, that reach no voxel outside the box) - Euler characteristic.
long handles(const openvdb::BoolGrid& g, const CoordBBox& box) {
    auto acc = g.getConstAccessor();
    const auto count = [&](bool value, bool faces_only, bool cavities) {
        CoordBBox b = box;
        b.expand(1);
        std::set<Coord> seen;
        long n = 0;
        for (auto it = b.beginXYZ(); it; ++it) {
            const Coord c = *it;
            if (acc.isValueOn(c) != value || seen.count(c)) continue;
            bool border = false;
            std::vector<Coord> stack{c};
            seen.insert(c);
            while (!stack.empty()) {
                const Coord p = stack.back();
                stack.pop_back();
                for (int dx = -1; dx <= 1; ++dx)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dz = -1; dz <= 1; ++dz) {
                            if (faces_only && std::abs(dx) + std::abs(dy) + std::abs(dz) != 1) continue;
                            const Coord q = p.offsetBy(dx, dy, dz);
                            if (!b.isInside(q)) {
                                border = true;
                                continue;
                            }
                            if (acc.isValueOn(q) != value || seen.count(q)) continue;
                            seen.insert(q);
                            stack.push_back(q);
                        }
            }
            n += !cavities || !border;
        }
        return n;
    };
    return count(true, false, false) + count(false, true, true) - euler(g);
}

// A 16 x 12 x 12 block; `cut` says which voxels the field removes and how far outside the
// allowance they lie (above 0: removed).
struct Removal : test::RemovalBlock {
    template <typename F>
    explicit Removal(F&& cut) : RemovalBlock(CoordBBox({0, 0, 0}, {15, 11, 11}), cut) {}
};

} // namespace

TEST(HullPlausibleGenus, ARemovalThroughTheBlockLeavesAWallAcrossIt) {
    // A slot through the block along z (x 5..10, y 4..7): alone, it leaves a ring (genus 1).
    // The field is lowest half-way along it.
    Removal r([](const Coord& c) {
        const bool slot = c.x() >= 5 && c.x() <= 10 && c.y() >= 4 && c.y() <= 7;
        return slot ? 1.0f + std::abs(float(c.z()) - 5.25f) : -1.0f;
    });
    auto out = r.run();
    EXPECT_EQ(euler(*out->occupancy), 1) << "a tunnel through the kept volume";
    EXPECT_GT(r.st.genus_kept, 0u);
    // The wall is where the field is lowest: both ends of the slot stay open.
    EXPECT_TRUE(out->occupancy->tree().isValueOn({7, 5, 5}));
    for (int z : {0, 1, 2, 9, 10, 11}) EXPECT_FALSE(out->occupancy->tree().isValueOn({7, 5, z})) << "z " << z;
    // No more than a wall a few voxels thick of the 6 x 4 x 12 slot comes back.
    EXPECT_LE(r.st.genus_kept, 6u * 4u * 4u);
}

TEST(HullPlausibleGenus, ADentStaysWhole) {
    // A pocket open on one face only (z 0..5): no tunnel, nothing comes back.
    Removal r([](const Coord& c) {
        const bool dent = c.x() >= 5 && c.x() <= 10 && c.y() >= 4 && c.y() <= 7 && c.z() <= 5;
        return dent ? 1.0f : -1.0f;
    });
    r.st.removed = 6u * 4u * 6u;
    auto out = r.run();
    EXPECT_EQ(euler(*out->occupancy), 1);
    EXPECT_EQ(r.st.genus_kept, 0u);
    EXPECT_EQ(r.st.removed, 6u * 4u * 6u);
}

TEST(HullPlausibleGenus, EulerChangeOfOneVoxelByItsNeighbours) {
    // Bit x + 3 y + 9 z of the 3x3x3 neighbourhood, offsets + 1.
    const auto bit = [](int x, int y, int z) { return 1u << ((x + 1) + 3 * (y + 1) + 9 * (z + 1)); };
    const unsigned centre = bit(0, 0, 0);
    unsigned all = 0, slab = 0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y) {
            for (int z = -1; z <= 1; ++z) all |= bit(x, y, z);
            slab |= bit(x, y, 0);
        }
    all &= ~centre;
    slab &= ~centre;
    // Out of a full block: a cavity (+1). Out of a plate one voxel thick: a hole (-1). A voxel
    // on a face alone: nothing changes.
    EXPECT_EQ(plausible::euler_change(all, centre), 1);
    EXPECT_EQ(plausible::euler_change(slab, centre), -1);
    EXPECT_EQ(plausible::euler_change(bit(0, 0, -1), centre), 0);
    // Taken out with its whole neighbourhood (no kept voxel about it): what it adds cancels.
    EXPECT_EQ(plausible::euler_change(0, all | centre), 0);
}

TEST(HullPlausibleGenus, APieceThatCutsAPartOffAndOpensATunnelLeavesAWall) {
    // One removed piece of three parts in a 16 x 12 x 12 block: a slot through it along z
    // (x 3..5, y 4..7; alone, a tunnel: Euler -1), a plane across it at x 12 (alone, a part
    // cut off: +1) and a groove along the top (z 10..11) that joins them. Its Euler change
    // sums to 0. (In hull.plausible the bridges of the pieces step would join the part cut
    // off back first; called directly, nothing does.)
    const auto field = [](const Coord& c) {
        const bool band = c.y() >= 4 && c.y() <= 7;
        if (band && c.x() >= 3 && c.x() <= 5) return 1.0f + std::abs(float(c.z()) - 5.25f);
        if (band && c.x() >= 6 && c.x() <= 11 && c.z() >= 10) return 8.0f;
        return c.x() == 12 ? 8.0f : -1.0f;
    };
    auto grid = openvdb::BoolGrid::create(false);
    grid->tree().denseFill(CoordBBox({0, 0, 0}, {15, 11, 11}), true, true);
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(grid->tree());
    std::vector<plausible::LeafMask> hull;
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) hull.push_back(plausible::leaf_mask(leaves.leaf(l)));
    std::size_t cut = 0;
    for (int x = 0; x < 16; ++x)
        for (int y = 0; y < 12; ++y)
            for (int z = 0; z < 12; ++z)
                if (field({x, y, z}) > 0) grid->tree().setValueOff({x, y, z}, false), ++cut;
    ASSERT_EQ(euler(*grid), 1) << "the piece at once: Euler unchanged";
    const std::size_t back = plausible::keep_hull_genus(leaves, hull, [&](std::size_t l, openvdb::Index off) {
        return field(leaves.leaf(l).offsetToGlobalCoord(off));
    });
    // Two pieces (the cut stays allowed), neither with a handle: Euler 2 (with the tunnel: 1).
    EXPECT_EQ(euler(*grid), 2) << "a tunnel through the kept volume";
    EXPECT_GT(back, 0u);
    EXPECT_LT(back, cut);
    EXPECT_FALSE(grid->tree().isValueOn({12, 1, 1})) << "the cut stays";
    EXPECT_TRUE(grid->tree().isValueOn({4, 5, 5})) << "a wall across the slot";
}

TEST(HullPlausibleGenus, APieceThatCutsAHandleOfTheHullAndDrillsATunnelIsNotTakenAtOnce) {
    // A hull of genus 1: a 24 x 12 x 12 block with a hole through it along z (x 3..6, y
    // 4..7). One removed piece of three parts: a cut through the hole's wall to the block's
    // -x face (x 0..2, y 5..6; alone, the hull's handle cut: Euler +1), a slot through the
    // block along z (x 15..17, y 4..7; alone, a tunnel: -1) and a dent in the top (z 10..11)
    // around the hole that joins them. Its Euler change sums to 0, the kept voxels about it
    // are one piece (the dent's floor goes round the hole) and every voxel of it reaches the
    // outside: the count lets it go at once, and the kept volume keeps genus 1 with its
    // tunnel where the hull has none (the trade). It meets the outside in two places (the
    // slot's lower end apart from the rest), so it goes one voxel at a time: the slot keeps a
    // wall. The hull's own handle may go (taking voxels out one at a time can cut a handle,
    // here from the dent down, never open one): the kept volume's genus is not above the
    // hull's, and no tunnel of it runs where the hull has none.
    const auto hole = [](const Coord& c) { return c.x() >= 3 && c.x() <= 6 && c.y() >= 4 && c.y() <= 7; };
    const auto field = [](const Coord& c) {
        if (c.x() <= 2 && c.y() >= 5 && c.y() <= 6) return 8.0f;
        if (c.x() >= 15 && c.x() <= 17 && c.y() >= 4 && c.y() <= 7) return 1.0f + std::abs(float(c.z()) - 5.25f);
        if (c.z() >= 10 && (c.x() <= 10 || (c.x() <= 17 && c.y() >= 4 && c.y() <= 7))) return 8.0f;
        return -1.0f;
    };
    auto grid = openvdb::BoolGrid::create(false);
    grid->tree().denseFill(CoordBBox({0, 0, 0}, {23, 11, 11}), true, true);
    for (int x = 0; x < 24; ++x)
        for (int y = 0; y < 12; ++y)
            for (int z = 0; z < 12; ++z)
                if (hole({x, y, z})) grid->tree().setValueOff({x, y, z}, false);
    ASSERT_EQ(euler(*grid), 0) << "the hull: one handle";
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(grid->tree());
    std::vector<plausible::LeafMask> hull;
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) hull.push_back(plausible::leaf_mask(leaves.leaf(l)));
    std::size_t cut = 0;
    for (int x = 0; x < 24; ++x)
        for (int y = 0; y < 12; ++y)
            for (int z = 0; z < 12; ++z)
                if (!hole({x, y, z}) && field({x, y, z}) > 0) grid->tree().setValueOff({x, y, z}, false), ++cut;
    ASSERT_EQ(euler(*grid), 0) << "the piece at once: Euler unchanged";
    const std::size_t back = plausible::keep_hull_genus(leaves, hull, [&](std::size_t l, openvdb::Index off) {
        return field(leaves.leaf(l).offsetToGlobalCoord(off));
    });
    // One piece without cavities: Euler 1 - genus, so genus 1 at most (the hull's).
    EXPECT_GE(euler(*grid), 0) << "more handles than the hull";
    EXPECT_GT(back, 0u);
    EXPECT_LT(back, cut);
    // No tunnel but through the hull's hole: with the hole filled in, none is left.
    auto filled = grid->deepCopy();
    filled->tree().denseFill(CoordBBox({3, 4, 0}, {6, 7, 11}), true, true);
    EXPECT_EQ(euler(*filled), 1) << "a tunnel where the hull has none";
    EXPECT_TRUE(grid->tree().isValueOn({16, 5, 5})) << "a wall across the slot";
    EXPECT_FALSE(grid->tree().isValueOn({9, 1, 11})) << "the dent stays";
}

TEST(HullPlausibleGenus, TheSameVoxelsComeBackOnOneThreadAsOnMany) {
    // A 64 x 48 x 48 block (hundreds of leaves) riddled by a removal that runs through it in
    // every direction: one piece that cannot go at once, split into chunks that are checked
    // side by side. Whatever the threads, the same voxels come back.
    const auto field = [](const Coord& c) {
        const float wave =
            std::sin(0.31f * float(c.x())) * std::sin(0.37f * float(c.y())) * std::sin(0.41f * float(c.z()));
        const unsigned h = unsigned(c.x()) * 73856093u ^ unsigned(c.y()) * 19349663u ^ unsigned(c.z()) * 83492791u;
        return wave - 0.05f + 0.1f * float(h % 1000u) / 1000.0f;
    };
    const auto run = [&](int threads, std::size_t& back) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        auto grid = openvdb::BoolGrid::create(false);
        grid->tree().denseFill(CoordBBox({0, 0, 0}, {63, 47, 47}), true, true);
        grid->tree().voxelizeActiveTiles();
        openvdb::tree::LeafManager<openvdb::BoolTree> leaves(grid->tree());
        std::vector<plausible::LeafMask> hull;
        for (std::size_t l = 0; l < leaves.leafCount(); ++l) hull.push_back(plausible::leaf_mask(leaves.leaf(l)));
        for (auto it = grid->tree().beginValueOn(); it; ++it)
            if (field(it.getCoord()) > 0) it.setValueOff();
        back = plausible::keep_hull_genus(leaves, hull, [&](std::size_t l, openvdb::Index off) {
            return field(leaves.leaf(l).offsetToGlobalCoord(off));
        });
        return grid;
    };
    std::size_t one = 0, many = 0;
    const auto a = run(1, one);
    const auto b = run(4, many);
    EXPECT_GT(one, 1000u) << "the removal should need its walls";
    // The block has no handle, and no removal opens one (a chunk that cut a part off and
    // opened a tunnel went at once: its own voxels, on while it was checked, held the kept
    // voxels about it together).
    EXPECT_EQ(handles(*a, CoordBBox({0, 0, 0}, {63, 47, 47})), 0);
    EXPECT_EQ(one, many);
    std::size_t differ = 0;
    for (int x = 0; x < 64; ++x)
        for (int y = 0; y < 48; ++y)
            for (int z = 0; z < 48; ++z) differ += a->tree().isValueOn({x, y, z}) != b->tree().isValueOn({x, y, z});
    EXPECT_EQ(differ, 0u);
}

TEST(HullPlausibleGenus, PaddedRowsGiveEachVoxelItsNeighbourhood) {
    // Two random sets over a 3 x 3 x 3 block of leaves (some leaves missing): the padded rows
    // of the centre leaf give every voxel of it the same neighbourhood as lookups one by one,
    // and a mask spills only into the neighbours spill_sides names.
    using plausible::LeafMask;
    auto grid = openvdb::BoolGrid::create(false);
    unsigned seed = 12345;
    const auto next = [&] { return seed = seed * 1103515245u + 12345u, seed >> 16; };
    for (int x = -8; x < 16; ++x)
        for (int y = -8; y < 16; ++y)
            for (int z = -8; z < 16; ++z)
                if ((x >= 0 || y < 8) && next() % 3 == 0) grid->tree().setValueOn({x, y, z}, true);
    grid->tree().touchLeaf({0, 0, 0});
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(grid->tree());
    const std::vector<std::uint32_t> around = plausible::leaf_neighbourhoods(leaves);
    std::vector<LeafMask> a(leaves.leafCount()), b(leaves.leafCount());
    std::size_t centre = 0;
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) {
        a[l] = plausible::leaf_mask(leaves.leaf(l));
        for (auto& w : b[l]) w = std::uint64_t(next()) << 48 ^ std::uint64_t(next()) << 24 ^ next();
        if (leaves.leaf(l).origin() == Coord(0, 0, 0)) centre = l;
    }
    const auto in = [&](const std::vector<LeafMask>& set, const Coord& c) {
        for (std::size_t l = 0; l < leaves.leafCount(); ++l) {
            const Coord o = leaves.leaf(l).origin();
            if (c.x() >> 3 == o.x() >> 3 && c.y() >> 3 == o.y() >> 3 && c.z() >> 3 == o.z() >> 3) {
                const openvdb::Index off = leaves.leaf(l).coordToOffset(c);
                return (set[l][off / 64] >> (off % 64) & 1) != 0;
            }
        }
        return false;
    };
    const plausible::genus_masks::Padded p([&](std::size_t n) { return a[n]; }, [&](std::size_t n) { return b[n]; },
                                           around, centre);
    int wrong = 0;
    for (openvdb::Index off = 0; off < 512; ++off) {
        const Coord c = leaves.leaf(centre).offsetToGlobalCoord(off);
        unsigned na = 0, nb = 0;
        for (int k = 0; k < 27; ++k) {
            const Coord q = c.offsetBy(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
            na |= unsigned(in(a, q)) << k;
            nb |= unsigned(in(b, q)) << k;
        }
        const auto [pa, pb] = p.around(off);
        wrong += pa != na || pb != nb;
    }
    EXPECT_EQ(wrong, 0);
    for (int trial = 0; trial < 200; ++trial) {
        LeafMask m{};
        for (int v = 0; v < 1 + trial % 5; ++v) {
            const unsigned off = next() % 512;
            m[off / 64] |= 1ull << (off % 64);
        }
        const unsigned sides = plausible::genus_masks::spill_sides(m);
        for (int k = 0; k < 27; ++k) {
            const bool spills = plausible::genus_masks::any(plausible::genus_masks::spill(m, k));
            EXPECT_TRUE(!spills || (sides >> k & 1)) << k;
        }
    }
}

TEST(HullPlausibleGenus, AChunkOnWhileCheckedDoesNotHoldTheKeptVoxelsAboutItTogether) {
    // A bar of 24 voxels along x. A piece that cannot go at once goes back on and is checked
    // in chunks; a chunk across the bar cuts it in two, so it may not go at once, even though
    // the kept voxels about it are joined through its own voxels while it is checked. (They
    // were: a chunk of bunny's line art cut a part off and opened a tunnel, Euler unchanged,
    // and went at once.) A chunk at the bar's end cuts nothing and goes.
    auto grid = openvdb::BoolGrid::create(false);
    for (int x = 0; x < 24; ++x) grid->tree().setValueOn(Coord(x, 0, 0), true);
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(grid->tree());
    const std::vector<std::uint32_t> around = plausible::leaf_neighbourhoods(leaves);
    plausible::genus_checks::PieceChecks checks(leaves, around);
    checks.load();
    const auto goes = [&](const Coord& c) {
        plausible::genus_checks::Scratch s;
        s.ready(leaves.leafCount());
        plausible::genus_checks::LeafMasks chunk(leaves.leafCount());
        std::size_t l = 0;
        while (!leaves.leaf(l).getNodeBoundingBox().isInside(c)) ++l;
        const openvdb::Index off = leaves.leaf(l).coordToOffset(c);
        chunk[l][off / 64] |= 1ull << (off % 64);
        return checks.at_once(s, chunk, {l}, 0, true);
    };
    EXPECT_FALSE(goes(Coord(12, 0, 0))) << "across the bar";
    EXPECT_FALSE(goes(Coord(7, 0, 0))) << "across the bar, at a leaf's edge";
    EXPECT_TRUE(goes(Coord(23, 0, 0))) << "at its end";
}
