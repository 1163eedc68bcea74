// Hidden depth in hull.plausible (`ghost`; plausible_ghost.cpp). A part thin in one view whose
// depth the other views hide behind a wider part (an arm beside the torso in the front view,
// inside the torso's outline in the side view) gets the hull's whole depth there: the box of
// its section pairs its own thin run with the run of the wider part. A modeller gives it a
// round section about as deep as it is wide, placed where the third view puts it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "plausible_state.h"

namespace cm::plausible {

/// The hidden-depth prior at a voxel.
struct GhostValue {
    float field = 0;  ///< cells outside the round section the hidden part gets (<= 0 inside)
    float weight = 0; ///< how clearly the depth is hidden, in [0, 1] (0: no say)
};

/// body(index, values, count) for each leaf of `vox`, in parallel: the hidden-depth prior of
/// the leaf's voxels (values[k] that of voxel index[k]), all of them or, with `only` (per
/// leaf, LeafManager order), just those in it.
using GhostLeafBody = std::function<void(const std::uint32_t* index, const GhostValue* values, std::size_t count)>;
void ghost_by_leaf(const HullVoxels& vox, const std::array<Projection, 3>& proj, const std::vector<LeafMask>* only,
                   const GhostLeafBody& body);

} // namespace cm::plausible
