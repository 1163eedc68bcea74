// Pictures of a coloured mesh through a camera (its base-colour texture, else its
// vertex colours, unlit: the colour as painted), and the colour error of such a mesh
// against the drawings it was coloured from.
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
/// 0 with `background` in RGB.
Image render_colour(const Mesh& mesh, const Camera& cam, int width, int height,
                    const std::array<float, 3>& background = {1, 1, 1}, const RenderCheck& check = {});

struct ViewColourError {
    std::string view;
    double pixels = 0;     ///< compared: inside the drawing's silhouette eroded by `erode_px`, covered by the mesh
    double mean_de = 0;    ///< mean CIE76 delta E
    double over10_pct = 0; ///< share of the compared pixels with delta E over 10, percent
    /// The same over the compared pixels that are not ink (find_ink as texturing finds it,
    /// without the fringe): the drawing where it gives a colour.
    double no_ink_pixels = 0, no_ink_mean_de = 0, no_ink_over10_pct = 0;
};

/// @brief Renders the mesh's colour through every view and compares it with the drawing
/// inside the silhouette eroded by `erode_px` (pixels where the mesh is); also without the
/// drawing's ink pixels (strokes up to `line_width` px, `line_contrast` darker than around them).
std::vector<ViewColourError> colour_error(const Mesh& mesh, const Views& views, double erode_px = 3,
                                          float line_width = 4, float line_contrast = 0.12f);

} // namespace cm
