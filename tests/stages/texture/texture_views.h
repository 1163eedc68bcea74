// Drawings in flat colours built in code, for the texturing tests: a view's silhouette
// filled with one colour (or a colour per region), optionally with ink lines drawn in.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <string>

#include "core/mesh.h"
#include "core/views.h"
#include "support/shapes.h"

namespace cm::test {

using Rgb = std::array<float, 3>;

/// Orthographic view `name` (size x size px, `scale` px per unit, origin at the centre) of
/// the shape `outline`, painted `fill(q)` inside (q the plane point of the pixel centre, as
/// Outline takes it) on white paper.
View painted_view(const std::string& name, int size, double scale, const Outline& outline,
                  const std::function<Rgb(const Vec3d& q)>& fill);

/// Draws black ink over `v`: an outline `width` px wide just inside the silhouette, and a
/// straight stroke `width` px wide across the middle row.
void draw_ink(View& v, int width);

/// Colour of a texture at UV (nearest texel, v up).
Rgb texel(const Image& t, float u, float v);

/// The UV of barycentric point (b0, b1, b2) of face f (corner UVs).
std::array<float, 2> uv_at(const Mesh& m, std::size_t f, double b0, double b1, double b2);

double max_diff(const Rgb& a, const Rgb& b);

} // namespace cm::test
