// Step 7 of hull.plausible (plausible_state.h): the output volume's crossings. The input's
// exact crossings stay wherever an edge still runs from an inside point to a point outside the
// hull; edges into the removed region get the smoothed field's zero crossing.
#pragma once
#include <cstddef>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/volume.h"
#include "leaf_masks.h"
#include "util/uninit_vector.h"

namespace cm::plausible {

/// The hull's voxels by leaf and the field on them, through the voxels' numbering
/// (HullVoxels: voxel index = base[leaf] + rank of the voxel in its leaf's mask).
struct HullField {
    const std::vector<LeafMask>& masks;   ///< the hull's voxels, per leaf
    const std::vector<Coord>& origins;    ///< each leaf's origin
    const std::vector<std::size_t>& base; ///< each leaf's first voxel index
    const UninitVector<float>& field;     ///< the field, per voxel
};

/// The crossings of the volume whose occupancy is `now` (a subset of the hull's, `in`'s, with
/// removed voxels put back in places): `in`'s crossings, the leaves at `touched` (sorted, each
/// once: those about the removed voxels) made anew, a leaf kept only where it holds a crossing.
/// `placed` gets the number of crossings placed on the field's zero level.
openvdb::Vec3fGrid::Ptr recrossed(const Volume& in, const openvdb::BoolGrid& now, const std::vector<Coord>& touched,
                                  const HullField& hull, std::size_t& placed);

} // namespace cm::plausible
