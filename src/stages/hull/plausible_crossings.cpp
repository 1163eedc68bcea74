// See plausible_crossings.h. The input's leaves of crossings away from the removal are copied;
// those about it are made anew from the input's (or the background's) values, each on the
// thread that fills it, and kept only where they hold a crossing: on spot at 512 the removal
// empties about 5,800 of the input's 11,900 leaves and moves the surface into 5,700 others.
#include "plausible_crossings.h"

#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <unordered_map>

namespace cm::plausible {

namespace {

using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using CrossTree = openvdb::Vec3fTree;
using CrossLeaf = CrossTree::LeafNodeType;

// Whether grid points are on, by leaf: a leaf's mask, or its tile's (or the background's) state.
struct OnLeaf {
    const BoolLeaf* leaf = nullptr;
    bool all = false;
    bool on(openvdb::Index off) const { return leaf ? leaf->isValueOn(off) : all; }
    LeafMask mask() const {
        LeafMask m;
        if (leaf) m = leaf_mask(*leaf);
        else m.fill(all ? ~std::uint64_t(0) : 0);
        return m;
    }
};

OnLeaf on_leaf(const openvdb::BoolGrid& grid, const openvdb::BoolGrid::ConstAccessor& acc, const Coord& origin) {
    OnLeaf s;
    s.leaf = grid.tree().probeConstLeaf(origin);
    if (!s.leaf) s.all = acc.isValueOn(origin);
    return s;
}

// The leaf of `grid` at `origin` (0) and its neighbours above in x, y and z (1 to 3).
void on_leaves(const openvdb::BoolGrid& grid, const openvdb::BoolGrid::ConstAccessor& acc, const Coord& origin,
               OnLeaf (&out)[4]) {
    for (int a = -1; a < 3; ++a) {
        Coord o = origin;
        if (a >= 0) o[a] += int(BoolLeaf::DIM);
        out[a + 1] = on_leaf(grid, acc, o);
    }
}

// The points of a leaf (`nw`: it and its neighbours above, as on_leaves()) with an edge whose
// ends differ (inside one, outside the other): the only points with crossings.
LeafMask differing_points(const OnLeaf (&nw)[4]) {
    LeafMask differ{};
    const LeafMask own = nw[0].mask();
    for (int a = 0; a < 3; ++a) {
        const LeafMask next = nw[a + 1].mask();
        const LeafMask above = neighbour_in(own, &next, 2 * a + 1);
        for (openvdb::Index w = 0; w < 8; ++w) differ[w] |= own[w] ^ above[w];
    }
    return differ;
}

class Recrossing {
public:
    Recrossing(const Volume& in, const openvdb::BoolGrid& now, const std::vector<Coord>& touched, const HullField& hull)
        : in_(in), cross_(*in.crossings), now_(now), touched_(touched), field_at_(hull) {}

    /// The output's crossings.
    openvdb::Vec3fGrid::Ptr make(std::size_t& placed) const;

private:
    bool only_background_tiles() const;
    std::vector<Coord> to_remake() const;
    std::vector<CrossLeaf*> untouched_copies() const;
    std::size_t recross(CrossLeaf& leaf, const openvdb::BoolGrid::ConstAccessor& was,
                        const openvdb::BoolGrid::ConstAccessor& now) const;

    const Volume& in_;
    const openvdb::Vec3fGrid& cross_;
    const openvdb::BoolGrid& now_;
    const std::vector<Coord>& touched_;
    const FieldAt field_at_;
};

openvdb::Vec3fGrid::Ptr Recrossing::make(std::size_t& placed) const {
    const std::vector<Coord> remake = to_remake();
    std::vector<CrossLeaf*> made(remake.size(), nullptr);
    std::atomic<std::size_t> count{0};
    openvdb::Vec3fGrid::Ptr out;
    if (!only_background_tiles()) {
        // The input's tiles carry over only by a whole copy (a tree with such tiles: none is
        // made by hull.marching_intersections): every leaf to re-make made in place.
        out = cross_.deepCopy();
        for (std::size_t k = 0; k < remake.size(); ++k) made[k] = out->tree().touchLeaf(remake[k]);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, remake.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        auto was = in_.occupancy->getConstAccessor();
        auto now = now_.getConstAccessor();
        auto acc = cross_.getConstAccessor();
        std::size_t mine = 0;
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
            if (out) {
                mine += recross(*made[k], was, now);
                continue;
            }
            // A copy of the input's leaf, or a leaf of the background (as the tree's touchLeaf()
            // would make it): allocated here, so each thread maps its own pages.
            const CrossLeaf* old = acc.probeConstLeaf(remake[k]);
            auto* leaf = old ? new CrossLeaf(*old) : new CrossLeaf(remake[k], cross_.background(), false);
            mine += recross(*leaf, was, now);
            if (leaf->isEmpty()) delete leaf;
            else made[k] = leaf;
        }
        count += mine;
    });
    placed = count;
    if (!out) {
        out = cross_.copyWithNewTree();
        for (CrossLeaf* leaf : untouched_copies()) out->tree().addLeaf(leaf);
        for (CrossLeaf* leaf : made)
            if (leaf) out->tree().addLeaf(leaf);
    }
    openvdb::tools::pruneInactive(out->tree());
    return out;
}

// Whether every tile of the input's crossings (not a leaf) is the inactive background.
bool Recrossing::only_background_tiles() const {
    auto it = cross_.tree().cbeginValueAll();
    it.setMaxDepth(CrossTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; it; ++it)
        if (it.isValueOn() || *it != cross_.background()) return false;
    return true;
}

// Of the touched leaves, those whose crossings can change: a leaf of the input's, a tile
// there other than the background, or a point with an edge whose ends differ now. (A leaf
// made anew for none of these, most of them deep inside the hull, would only be cleared and
// pruned again: at 512 more than half of the touched leaves.)
std::vector<Coord> Recrossing::to_remake() const {
    std::vector<Coord> touch = touched_;
    std::vector<std::uint8_t> need(touch.size(), 0);
    const openvdb::Vec3f bg = cross_.background();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, touch.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        auto acc = cross_.getConstAccessor();
        auto now = now_.getConstAccessor();
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
            const Coord& o = touch[k];
            if (acc.probeConstLeaf(o) || acc.isValueOn(o) || acc.getValue(o) != bg) {
                need[k] = 1;
                continue;
            }
            OnLeaf nw[4];
            on_leaves(now_, now, o, nw);
            const LeafMask differ = differing_points(nw);
            for (const std::uint64_t w : differ) need[k] |= w != 0;
        }
    });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < touch.size(); ++k)
        if (need[k]) touch[kept++] = touch[k];
    touch.resize(kept);
    return touch;
}

// Copies of the input's leaves away from the removal (not touched), made in parallel.
std::vector<CrossLeaf*> Recrossing::untouched_copies() const {
    const openvdb::tree::LeafManager<const CrossTree> leaves(cross_.tree());
    std::vector<CrossLeaf*> copies(leaves.leafCount(), nullptr);
    tbb::parallel_for(std::size_t(0), leaves.leafCount(), [&](std::size_t l) {
        const CrossLeaf& leaf = leaves.leaf(l);
        if (!std::binary_search(touched_.begin(), touched_.end(), leaf.origin())) copies[l] = new CrossLeaf(leaf);
    });
    copies.erase(std::remove(copies.begin(), copies.end(), nullptr), copies.end());
    return copies;
}

// One leaf of crossings, a copy of the old crossings' leaf (or their tile's values), made
// anew; returns the crossings placed on the field's zero level.
std::size_t Recrossing::recross(CrossLeaf& leaf, const openvdb::BoolGrid::ConstAccessor& was,
                                const openvdb::BoolGrid::ConstAccessor& now) const {
    constexpr int kStride[3] = {64, 8, 1};
    std::size_t placed = 0;
    // This leaf (0) and its neighbours above in x, y and z (1 to 3), now and before.
    OnLeaf nw[4], wa[4];
    on_leaves(now_, now, leaf.origin(), nw);
    on_leaves(*in_.occupancy, was, leaf.origin(), wa);
    // The points with an edge whose ends differ now; every other point's edges have no crossing.
    const LeafMask differ = differing_points(nw);
    for (openvdb::Index off = 0; off < CrossLeaf::SIZE; ++off) {
        if (!(differ[off >> 6] >> (off & 63) & 1)) {
            leaf.setValueOff(off, openvdb::Vec3f(-1.0f));
            continue;
        }
        const int loc[3] = {int(off >> 6), int((off >> 3) & 7), int(off & 7)};
        const bool ig = nw[0].on(off), rg = !ig && wa[0].on(off);
        openvdb::Vec3f val = leaf.getValue(off);
        bool any = false;
        for (int a = 0; a < 3; ++a) {
            // The point above along a: in this leaf, or the first of the next one's.
            const bool inside = loc[a] < 7;
            const int at = inside ? 0 : a + 1;
            const openvdb::Index qoff =
                inside ? off + openvdb::Index(kStride[a]) : off - openvdb::Index(7 * kStride[a]);
            const bool iq = nw[at].on(qoff), rq = !iq && wa[at].on(qoff);
            if (ig == iq) {
                val[a] = -1.0f;
            } else if (rg || rq) {
                // One end kept (inside), the other removed: the field's zero level
                // (half-way from a voxel the plate repair put back).
                const Coord g = leaf.offsetToGlobalCoord(off);
                Coord q = g;
                q[a] += 1;
                const float sk = field_at_(ig ? g : q), sr = field_at_(ig ? q : g);
                float f = 0.5f;
                if (sk <= 0 && sr > sk) f = std::clamp(-sk / (sr - sk), 0.0f, 1.0f);
                val[a] = ig ? f : 1.0f - f;
                ++placed;
            }
            any = any || val[a] >= 0;
        }
        if (any) leaf.setValueOn(off, val);
        else leaf.setValueOff(off, openvdb::Vec3f(-1.0f));
    }
    return placed;
}

} // namespace

openvdb::Vec3fGrid::Ptr recrossed(const Volume& in, const openvdb::BoolGrid& now, const std::vector<Coord>& touched,
                                  const HullField& hull, std::size_t& placed) {
    return Recrossing(in, now, touched, hull).make(placed);
}

} // namespace cm::plausible
