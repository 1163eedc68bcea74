// Thin parts in Marching Cubes: parts thinner than a cell that the refinement found on
// grid edges whose ends are both outside (hull.marching_intersections' thin_enter and
// thin_leave grids) are kept by making a grid point inside (promote_thin), and the vertices
// around such a point are moved onto the near face of its part. untangle_thin undoes that
// move wherever it made faces cross.
#pragma once
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/volume.h"
#include "mc_blocks.h"

namespace cm::mc {

/// The points made inside for the thin parts, each with its offset (in cells, per axis) to
/// the near face of its part; `count` grows by the number of points.
FlipGrid::Ptr promote_thin(const Volume& vol, const openvdb::Vec3fGrid& enter, const openvdb::Vec3fGrid& leave,
                           std::size_t& count);

/// A vertex moved onto the near face of a thin part, and where it was on its edge.
struct ShiftedVertex {
    std::uint32_t vertex;
    Vec3f on_edge;
};

/// Puts back on their edges the shifted vertices of faces that cross another face (and
/// re-centres the centre vertices of their loops), until no face near a shifted vertex
/// crosses another or none is left to put back. `first_extra` is the index of the first
/// centre vertex. Returns the number of vertices put back.
std::size_t untangle_thin(Mesh& mesh, const std::vector<ShiftedVertex>& shifted, std::size_t first_extra,
                          const openvdb::math::Transform& xform);

} // namespace cm::mc
