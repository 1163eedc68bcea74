// Pictures of a mesh through a camera: a concept-art-like drawing (shaded fill, dark
// outlines on the silhouette and on creases, off-white paper with grain) for synthetic
// test views, and the same shading on a plain background for preview sheets.
#pragma once
#include <array>

#include "core/camera.h"
#include "core/mesh.h"
#include "core/progress.h"
#include "core/views.h"

namespace cm {

struct ArtOptions {
    std::array<float, 3> paper{0.957f, 0.937f, 0.886f}; ///< background colour
    std::array<float, 3> fill{0.49f, 0.55f, 0.64f};     ///< lit fill colour
    std::array<float, 3> ink{0.12f, 0.11f, 0.13f};      ///< line colour
    float grain = 0.025f;                               ///< paper grain amplitude (uniform, +-), 0 for none
    float vignette = 0.04f;                             ///< darkening at the corners, 0 for none
    float outline_px = 2.0f;                            ///< silhouette line width, drawn inside the silhouette
    /// true: the outline centred on the silhouette's edge, half of it outside, as a
    /// draughtsman inks an outline (blueprint style); false: inside, so a filled drawing's
    /// silhouette is the mask's.
    bool outline_centred = false;
    float crease_px = 1.2f;   ///< width of crease and inner-contour lines
    float crease_deg = 40.0f; ///< dihedral angle that draws a crease line
    bool lines = true;        ///< false: shaded fill only
    bool shade = true;        ///< false: the fill flat in its colour (blueprint-style line art: fill = paper)
    int supersample = 3;      ///< samples per pixel along x and y (anti-aliasing)
    unsigned seed = 1;        ///< grain pattern
};

/// @brief Renders the mesh as a drawing. The silhouette's anti-aliased coverage follows the
/// pixel-centre silhouette of render_mask() (outlines lie inside the silhouette unless
/// `outline_centred`), so a silhouette extracted from the drawing matches the mask.
/// `progress` is looked at between the steps and per chunk of the render (progress.check()).
/// @return RGBA, alpha 1 everywhere (the drawing has no transparency).
Image render_art(const Mesh& mesh, const Camera& cam, int width, int height, const ArtOptions& opt = {},
                 Progress progress = {});

} // namespace cm
