// The smoothing guard (SmoothOptions::guard): pulls the vertices of bad faces back towards
// their input positions until no face crosses another, turns over or collapses, and no two
// vertices that were apart in the input coincide.
#pragma once
#include <vector>

#include "core/mesh.h"
#include "mesh_smooth.h"

namespace cm {

/// @brief Mends the smoothed positions `p` of `in`'s vertices; counts what it found and did in
/// `st` (bad_faces, coincident, pulled_back, guard_rounds, unresolved).
void guard_surface(const Mesh& in, std::vector<Vec3f>& p, SmoothStats& st);

} // namespace cm
