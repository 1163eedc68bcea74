// The last phase of hull.plausible (plausible.cpp): from the voxels the field removes to the
// volume the extractors take. The output occupancy (removed voxels off, plates one cell thin
// put back, sealed pockets filled, pieces cut off bridged back to the body, full leaves back
// to tiles), the thin-part edges beside a removed grid point dropped, and the crossings:
// the hull's own where an edge still runs to the outside of the hull, the field's zero level
// on edges into the removed region.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include "plausible.h"

namespace cm::plausible {

/// `occ`: a voxelized copy of the input's occupancy, `leaves` its leaves and `base` their
/// voxel numbering (leaf base + rank); `removed[i]` and `field[i]` per voxel; `maxdim` the
/// box's longest side in cells. Changes `occ` (and `removed`, for pockets put back); fills
/// the removal's figures of `st`; `step(fraction)` reports progress.
std::shared_ptr<Volume> plausible_volume(const Volume& in, const openvdb::BoolGrid::Ptr& occ,
                                         openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                                         const std::vector<std::size_t>& base, std::vector<std::uint8_t>& removed,
                                         const std::vector<float>& field, int maxdim, PlausibleStats& st,
                                         const std::function<void(double)>& step);

} // namespace cm::plausible
