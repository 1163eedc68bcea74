// Far pieces of the kept volume (plausible_pieces.h): the main body by a flood of the leaf
// masks, the voxels apart from it split into 6-connected pieces by floods over their own
// leaves alone (they are few: what the bridges left).
#include "plausible_pieces.h"

#include <algorithm>

namespace cm::plausible {

namespace {

using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;
using Neighbours = std::vector<std::array<std::uint32_t, 6>>;

// The kept voxels 6-connected to the fullest leaf's: the main body.
std::vector<LeafMask> main_body(const Neighbours& nbr, const std::vector<LeafMask>& kept) {
    std::size_t best = 0, most = 0;
    for (std::size_t l = 0; l < kept.size(); ++l) {
        std::size_t c = 0;
        for (const auto w : kept[l]) c += std::size_t(__builtin_popcountll(w));
        if (c > most) most = c, best = l;
    }
    std::vector<LeafMask> seed(kept.size(), LeafMask{});
    if (most == 0) return seed;
    seed[best] = kept[best];
    return flood(nbr, seed, kept, false);
}

} // namespace

FarPieces far_pieces(const Leaves& leaves, const Neighbours& nbr, const std::vector<LeafMask>& hull,
                     const std::vector<LeafMask>& kept, int reach) {
    FarPieces out;
    const std::size_t nleaf = kept.size();
    const std::vector<LeafMask> body = main_body(nbr, kept);
    // Apart from the body, but within the hull's piece of it.
    const std::vector<LeafMask> within = flood(nbr, body, hull, false);
    std::vector<LeafMask> apart(nleaf);
    for (std::size_t l = 0; l < nleaf; ++l)
        for (int w = 0; w < 8; ++w)
            apart[l][std::size_t(w)] = kept[l][std::size_t(w)] & ~body[l][std::size_t(w)] & within[l][std::size_t(w)];
    for_each_piece(nbr, apart, [&](const std::vector<LeafMask>& piece, const std::vector<std::uint32_t>& touched) {
        std::vector<FarVoxel> voxels;
        openvdb::CoordBBox box;
        for (const std::uint32_t l : touched)
            for (int w = 0; w < 8; ++w)
                for (std::uint64_t b = piece[l][std::size_t(w)]; b; b &= b - 1) {
                    const auto o = openvdb::Index(w * 64 + __builtin_ctzll(b));
                    voxels.push_back({l, o});
                    box.expand(leaves.leaf(l).offsetToGlobalCoord(o));
                }
        const auto dim = box.dim();
        if (std::max({dim.x(), dim.y(), dim.z()}) < reach) {
            out.crumbs.insert(out.crumbs.end(), voxels.begin(), voxels.end());
            ++out.crumb_pieces;
        } else {
            ++out.large_pieces;
        }
    });
    return out;
}

} // namespace cm::plausible
