#include "plausible_volume.h"

#include <openvdb/tools/Prune.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <unordered_map>

#include "leaf_masks.h"

namespace cm::plausible {

namespace {
using LeafT = openvdb::BoolTree::LeafNodeType;
} // namespace

std::shared_ptr<Volume> plausible_volume(const Volume& in, const openvdb::BoolGrid::Ptr& occ,
                                         openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                                         const std::vector<std::size_t>& base, std::vector<std::uint8_t>& removed,
                                         const std::vector<float>& field, int maxdim, PlausibleStats& st,
                                         const std::function<void(double)>& step) {
    const std::size_t nleaf = leaves.leafCount();
    // The hull's voxels, as numbered, before the removal changes the leaves.
    // (Leaves that come back full become tiles below: their origins are kept here too.)
    std::vector<LeafMask> hull_masks(nleaf);
    std::vector<Coord> hull_origin(nleaf);
    tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
        hull_origin[l] = leaves.leaf(l).origin();
        hull_masks[l] = leaf_mask(leaves.leaf(l));
    });
    // 6. The output occupancy: removed voxels off; leaves full with 26 full neighbours back
    // to tiles (so every inside point next to the outside stays a leaf voxel, volume.h).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            std::size_t i = base[l];
            auto& leaf = leaves.leaf(l);
            std::vector<openvdb::Index> off;
            for (auto it = leaf.cbeginValueOn(); it; ++it)
                if (removed[i++]) off.push_back(it.pos());
            for (const auto o : off) leaf.setValueOff(o, false);
        }
    });
    // 6a. No plate one voxel thin where the removal cut on both sides of it: Marching Cubes
    // puts its two faces on mirrored crossings, and smoothing draws them onto one another
    // (coincident vertices, crossing faces). Such a voxel's removed neighbours along that
    // axis come back (only adding: every line of sight keeps what it had). Two passes: a
    // voxel put back can be such a plate along another axis, and on small or lacy parts
    // putting its neighbours back in turn would go on growing the volume.
    // Only leaves with a removed voxel in them or across a face can hold such a plate.
    std::vector<char> near_cut(nleaf, 0);
    {
        std::vector<char> cut(nleaf, 0);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            for (std::size_t i = base[l]; i < base[l + 1] && !cut[l]; ++i) cut[l] = removed[i];
        });
        std::set<Coord> origins;
        for (std::size_t l = 0; l < nleaf; ++l)
            if (cut[l]) origins.insert(leaves.leaf(l).origin());
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            near_cut[l] = cut[l];
            for (int d = 0; d < 6 && !near_cut[l]; ++d) {
                Coord o = leaves.leaf(l).origin();
                o[d / 2] += (d & 1) ? int(LeafT::DIM) : -int(LeafT::DIM);
                near_cut[l] = origins.count(o) > 0;
            }
        });
    }
    const auto nbr = leaf_neighbours(leaves);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::vector<Coord>> back(nleaf);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            if (!near_cut[l]) return;
            // Leaf masks, now and in the hull (the removal only took voxels of existing leaves).
            auto now_of = [&](std::uint32_t k) { return leaf_mask(leaves.leaf(k)); };
            const LeafMask now = now_of(std::uint32_t(l));
            for (int a = 0; a < 3; ++a) {
                LeafMask on[2], was[2], nm;
                for (int side = 0; side < 2; ++side) {
                    const int d = 2 * a + side;
                    const std::uint32_t k = nbr[l][std::size_t(d)];
                    if (k != kNoLeaf) nm = now_of(k);
                    on[side] = neighbour_in(now, k != kNoLeaf ? &nm : nullptr, d);
                    was[side] = neighbour_in(hull_masks[l], k != kNoLeaf ? &hull_masks[k] : nullptr, d);
                }
                for (openvdb::Index w = 0; w < 8; ++w) {
                    // On, with both neighbours along a off and one of them in the hull.
                    std::uint64_t plate = now[w] & ~on[0][w] & ~on[1][w] & (was[0][w] | was[1][w]);
                    for (; plate; plate &= plate - 1) {
                        const int b = __builtin_ctzll(plate);
                        const Coord g = leaves.leaf(l).offsetToGlobalCoord(w * 64 + openvdb::Index(b));
                        for (int side = 0; side < 2; ++side)
                            if (was[side][w] >> b & 1) {
                                Coord q = g;
                                q[a] += side ? 1 : -1;
                                back[l].push_back(q);
                            }
                    }
                }
            }
        });
        std::size_t added = 0;
        for (const auto& b : back)
            for (const Coord& c : b)
                if (!occ->tree().isValueOn(c)) {
                    occ->tree().setValueOn(c, true);
                    ++added;
                }
        st.removed -= std::min(st.removed, added);
        st.thickened += added;
        if (added == 0) break;
    }
    // 6b. What is still removed and reaches no point outside the hull is a cavity sealed inside
    // the kept volume: Marching Cubes would give it a closed shell of its own, unseen and
    // useless. It is put back (only adding: no line of sight loses a voxel).
    {
        std::vector<LeafMask> cut_masks(nleaf, LeafMask{});
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            if (!near_cut[l]) return;
            const auto& mask = leaves.leaf(l).getValueMask();
            for (openvdb::Index w = 0; w < 8; ++w) cut_masks[l][w] = hull_masks[l][w] & ~mask.getWord<std::uint64_t>(w);
        });
        const std::vector<LeafMask> pockets = sealed_pockets(leaves, hull_masks, cut_masks);
        std::size_t filled = 0;
        for (std::size_t l = 0; l < nleaf; ++l) {
            if (!near_cut[l]) continue;
            auto& leaf = leaves.leaf(l);
            std::size_t i = base[l];
            for (openvdb::Index w = 0; w < 8; ++w)
                for (std::uint64_t bits = hull_masks[l][w]; bits; bits &= bits - 1, ++i) {
                    const int b = __builtin_ctzll(bits);
                    if (!(pockets[l][w] >> b & 1)) continue;
                    leaf.setValueOn(w * 64 + openvdb::Index(b), true);
                    removed[i] = 0;
                    ++filled;
                }
        }
        st.cavities_filled = filled;
        st.removed -= std::min(st.removed, filled);
    }
    // 6c. Pieces of the kept volume apart from the main body (a part whose connection the
    // removal took: an ear kept as a thin part, a hand) would float in the mesh: each is joined
    // to the body by the shortest path back through the removed voxels (only adding: no line
    // of sight loses a voxel).
    {
        std::vector<LeafMask> kept(nleaf);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) { kept[l] = leaf_mask(leaves.leaf(l)); });
        std::size_t joined = 0;
        const std::vector<Coord> path = bridges(leaves, nbr, hull_masks, kept, std::max(8, maxdim / 16), &joined);
        // A path one voxel wide would be a strand a cell thin in the mesh: it is thickened by
        // its face neighbours within the hull.
        std::size_t added = 0;
        auto hull_acc = in.occupancy->getConstAccessor();
        for (const Coord& c : path)
            for (int k = 0; k < 7; ++k) {
                Coord q = c;
                if (k > 0) q[(k - 1) / 2] += (k & 1) ? 1 : -1;
                if (hull_acc.isValueOn(q) && !occ->tree().isValueOn(q)) occ->tree().setValueOn(q, true), ++added;
            }
        st.pieces_joined = joined;
        st.removed -= std::min(st.removed, added);
    }
    {
        // A leaf comes back as a tile when it and its 26 neighbours are full (each reached
        // through face neighbours, which must be full themselves).
        std::vector<char> whole(nleaf), tile(nleaf, 0);
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) { whole[l] = leaves.leaf(l).isValueMaskOn(); });
        auto step_to = [&](std::uint32_t l, int axis, int dir) {
            if (l == kNoLeaf || dir == 0) return l;
            const std::uint32_t k = nbr[l][std::size_t(2 * axis + (dir > 0))];
            return k != kNoLeaf && whole[k] ? k : kNoLeaf;
        };
        tbb::parallel_for(std::size_t(0), nleaf, [&](std::size_t l) {
            if (!whole[l]) return;
            bool all = true;
            for (int dx = -1; dx <= 1 && all; ++dx)
                for (int dy = -1; dy <= 1 && all; ++dy)
                    for (int dz = -1; dz <= 1 && all; ++dz)
                        all = step_to(step_to(step_to(std::uint32_t(l), 0, dx), 1, dy), 2, dz) != kNoLeaf;
            tile[l] = all;
        });
        std::vector<Coord> full;
        for (std::size_t l = 0; l < nleaf; ++l)
            if (tile[l]) full.push_back(leaves.leaf(l).origin());
        for (const Coord& o : full) occ->tree().addTile(1, o, true, true);
    }
    step(0.8);

    // 7. Crossings: unchanged where an edge still runs from an inside point to a point
    // outside the hull; the smoothed field's zero crossing on edges into the removed region.
    std::shared_ptr<Volume> out = std::make_shared<Volume>();
    out->views = in.views;
    out->silhouette_tables = in.silhouette_tables;
    out->occupancy = occ;
    // Thin parts between grid points hang on the hull's surface next to them: where the
    // removal took any grid point around one, it would float free, so it goes.
    {
        auto enter = openvdb::GridBase::grid<openvdb::Vec3fGrid>(in.find_extra("thin_enter"));
        auto leave = openvdb::GridBase::grid<openvdb::Vec3fGrid>(in.find_extra("thin_leave"));
        std::size_t dropped = 0;
        for (const auto& g : in.extra) {
            if (g == enter || g == leave) continue;
            out->extra.push_back(g);
        }
        if (enter && leave) {
            auto e2 = enter->deepCopy(), l2 = leave->deepCopy();
            auto was = in.occupancy->getConstAccessor();
            auto now = occ->getConstAccessor();
            auto la = l2->getAccessor();
            std::vector<Coord> off;
            for (auto it = e2->beginValueOn(); it; ++it) {
                const Coord p = it.getCoord();
                openvdb::Vec3f te = *it, tl = la.getValue(p);
                bool any = false;
                for (int a = 0; a < 3; ++a) {
                    if (te[a] < 0) continue;
                    Coord q = p;
                    q[a] += 1;
                    bool cut = false;
                    for (int k = 0; k < 27 * 2 && !cut; ++k) {
                        const Coord g = (k < 27 ? p : q).offsetBy(k % 27 / 9 - 1, k % 9 / 3 - 1, k % 3 - 1);
                        cut = was.isValueOn(g) && !now.isValueOn(g);
                    }
                    if (cut) {
                        te[a] = tl[a] = -1.0f;
                        ++dropped;
                    } else {
                        any = true;
                    }
                }
                if (any) {
                    it.setValue(te);
                    la.setValue(p, tl);
                } else {
                    off.push_back(p);
                }
            }
            for (const Coord& p : off) {
                e2->tree().setValueOff(p, openvdb::Vec3f(-1.0f));
                l2->tree().setValueOff(p, openvdb::Vec3f(-1.0f));
            }
            if (e2->activeVoxelCount() > 0) {
                out->extra.push_back(e2);
                out->extra.push_back(l2);
            }
        }
        st.thin_dropped = dropped;
    };
    if (in.crossings) {
        auto cross = in.crossings->deepCopy();
        // The leaves to revisit: those holding removed voxels, and the ones just below in
        // x, y or z (an edge is stored at its lower end).
        std::vector<Coord> touch;
        {
            std::vector<std::uint8_t> has(nleaf, 0);
            for (std::size_t l = 0; l < nleaf; ++l)
                for (std::size_t i = base[l]; i < base[l + 1] && !has[l]; ++i) has[l] = removed[i];
            for (std::size_t l = 0; l < nleaf; ++l) {
                if (!has[l]) continue;
                const Coord o = leaves.leaf(l).origin();
                for (int a = -1; a < 3; ++a) {
                    Coord q = o;
                    if (a >= 0) q[a] -= 8;
                    touch.push_back(q);
                }
            }
        }
        std::sort(touch.begin(), touch.end());
        touch.erase(std::unique(touch.begin(), touch.end()), touch.end());
        std::vector<openvdb::Vec3fTree::LeafNodeType*> cl(touch.size());
        for (std::size_t k = 0; k < touch.size(); ++k) cl[k] = cross->tree().touchLeaf(touch[k]);
        // The field at a grid point of the hull (0 elsewhere), through the voxels' numbering.
        std::unordered_map<std::uint64_t, std::uint32_t> leaf_of;
        leaf_of.reserve(nleaf * 2);
        for (std::size_t l = 0; l < nleaf; ++l) leaf_of.emplace(leaf_key(hull_origin[l]), std::uint32_t(l));
        auto field_at = [&](const Coord& g) {
            const auto it = leaf_of.find(leaf_key(g));
            if (it == leaf_of.end()) return 0.0f;
            const std::size_t l = it->second;
            const openvdb::Index off = LeafT::coordToOffset(g);
            const std::uint64_t bit = std::uint64_t(1) << (off & 63), word = hull_masks[l][off >> 6];
            if (!(word & bit)) return 0.0f;
            std::size_t i = base[l] + std::size_t(__builtin_popcountll(word & (bit - 1)));
            for (openvdb::Index w = 0; w < (off >> 6); ++w) i += std::size_t(__builtin_popcountll(hull_masks[l][w]));
            return field[i];
        };
        std::atomic<std::size_t> placed{0};
        // Whether grid points are on, by leaf: a leaf's mask, or its tile's (or the background's) state.
        struct OnLeaf {
            const LeafT* leaf = nullptr;
            bool all = false;
            bool on(openvdb::Index off) const { return leaf ? leaf->isValueOn(off) : all; }
        };
        auto on_leaf = [](const openvdb::BoolGrid& grid, auto& acc, const Coord& origin) {
            OnLeaf s;
            s.leaf = grid.tree().probeConstLeaf(origin);
            if (!s.leaf) s.all = acc.isValueOn(origin);
            return s;
        };
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cl.size()), [&](const tbb::blocked_range<std::size_t>& r) {
            auto was = in.occupancy->getConstAccessor();
            auto now = occ->getConstAccessor();

            std::size_t mine = 0;
            constexpr int kStride[3] = {64, 8, 1};
            for (std::size_t k = r.begin(); k != r.end(); ++k) {
                auto* leaf = cl[k]; // a copy of the old crossings' leaf (or their tile's values)
                // This leaf (0) and its neighbours above in x, y and z (1 to 3), now and before.
                OnLeaf nw[4], wa[4];
                for (int a = -1; a < 3; ++a) {
                    Coord o = leaf->origin();
                    if (a >= 0) o[a] += int(LeafT::DIM);
                    nw[a + 1] = on_leaf(*occ, now, o);
                    wa[a + 1] = on_leaf(*in.occupancy, was, o);
                }
                for (openvdb::Index off = 0; off < openvdb::Vec3fTree::LeafNodeType::SIZE; ++off) {
                    const int loc[3] = {int(off >> 6), int((off >> 3) & 7), int(off & 7)};
                    const bool ig = nw[0].on(off), rg = !ig && wa[0].on(off);
                    openvdb::Vec3f val = leaf->getValue(off);
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
                            const Coord g = leaf->offsetToGlobalCoord(off);
                            Coord q = g;
                            q[a] += 1;
                            const float sk = field_at(ig ? g : q), sr = field_at(ig ? q : g);
                            float f = 0.5f;
                            if (sk <= 0 && sr > sk) f = std::clamp(-sk / (sr - sk), 0.0f, 1.0f);
                            val[a] = ig ? f : 1.0f - f;
                            ++mine;
                        }
                        any = any || val[a] >= 0;
                    }
                    if (any) leaf->setValueOn(off, val);
                    else leaf->setValueOff(off, openvdb::Vec3f(-1.0f));
                }
            }
            placed += mine;
        });
        st.new_crossings = placed;
        openvdb::tools::pruneInactive(cross->tree());
        out->crossings = cross;
    }
    return out;
}

} // namespace cm::plausible
