// The volume passed between stages: OpenVDB grids on one transform. Include
// only in stages that work on grids (OpenVDB headers are slow to compile).
//
// Lattice: grid point (i,j,k) sits at transform().indexToWorld(i,j,k) (the voxel
// centre in OpenVDB's terms). Marching Cubes cells have grid points as corners.
#pragma once
#include <memory>
#include <openvdb/openvdb.h>

#include "core/views.h"

namespace cm {

struct Volume {
    /// Inside of the hull: a grid point is inside when its value is active (and true).
    /// Solid interior is stored as active tiles; leaf voxels only near the surface;
    /// the inactive background is outside.
    openvdb::BoolGrid::Ptr occupancy;
    /// Exact crossings, once refined (hull.marching_intersections). At grid point p,
    /// component a (0=x,1=y,2=z) is t in [0,1]: the surface crosses the lattice edge
    /// from p to p + e_a at p + t e_a. Set only where occupancy differs at the two ends;
    /// -1 (or an inactive value) elsewhere. Null when the volume is not refined.
    openvdb::Vec3fGrid::Ptr crossings;
    /// Further grids a stage adds (for example thin-feature crossings), by grid name.
    openvdb::GridPtrVec extra;
    /// The views the volume was carved from (same world frame).
    std::shared_ptr<const Views> views;

    const openvdb::math::Transform& transform() const { return occupancy->transform(); }
    double voxel_size() const { return occupancy->voxelSize()[0]; }
};

} // namespace cm
