// The colour error of a coloured mesh against the drawings it was coloured from: its colour
// rendered through every view (render/textured.h) and compared with the drawing in CIELAB.
#pragma once
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/views.h"

namespace cm {

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
