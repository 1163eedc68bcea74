// Pictures of a coloured mesh through a camera (its base-colour texture, else its
// vertex colours, unlit: the colour as painted).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/mesh.h"
#include "core/views.h"
#include "render/raster.h"

namespace cm {

/// True when the mesh carries colour: a texture with UVs, or vertex colours.
bool has_colour(const Mesh& mesh);

/// @brief The mesh's colour (sRGB) seen through `cam`: texture at the UVs (bilinear), else
/// the vertex colours interpolated. Alpha 1 where the mesh covers the pixel centre, else
/// 0 with `background` in RGB. `progress` is looked at per chunk of the render and of the rows
/// (progress.check()).
Image render_colour(const Mesh& mesh, const Camera& cam, int width, int height,
                    const std::array<float, 3>& background = {1, 1, 1}, Progress progress = {});

} // namespace cm
