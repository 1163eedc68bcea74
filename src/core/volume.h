// The volume passed between stages: OpenVDB grids on one transform. Include
// only in stages that work on grids (OpenVDB headers are slow to compile).
//
// Lattice: grid point (i,j,k) sits at transform().indexToWorld(i,j,k) (the voxel
// centre in OpenVDB's terms). Marching Cubes cells have grid points as corners.
// The transform is a uniform linear transform (voxel size h, grid point (0,0,0) at
// the padded box's minimum corner); the inside never touches the edge of the
// carved box (hull.carve pads it by two cells), so every surface cell is complete.
#pragma once
#include <openvdb/openvdb.h>
#include <memory>

#include "core/views.h"

namespace cm {

struct SilhouetteTables; // geometry/visual_hull.h

struct Volume {
    /// Inside of the hull: a grid point is inside when its value is active (and true).
    /// Solid interior is stored as active tiles; leaf voxels only near the surface;
    /// the inactive background is outside.
    /// hull.carve guarantees: every inside grid point that has an outside point among
    /// its 26 neighbours is a voxel of a leaf node (never part of a tile), so every
    /// Marching Cubes cell with mixed corners has at least one inside corner in a leaf.
    /// Active leaf voxels hold true, inactive ones false.
    openvdb::BoolGrid::Ptr occupancy;
    /// Exact crossings, once refined (hull.marching_intersections). At grid point p,
    /// component a (0=x,1=y,2=z) is t in [0,1]: the surface crosses the lattice edge
    /// from p to p + e_a at p + t e_a. Set only where occupancy differs at the two ends;
    /// -1 (or an inactive value) elsewhere. Null when the volume is not refined.
    /// Detail: a voxel is active when at least one component is set; unset components of
    /// an active voxel are -1; the background is (-1,-1,-1). t is measured from p whichever
    /// end is inside. When the edge crosses the hull more than once, t is the crossing next
    /// to the inside end (where the inside end's solid stops).
    openvdb::Vec3fGrid::Ptr crossings;
    /// Further grids a stage adds, by grid name. hull.marching_intersections adds:
    ///  - "thin_enter" and "thin_leave" (openvdb::Vec3fGrid, same transform, background
    ///    (-1,-1,-1)): thin parts that fall between two grid points. For an edge p -> p + e_a
    ///    whose BOTH ends are outside but which passes through the hull, component a of
    ///    "thin_enter" at p is t0 and of "thin_leave" at p is t1 (0 < t0 < t1 < 1): the
    ///    edge is inside the hull for t in [t0, t1]. When an edge passes through solid
    ///    more than once, the longest inside interval is kept. Both grids are active at
    ///    exactly the same voxels; unset components are -1. Absent when the hull has no
    ///    such edge. A mesher that ignores them still gets a closed surface, only without
    ///    the parts thinner than a cell.
    openvdb::GridPtrVec extra;
    /// The views the volume was carved from (same world frame).
    std::shared_ptr<const Views> views;
    /// The summed-area tables of the silhouettes of `views` (geometry/visual_hull.h), for the
    /// stages that ask the visual hull of these views again. hull.carve fills them (it made
    /// them for its own hulls); hull.marching_intersections and hull.plausible pass their
    /// input's on; hull.marching_intersections and extract.dual_marching_cubes (its normals)
    /// read them. Null when the volume was made elsewhere: a stage that needs them makes them.
    std::shared_ptr<const SilhouetteTables> silhouette_tables;

    const openvdb::math::Transform& transform() const { return occupancy->transform(); }
    double voxel_size() const { return occupancy->voxelSize()[0]; }
    /// The extra grid of that name, or null.
    openvdb::GridBase::Ptr find_extra(const std::string& name) const {
        for (const auto& g : extra)
            if (g && g->getName() == name) return g;
        return nullptr;
    }
};

} // namespace cm
