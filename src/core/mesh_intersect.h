// Self-intersection test of a triangle mesh, for checks in tests, benchmarks and
// run reports ("no self-intersections" is one of the output quality rules).
#pragma once
#include <cstddef>

#include "core/mesh.h"

namespace cm {

/// @brief Counts pairs of triangles that cross each other. Triangles sharing an edge
/// are not tested; triangles sharing one vertex are tested with their opposite edges.
/// Coplanar overlaps are not counted. Uniform-grid broad phase, TBB-parallel.
std::size_t count_self_intersections(const Mesh& mesh);

} // namespace cm
