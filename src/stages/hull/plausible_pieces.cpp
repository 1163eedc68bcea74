// Far pieces of the kept volume (plausible_pieces.h): the main body by a flood of the leaf
// masks, the voxels apart from it split into 6-connected pieces by a search over their grid
// points (they are few: what the bridges left).
#include "plausible_pieces.h"

#include <algorithm>
#include <unordered_map>

namespace cm::plausible {

namespace {

using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

// The kept voxels 6-connected to the fullest leaf's: the main body.
std::vector<LeafMask> main_body(const Leaves& leaves, const std::vector<LeafMask>& kept) {
    std::size_t best = 0, most = 0;
    for (std::size_t l = 0; l < kept.size(); ++l) {
        std::size_t c = 0;
        for (const auto w : kept[l]) c += std::size_t(__builtin_popcountll(w));
        if (c > most) most = c, best = l;
    }
    std::vector<LeafMask> seed(kept.size(), LeafMask{});
    if (most == 0) return seed;
    seed[best] = kept[best];
    return flood(leaves, seed, kept, false);
}

// The voxels of a set of leaf masks, looked up by grid point.
class MaskSet {
public:
    MaskSet(const Leaves& leaves, const std::vector<LeafMask>& masks) : masks_(masks) {
        for (std::size_t l = 0; l < masks.size(); ++l) index_[leaf_key(leaves.leaf(l).origin())] = std::uint32_t(l);
    }
    /// Whether grid point c is in the set; its leaf and offset then in `v`.
    bool find(const Coord& c, FarVoxel& v) const {
        const auto it = index_.find(leaf_key(c));
        if (it == index_.end()) return false;
        v = {it->second, LeafT::coordToOffset(c)};
        return masks_[v.leaf][v.offset >> 6] >> (v.offset & 63) & 1;
    }

private:
    using LeafT = openvdb::BoolTree::LeafNodeType;
    const std::vector<LeafMask>& masks_;
    std::unordered_map<std::uint64_t, std::uint32_t> index_;
};

} // namespace

FarPieces far_pieces(const Leaves& leaves, const std::vector<LeafMask>& hull, const std::vector<LeafMask>& kept,
                     int reach) {
    FarPieces out;
    const std::size_t nleaf = kept.size();
    const std::vector<LeafMask> body = main_body(leaves, kept);
    // Apart from the body, but within the hull's piece of it.
    const std::vector<LeafMask> within = flood(leaves, body, hull, false);
    std::vector<LeafMask> apart(nleaf);
    std::vector<FarVoxel> seeds;
    for (std::size_t l = 0; l < nleaf; ++l)
        for (int w = 0; w < 8; ++w) {
            apart[l][std::size_t(w)] = kept[l][std::size_t(w)] & ~body[l][std::size_t(w)] & within[l][std::size_t(w)];
            for (std::uint64_t b = apart[l][std::size_t(w)]; b; b &= b - 1)
                seeds.push_back({std::uint32_t(l), openvdb::Index(w * 64 + __builtin_ctzll(b))});
        }
    if (seeds.empty()) return out;
    const MaskSet in_apart(leaves, apart);
    openvdb::BoolGrid::Ptr seen = openvdb::BoolGrid::create(false);
    auto acc = seen->getAccessor();
    const auto coord = [&](const FarVoxel& v) { return leaves.leaf(v.leaf).offsetToGlobalCoord(v.offset); };
    for (const FarVoxel& s : seeds) {
        const Coord c = coord(s);
        if (acc.isValueOn(c)) continue;
        std::vector<FarVoxel> piece{s};
        acc.setValueOn(c, true);
        openvdb::CoordBBox box(c, c);
        for (std::size_t h = 0; h < piece.size(); ++h)
            for (int d = 0; d < 6; ++d) {
                Coord q = coord(piece[h]);
                q[d / 2] += (d & 1) ? 1 : -1;
                FarVoxel v;
                if (acc.isValueOn(q) || !in_apart.find(q, v)) continue;
                acc.setValueOn(q, true);
                box.expand(q);
                piece.push_back(v);
            }
        const auto dim = box.dim();
        if (std::max({dim.x(), dim.y(), dim.z()}) < reach) {
            out.crumbs.insert(out.crumbs.end(), piece.begin(), piece.end());
            ++out.crumb_pieces;
        } else {
            ++out.large_pieces;
        }
    }
    return out;
}

} // namespace cm::plausible
