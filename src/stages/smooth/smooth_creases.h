// The crease hold of the smoothing (SmoothOptions::crease_angle_deg): sharp creases of the
// input stay sharp and the flat sides beside them stay in their planes.
#pragma once
#include <vector>

#include "core/mesh.h"
#include "geometry/mesh_adjacency.h"

namespace cm {

/// What each vertex may do during the smoothing.
struct CreaseHold {
    /// The neighbours each vertex is smoothed towards: its one-ring, but for a vertex on a
    /// sharp crease (an edge whose two faces meet at more than the angle) its two crease
    /// neighbours, so it moves along the crease only, and none (it stays) for the end or the
    /// meeting point of creases.
    VertexAdjacency adj;
    /// Per vertex, the unit normal of the plane its steps are kept in (its faces' mean
    /// normal in the input) for a vertex off the creases beside one; zero: free.
    std::vector<Vec3f> plane;
    std::size_t crease_vertices = 0, held_vertices = 0, plane_vertices = 0;
};

/// The hold of `in` (closed or not; edges with other than two faces are not creases) for
/// creases sharper than `angle_deg`, from its one-rings `ring`.
CreaseHold hold_creases(const Mesh& in, const VertexAdjacency& ring, double angle_deg);

} // namespace cm
