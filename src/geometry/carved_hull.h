// The visual hull a grid was carved from, for the stages that ask the hull again (the
// crossings' normals, Dual Marching Cubes). Inline and in a header of its own: it reads the
// grid's metadata through OpenVDB, which those stage families link, while
// libconceptmesh_geometry (and so the command, until it loads an OpenVDB plugin) stays
// free of OpenVDB and of its 60 ms of loading.
#pragma once
#include <memory>

#include "core/volume.h"
#include "geometry/visual_hull.h"

namespace cm {

/// @brief The visual hull `occupancy` was carved from: the cones of `views` clipped to the
/// box hull.carve recorded in the grid's "hull_clip_min"/"hull_clip_max" metadata (no clip
/// box when it has none). Keeps references into `views`.
/// @throw cm::Error when there are no views.
inline std::unique_ptr<VisualHull> carved_hull(const openvdb::BoolGrid& occupancy, const Views& views) {
    Vec3d lo{-1e300, -1e300, -1e300}, hi{1e300, 1e300, 1e300};
    if (auto m = occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_min")) {
        const auto v = m->value();
        lo = {v.x(), v.y(), v.z()};
    }
    if (auto m = occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_max")) {
        const auto v = m->value();
        hi = {v.x(), v.y(), v.z()};
    }
    return std::make_unique<VisualHull>(views, lo, hi);
}

} // namespace cm
