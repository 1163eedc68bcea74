// Shapes for the mesh-stage tests and benchmarks, built in code.
#pragma once
#include <cstdint>

#include "core/mesh.h"
#include "core/views.h"

namespace cm::test {

/// Closed outward cube [lo, hi]^3 whose six faces are n x n grids of quads (two
/// triangles each), sharing vertices along the edges: 12 n^2 triangles.
Mesh make_grid_box(float lo, float hi, int n);

/// Moves every vertex along its direction from `centre` by a uniform random amount in
/// [-amplitude, amplitude] (fixed seed).
void add_radial_noise(Mesh& m, Vec3f centre, float amplitude, std::uint32_t seed = 1);

/// Front, right and top orthographic views (width x width px, framed so the box
/// [lo, hi]^3 spans 80 % of the image) of the axis-aligned box, with anti-aliased
/// coverage (4 x 4 samples per pixel).
Views make_box_views(float lo, float hi, int width);

/// Splits every triangle into four, `levels` times (positions at edge midpoints).
Mesh subdivide(const Mesh& m, int levels);

} // namespace cm::test
