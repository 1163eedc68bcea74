// The volume passed between stages: OpenVDB grids on one transform. Include
// only in stages that work on grids (OpenVDB headers are slow to compile).
#pragma once
#include <memory>
#include <openvdb/openvdb.h>

#include "core/views.h"

namespace cm {

struct Volume {
    /// Inside of the hull: active = inside. Solid interior is stored as active tiles,
    /// leaf voxels only near the surface. Grid points are voxel centres in world space.
    openvdb::BoolGrid::Ptr occupancy;
    /// Exact crossings, once refined: for each active voxel v, component k is the
    /// fraction t in [0,1] along the edge from v to v + e_k where the surface crosses
    /// it, or -1 when that edge has no crossing.
    openvdb::Vec3fGrid::Ptr crossings;
    /// Further grids a stage adds (for example thin-feature crossings), by name.
    openvdb::GridPtrVec extra;
    /// The views the volume was carved from (the same transform frame).
    std::shared_ptr<const Views> views;

    const openvdb::math::Transform& transform() const { return occupancy->transform(); }
    double voxel_size() const { return occupancy->voxelSize()[0]; }
};

} // namespace cm
