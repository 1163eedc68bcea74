// Steps 6 and 7 of hull.plausible (plausible_state.h): from the voxels the field removes to
// the volume the extractors take. 6: the output occupancy (removed voxels off, plates one cell
// thin put back, sealed pockets filled, pieces cut off bridged back to the body, full leaves
// back to tiles); 7: the thin parts that would float free dropped (plausible_thin.h), and the
// crossings: the hull's own where an edge still runs to the outside of the hull, the field's
// zero level on edges into the removed region (plausible_crossings.h).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <set>

#include "leaf_masks.h"
#include "plausible_crossings.h"
#include "plausible_genus.h"
#include "plausible_handles.h"
#include "plausible_pieces.h"
#include "plausible_state.h"
#include "plausible_thin.h"

namespace cm::plausible {

namespace {

// The output volume's steps over the voxelized hull (HullVoxels), whose occupancy becomes
// the output's.
class OutputVolume {
public:
    OutputVolume(const Volume& in, HullVoxels& vox, UninitVector<std::uint8_t>& removed,
                 const UninitVector<float>& field, PlausibleStats& st)
        : in_(in), vox_(vox), removed_(removed), field_(field), st_(st), nleaf_(vox.nleaf) {}

    /// 6. The removed voxels off. The hull's voxels, as numbered, are kept first.
    void cut();
    /// 6a. No plate one voxel thin where the removal cut on both sides of it.
    void thicken_plates();
    /// 6b. Sealed cavities put back.
    void fill_pockets();
    /// 6c. Pieces apart from the main body joined to it.
    void join_pieces();
    /// 6c. The kept voxels now, per leaf.
    std::vector<LeafMask> kept_masks() const;
    /// 6d. No handle the hull has not (plausible_genus.h).
    void keep_genus();
    /// 6e. The handles no line of sight needs cut (plausible_handles.h).
    void cut_handles(const std::vector<RayRaster>& rays);
    /// 6. Leaves full with 26 full neighbours back to tiles.
    void make_tiles();
    /// 7. The output volume: the occupancy, the thin parts that still hang on the surface and
    /// the crossings.
    std::shared_ptr<Volume> output();

private:
    void find_near_cut();
    std::size_t bridge_pieces(int reach);
    std::vector<std::vector<Coord>> plates() const;
    void drop_thin_parts(Volume& out) const;
    void place_crossings(Volume& out) const;
    std::vector<Coord> touched_leaves() const;

    const Volume& in_;
    HullVoxels& vox_;
    UninitVector<std::uint8_t>& removed_;
    const UninitVector<float>& field_;
    PlausibleStats& st_;
    const std::size_t nleaf_;
    // The hull's voxels by leaf (leaves that come back full become tiles: their origins are
    // kept too), the leaves with a removed voxel in them or across a face, and each leaf's
    // face neighbours.
    std::vector<LeafMask> hull_masks_;
    std::vector<Coord> hull_origin_;
    std::vector<char> near_cut_;
    std::vector<std::array<std::uint32_t, 6>> nbr_;
};

void OutputVolume::cut() {
    auto& leaves = vox_.leaves;
    hull_masks_.resize(nleaf_);
    hull_origin_.resize(nleaf_);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        hull_origin_[l] = leaves.leaf(l).origin();
        hull_masks_[l] = leaf_mask(leaves.leaf(l));
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf_), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            std::size_t i = vox_.base[l];
            auto& leaf = leaves.leaf(l);
            std::vector<openvdb::Index> off;
            for (auto it = leaf.cbeginValueOn(); it; ++it)
                if (removed_[i++]) off.push_back(it.pos());
            for (const auto o : off) leaf.setValueOff(o, false);
        }
    });
}

// Only leaves with a removed voxel in them or across a face can hold a plate.
void OutputVolume::find_near_cut() {
    near_cut_.assign(nleaf_, 0);
    std::vector<char> cut(nleaf_, 0);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        for (std::size_t i = vox_.base[l]; i < vox_.base[l + 1] && !cut[l]; ++i) cut[l] = removed_[i];
    });
    std::set<Coord> origins;
    for (std::size_t l = 0; l < nleaf_; ++l)
        if (cut[l]) origins.insert(vox_.leaves.leaf(l).origin());
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        near_cut_[l] = cut[l];
        for (int d = 0; d < 6 && !near_cut_[l]; ++d) {
            Coord o = vox_.leaves.leaf(l).origin();
            o[d / 2] += (d & 1) ? int(LeafT::DIM) : -int(LeafT::DIM);
            near_cut_[l] = origins.count(o) > 0;
        }
    });
}

// Marching Cubes puts the two faces of a plate one voxel thin on mirrored crossings, and
// smoothing draws them onto one another (coincident vertices, crossing faces). Such a voxel's
// removed neighbours along that axis come back (only adding: every line of sight keeps what it
// had). Two passes: a voxel put back can be such a plate along another axis, and on small or
// lacy parts putting its neighbours back in turn would go on growing the volume.
void OutputVolume::thicken_plates() {
    find_near_cut();
    nbr_ = leaf_neighbours(vox_.leaves);
    auto& tree = vox_.occ->tree();
    for (int pass = 0; pass < 2; ++pass) {
        const std::vector<std::vector<Coord>> back = plates();
        std::size_t added = 0;
        for (const auto& b : back)
            for (const Coord& c : b)
                if (!tree.isValueOn(c)) {
                    tree.setValueOn(c, true);
                    ++added;
                }
        st_.removed -= std::min(st_.removed, added);
        st_.thickened += added;
        if (added == 0) break;
    }
}

// Per leaf, the removed neighbours of its plates to put back.
std::vector<std::vector<Coord>> OutputVolume::plates() const {
    const auto& leaves = vox_.leaves;
    std::vector<std::vector<Coord>> back(nleaf_);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        if (!near_cut_[l]) return;
        // Leaf masks, now and in the hull (the removal only took voxels of existing leaves).
        auto now_of = [&](std::uint32_t k) { return leaf_mask(leaves.leaf(k)); };
        const LeafMask now = now_of(std::uint32_t(l));
        for (int a = 0; a < 3; ++a) {
            LeafMask on[2], was[2], nm;
            for (int side = 0; side < 2; ++side) {
                const int d = 2 * a + side;
                const std::uint32_t k = nbr_[l][std::size_t(d)];
                if (k != kNoLeaf) nm = now_of(k);
                on[side] = neighbour_in(now, k != kNoLeaf ? &nm : nullptr, d);
                was[side] = neighbour_in(hull_masks_[l], k != kNoLeaf ? &hull_masks_[k] : nullptr, d);
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
    return back;
}

// What is still removed and reaches no point outside the hull is a cavity sealed inside the
// kept volume: Marching Cubes would give it a closed shell of its own, unseen and useless. It
// is put back (only adding: no line of sight loses a voxel).
void OutputVolume::fill_pockets() {
    auto& leaves = vox_.leaves;
    std::vector<LeafMask> cut_masks(nleaf_, LeafMask{});
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        if (!near_cut_[l]) return;
        const auto& mask = leaves.leaf(l).getValueMask();
        for (openvdb::Index w = 0; w < 8; ++w) cut_masks[l][w] = hull_masks_[l][w] & ~mask.getWord<std::uint64_t>(w);
    });
    const std::vector<LeafMask> pockets = sealed_pockets(nbr_, hull_masks_, cut_masks);
    // Per leaf, in parallel (each leaf's voxels and flags are its own).
    std::atomic<std::size_t> filled{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf_), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t mine = 0;
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            if (!near_cut_[l]) continue;
            auto& leaf = leaves.leaf(l);
            std::size_t i = vox_.base[l];
            for (openvdb::Index w = 0; w < 8; ++w)
                for (std::uint64_t bits = hull_masks_[l][w]; bits; bits &= bits - 1, ++i) {
                    const int b = __builtin_ctzll(bits);
                    if (!(pockets[l][w] >> b & 1)) continue;
                    leaf.setValueOn(w * 64 + openvdb::Index(b), true);
                    removed_[i] = 0;
                    ++mine;
                }
        }
        filled += mine;
    });
    st_.cavities_filled = filled;
    st_.removed -= std::min(st_.removed, filled.load());
}

// Pieces of the kept volume apart from the main body (a part whose connection the removal
// took: an ear kept as a thin part, a hand) would float in the mesh: each is joined to the body
// by the shortest path back through the removed voxels (only adding: no line of sight loses a
// voxel). What is farther from the body than the bridges reach is sorted by its size
// (plausible_pieces.h): a crumb goes, a larger part is joined however far.
void OutputVolume::join_pieces() {
    const int reach = std::max(8, vox_.maxdim / 8);
    st_.pieces_joined = bridge_pieces(reach);
    const FarPieces far = far_pieces(vox_.leaves, nbr_, hull_masks_, kept_masks(), reach);
    auto& leaves = vox_.leaves;
    for (const FarVoxel& v : far.crumbs) {
        leaves.leaf(v.leaf).setValueOff(v.offset, false);
        const LeafMask& hull = hull_masks_[v.leaf];
        std::size_t i = vox_.base[v.leaf];
        for (openvdb::Index w = 0; w < v.offset >> 6; ++w) i += std::size_t(__builtin_popcountll(hull[w]));
        i += std::size_t(__builtin_popcountll(hull[v.offset >> 6] & ((std::uint64_t(1) << (v.offset & 63)) - 1)));
        removed_[i] = 1;
    }
    st_.removed += far.crumbs.size();
    st_.far_dropped = far.crumbs.size();
    // (The longest path within the hull is shorter than its voxel count.)
    if (far.large_pieces > 0) st_.pieces_joined += bridge_pieces(int(std::min<std::size_t>(vox_.n, 1u << 30)));
}

std::vector<LeafMask> OutputVolume::kept_masks() const {
    std::vector<LeafMask> kept(nleaf_);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) { kept[l] = leaf_mask(vox_.leaves.leaf(l)); });
    return kept;
}

// The pieces apart from the body within `reach` voxels of it joined to it; returns their
// number.
std::size_t OutputVolume::bridge_pieces(int reach) {
    std::size_t joined = 0;
    const std::vector<Coord> path = bridges(vox_.leaves, nbr_, hull_masks_, kept_masks(), reach, &joined);
    // A path one voxel wide would be a strand a cell thin in the mesh: it is thickened by
    // its face neighbours within the hull.
    std::size_t added = 0;
    auto hull_acc = in_.occupancy->getConstAccessor();
    auto& tree = vox_.occ->tree();
    for (const Coord& c : path)
        for (int k = 0; k < 7; ++k) {
            Coord q = c;
            if (k > 0) q[(k - 1) / 2] += (k & 1) ? 1 : -1;
            if (hull_acc.isValueOn(q) && !tree.isValueOn(q)) tree.setValueOn(q, true), ++added;
        }
    st_.removed -= std::min(st_.removed, added);
    return joined;
}

// Removed voxels whose removal opened a tunnel through the kept volume put back
// (plausible_genus.h; only adding: no line of sight loses a voxel).
void OutputVolume::keep_genus() {
    // The field of voxel `off` of leaf l: its number, the hull's voxels before it (those
    // before its word counted once per word).
    std::vector<std::array<std::size_t, 8>> first(nleaf_);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        std::size_t i = vox_.base[l];
        for (std::size_t w = 0; w < 8; ++w) first[l][w] = i, i += std::size_t(__builtin_popcountll(hull_masks_[l][w]));
    });
    const auto field_at = [&](std::size_t l, openvdb::Index off) {
        const std::uint64_t below = hull_masks_[l][off >> 6] & ((1ull << (off & 63)) - 1);
        return field_[first[l][off >> 6] + std::size_t(__builtin_popcountll(below))];
    };
    const std::size_t back = keep_hull_genus(vox_.leaves, hull_masks_, field_at);
    st_.genus_kept = back;
    st_.removed -= std::min(st_.removed, back);
}

// The deepest a cut of a handle reaches, in cells of a grid 256 across: a touch of two parts
// in one view is that thin (a camel's knees, a hand on a hip: 2 to 4 cells); a ring drawn as
// one (a handle, a torus) is thicker.
constexpr double kTouchCells = 5.0;

// The voxels the cut takes out are removed ones: the crossings about them are placed anew.
void OutputVolume::cut_handles(const std::vector<RayRaster>& rays) {
    // The leaves by origin, for the voxels cut (made at the first: most volumes have none).
    std::vector<std::pair<Coord, std::size_t>> leaf_at;
    const int most = std::max(2, int(std::lround(kTouchCells * vox_.maxdim / 256.0)));
    const HandleCut cut = plausible::cut_handles(vox_.leaves, rays, most, [&](const Coord& c) {
        if (leaf_at.empty()) {
            for (std::size_t l = 0; l < nleaf_; ++l) leaf_at.emplace_back(hull_origin_[l], l);
            std::sort(leaf_at.begin(), leaf_at.end());
        }
        const Coord o(c.x() & ~7, c.y() & ~7, c.z() & ~7);
        const auto it = std::lower_bound(leaf_at.begin(), leaf_at.end(), std::make_pair(o, std::size_t(0)));
        const std::size_t l = it->second;
        const openvdb::Index off = LeafT::coordToOffset(c);
        const std::uint64_t below = hull_masks_[l][off >> 6] & ((1ull << (off & 63)) - 1);
        std::size_t i = vox_.base[l] + std::size_t(__builtin_popcountll(below));
        for (openvdb::Index w = 0; w < (off >> 6); ++w) i += std::size_t(__builtin_popcountll(hull_masks_[l][w]));
        removed_[i] = 1;
    });
    st_.handles = std::size_t(std::max(0L, cut.handles));
    st_.handles_left = std::size_t(std::max(0L, cut.handles_left));
    st_.handle_voxels = cut.voxels;
    st_.removed += cut.voxels;
}

// A leaf comes back as a tile when it and its 26 neighbours are full (each reached through
// face neighbours, which must be full themselves), so every inside point next to the outside
// stays a leaf voxel (volume.h).
void OutputVolume::make_tiles() {
    auto& leaves = vox_.leaves;
    std::vector<char> whole(nleaf_), tile(nleaf_, 0);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) { whole[l] = leaves.leaf(l).isValueMaskOn(); });
    auto step_to = [&](std::uint32_t l, int axis, int dir) {
        if (l == kNoLeaf || dir == 0) return l;
        const std::uint32_t k = nbr_[l][std::size_t(2 * axis + (dir > 0))];
        return k != kNoLeaf && whole[k] ? k : kNoLeaf;
    };
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        if (!whole[l]) return;
        bool all = true;
        for (int dx = -1; dx <= 1 && all; ++dx)
            for (int dy = -1; dy <= 1 && all; ++dy)
                for (int dz = -1; dz <= 1 && all; ++dz)
                    all = step_to(step_to(step_to(std::uint32_t(l), 0, dx), 1, dy), 2, dz) != kNoLeaf;
        tile[l] = all;
    });
    std::vector<Coord> full;
    for (std::size_t l = 0; l < nleaf_; ++l)
        if (tile[l]) full.push_back(leaves.leaf(l).origin());
    for (const Coord& o : full) vox_.occ->tree().addTile(1, o, true, true);
}

std::shared_ptr<Volume> OutputVolume::output() {
    std::shared_ptr<Volume> out = std::make_shared<Volume>();
    out->views = in_.views;
    out->silhouette_tables = in_.silhouette_tables;
    out->occupancy = vox_.occ;
    drop_thin_parts(*out);
    if (in_.crossings) place_crossings(*out);
    return out;
}

// Thin parts that would float free go (plausible_thin.h).
void OutputVolume::drop_thin_parts(Volume& out) const {
    st_.thin_dropped = keep_hanging_thin_parts(in_, *vox_.occ, out);
}

// The leaves of crossings to revisit: those holding removed voxels, and the ones just below in
// x, y or z (an edge is stored at its lower end). Sorted, each once.
std::vector<Coord> OutputVolume::touched_leaves() const {
    std::vector<Coord> touch;
    std::vector<std::uint8_t> has(nleaf_, 0);
    tbb::parallel_for(std::size_t(0), nleaf_, [&](std::size_t l) {
        for (std::size_t i = vox_.base[l]; i < vox_.base[l + 1] && !has[l]; ++i) has[l] = removed_[i];
    });
    for (std::size_t l = 0; l < nleaf_; ++l) {
        if (!has[l]) continue;
        // (The hull's origin: a leaf that came back full may be a tile now.)
        const Coord o = hull_origin_[l];
        for (int a = -1; a < 3; ++a) {
            Coord q = o;
            if (a >= 0) q[a] -= 8;
            touch.push_back(q);
        }
    }
    std::sort(touch.begin(), touch.end());
    touch.erase(std::unique(touch.begin(), touch.end()), touch.end());
    return touch;
}

// Crossings: unchanged where an edge still runs from an inside point to a point outside the
// hull; the smoothed field's zero crossing on edges into the removed region
// (plausible_crossings.h).
void OutputVolume::place_crossings(Volume& out) const {
    std::size_t placed = 0;
    out.crossings =
        recrossed(in_, *vox_.occ, touched_leaves(), HullField{hull_masks_, hull_origin_, vox_.base, field_}, placed);
    st_.new_crossings = placed;
}

} // namespace

std::shared_ptr<Volume> plausible_volume(const Volume& in, HullVoxels& vox, UninitVector<std::uint8_t>& removed,
                                         const UninitVector<float>& field, const std::vector<RayRaster>& rays,
                                         bool cut_handles, PlausibleStats& st, const Progress& progress) {
    OutputVolume out(in, vox, removed, field, st);
    // 6. The output occupancy.
    out.cut();
    out.thicken_plates();
    out.fill_pockets();
    out.join_pieces();
    st.step_done("volume");
    out.keep_genus();
    st.step_done("genus");
    if (cut_handles) out.cut_handles(rays);
    st.step_done("handles");
    out.make_tiles();
    progress(0.8);
    // 7. Crossings and thin parts.
    std::shared_ptr<Volume> v = out.output();
    st.step_done("crossings");
    return v;
}

} // namespace cm::plausible
