// Sets of voxels of a bool tree's leaves as 512-bit masks (the leaf value mask's eight
// words: offset x * 64 + y * 8 + z is word x, byte y, bit z), one per leaf in LeafManager
// order, and what hull.plausible does with them 512 voxels at a time: neighbours by word
// shifts, floods to a fixed point, the shortest paths between pieces, sealed pockets.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

namespace cm::plausible {

using openvdb::Coord;
using LeafMask = std::array<std::uint64_t, 8>;

/// A leaf's on voxels as a mask.
inline LeafMask leaf_mask(const openvdb::BoolTree::LeafNodeType& leaf) {
    LeafMask m;
    for (openvdb::Index w = 0; w < 8; ++w) m[w] = leaf.getValueMask().getWord<std::uint64_t>(w);
    return m;
}

/// A hash key of a leaf origin (21 bits of each coordinate's leaf index).
inline std::uint64_t leaf_key(const Coord& o) {
    return (std::uint64_t(std::uint32_t(o.x()) >> 3) & 0x1fffff) << 42 |
           (std::uint64_t(std::uint32_t(o.y()) >> 3) & 0x1fffff) << 21 |
           (std::uint64_t(std::uint32_t(o.z()) >> 3) & 0x1fffff);
}
constexpr std::uint32_t kNoLeaf = ~std::uint32_t(0);
/// Each leaf's face neighbours (0: -x, 1: +x, 2: -y, 3: +y, 4: -z, 5: +z) as LeafManager
/// indices, kNoLeaf where the tree has none.
std::vector<std::array<std::uint32_t, 6>> leaf_neighbours(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves);
/// For each voxel of a leaf, whether its neighbour in direction d (as above) is in `own`
/// (the leaf's mask) or, across the face, in `next` (the mask of the leaf beside it that
/// way; none when null).
LeafMask neighbour_in(const LeafMask& own, const LeafMask* next, int d);
/// Each leaf's 26 neighbours and itself, 27 per leaf, offset k = (dx + 1) + 3 (dy + 1) + 9 (dz + 1)
/// in leaves; LeafManager indices, kNoLeaf where the tree has none.
std::vector<std::uint32_t> leaf_neighbourhoods(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves);

/// The voxels of `through` (per leaf, in LeafManager order) reached from those of `seed` by
/// 6-neighbour steps within `through` (a step from a seed into `through` included; with
/// `missing_is_seed`, from every point of a leaf the manager lacks). Bit-parallel: a leaf's
/// 512 voxels at a time, dilated by shifts of its mask words to a fixed point, then across its
/// faces to the next leaves, until nothing grows.
std::vector<LeafMask> flood(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                            const std::vector<LeafMask>& seed, const std::vector<LeafMask>& through,
                            bool missing_is_seed);
/// The same flood with the leaves' face neighbours (leaf_neighbours) given: a caller that
/// floods more than once builds them once.
std::vector<LeafMask> flood(const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<LeafMask>& seed,
                            const std::vector<LeafMask>& through, bool missing_is_seed);
/// Each 6-connected piece of `masks` (per leaf; face neighbours `nbr`), in the order of its
/// first voxel (leaf, then offset), taken out of `masks` and handed to `fn` as its voxels per
/// leaf (`piece`, set on the leaves `leaves` alone, cleared after the call). A piece's flood
/// works over its own leaves alone, however many leaves the tree has: for many small pieces.
void for_each_piece(
    const std::vector<std::array<std::uint32_t, 6>>& nbr, std::vector<LeafMask>& masks,
    const std::function<void(const std::vector<LeafMask>& piece, const std::vector<std::uint32_t>& leaves)>& fn);

/// The kept volume (`kept`, per leaf, within `hull`) as one piece: its pieces apart from the
/// main body (the piece of the fullest leaf) are joined to it by bridges through the hull's
/// removed voxels, each a shortest 6-connected path (breadth-first out of the piece, at most
/// `max_steps` voxels) from the piece to the main body. Returns the voxels of the bridges; `pieces`
/// gets the number of pieces joined. Pieces of the hull itself apart from the rest (no path
/// within the hull) stay apart.
std::vector<Coord> bridges(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                           const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<LeafMask>& hull,
                           const std::vector<LeafMask>& kept, int max_steps, std::size_t* pieces);

/// Of the voxels of `removed` (per leaf, in LeafManager order; a subset of the voxels of
/// `hull`), those in 6-connected pieces of removed voxels that reach no point outside `hull`:
/// pockets sealed inside what is kept (what a flood from the outside through them misses).
std::vector<LeafMask> sealed_pockets(const std::vector<std::array<std::uint32_t, 6>>& nbr,
                                     const std::vector<LeafMask>& hull, const std::vector<LeafMask>& removed);

} // namespace cm::plausible
