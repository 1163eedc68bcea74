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
/// box when it has none). Keeps references into `views`. `tables`: the views' silhouette
/// tables (Volume::silhouette_tables when the views are the volume's own); null: made here.
/// @throw cm::Error when there are no views.
inline std::unique_ptr<VisualHull> carved_hull(const openvdb::BoolGrid& occupancy, const Views& views,
                                               std::shared_ptr<const SilhouetteTables> tables = nullptr) {
    Vec3d lo{-1e300, -1e300, -1e300}, hi{1e300, 1e300, 1e300};
    if (auto m = occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_min")) {
        const auto v = m->value();
        lo = {v.x(), v.y(), v.z()};
    }
    if (auto m = occupancy.getMetadata<openvdb::Vec3DMetadata>("hull_clip_max")) {
        const auto v = m->value();
        hi = {v.x(), v.y(), v.z()};
    }
    return std::make_unique<VisualHull>(views, lo, hi, std::move(tables));
}

/// The silhouette tables `vol` carries for `views`: its own (Volume::silhouette_tables) when
/// `views` are the volume's views, else null (a hull of other views makes its own).
inline std::shared_ptr<const SilhouetteTables> carried_tables(const Volume& vol,
                                                              const std::shared_ptr<const Views>& views) {
    return views == vol.views ? vol.silhouette_tables : nullptr;
}

} // namespace cm
