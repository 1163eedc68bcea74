// Pieces of hull.plausible's kept volume that the bridges (leaf_masks.h, `bridges`) leave
// apart from the main body: more than their reach from it through the removed voxels.
// A piece smaller than that reach along every axis is farther from the body than it is large:
// a crumb an artist would delete (the remnant of a wall of the hull the removal took, kept by
// a few lines of sight that the body covers all but a few pixels of); it goes. A larger one
// is a part the removal cut off its body (a hand whose wrist went): it is joined by a bridge
// however long. Pieces of the hull itself apart from the rest (no path within the hull) are
// drawn apart and stay as they are.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "leaf_masks.h"

namespace cm::plausible {

/// A voxel by its leaf (LeafManager index) and offset in the leaf.
struct FarVoxel {
    std::uint32_t leaf = 0;
    openvdb::Index offset = 0;
};

/// The pieces of `kept` (per leaf of `leaves`, within `hull`) apart from the main body (the
/// piece of the fullest leaf, 6-connected) but joined to it within the hull.
struct FarPieces {
    std::vector<FarVoxel> crumbs; ///< voxels of the pieces smaller than the reach along every axis
    std::size_t crumb_pieces = 0;
    std::size_t large_pieces = 0; ///< pieces at least the reach long along some axis
};

/// The far pieces of `kept`, sorted by size against `reach` (voxels) as above.
/// `nbr`: the leaves' face neighbours (leaf_neighbours).
FarPieces far_pieces(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                     const std::vector<std::array<std::uint32_t, 6>>& nbr, const std::vector<LeafMask>& hull,
                     const std::vector<LeafMask>& kept, int reach);

} // namespace cm::plausible
