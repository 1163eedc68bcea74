// The colour a drawing gives its object, cleaned for texturing: the silhouette border
// eroded (the background bleeds in there), the ink strokes of concept art (outlines,
// hatching: thin, dark, high-contrast) found and replaced by the neighbouring fill, and
// a confidence that ramps from 0 at what was removed (and at occlusion edges of the
// mesh in this view) to 1 a few pixels inside, so views hand over smoothly.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "core/params.h"
#include "core/views.h"
#include "render/raster.h"

namespace cm {

/// The parameters of a drawing's cleaning (texture.project's strokes, line_width,
/// line_contrast, paper_slivers, ink_chroma, fill_smooth, erode and blend).
struct CleanOptions {
    /// What becomes of the drawing's strokes: left out and filled from the neighbouring
    /// fill, or kept in the colours for a hand-drawn look.
    enum class Strokes { Strip, Keep };
    Strokes strokes;     ///< Strip: find ink strokes and fill them from the neighbouring fill
    float line_width;    ///< widest stroke taken for ink, px
    float line_contrast; ///< a stroke is this much darker (luminance) than the fill around it
    bool paper_slivers;  ///< also leave out the paper showing between strokes (thin, light, paper-coloured)
    float ink_chroma;    ///< strokes at least this saturated are coloured (fill), not ink; 1: every stroke is ink
    float fill_smooth;   ///< radius of the fill's low-pass across the stroke pattern, px (0: none)
    float erode_px;      ///< silhouette border not sampled, px
    float blend_px;      ///< confidence ramp from removed pixels and occlusion edges, px

    CleanOptions() { set_declared_defaults(*this); }
    void declare(ParamBinder& b);
};

struct ViewColours {
    int width = 0, height = 0;
    std::vector<std::array<float, 3>> rgb; ///< every pixel: its own colour where valid, else the nearest valid one
    std::vector<float> confidence;         ///< [0,1]
    std::vector<char> drawn;               ///< the drawing's own colour (not ink, not the eroded border)
    std::vector<float> border_px;          ///< distance to the outside of the silhouette, px
    std::size_t line_pixels = 0;           ///< pixels taken for ink inside the silhouette
    std::size_t sliver_pixels = 0;         ///< pixels taken for paper between strokes inside the silhouette
    bool any_valid = false;
    /// Bilinear colour and confidence at continuous pixel coordinates (clamped to the image).
    void sample(double x, double y, std::array<float, 3>& c, float& conf) const;
    /// True when the pixel at continuous coordinates (x, y) is drawn (inside the image).
    bool drawn_at(double x, double y) const {
        const int ix = int(x), iy = int(y);
        return x >= 0 && y >= 0 && ix < width && iy < height && drawn[std::size_t(iy) * width + ix];
    }
};

/// @brief The cleaned colours of `view`; `depth` (the mesh rendered through the view's
/// camera, may be empty) marks occlusion edges where the confidence ramps down.
ViewColours clean_view_colours(const View& view, const DepthImage* depth, double depth_jump, const CleanOptions& opt);

} // namespace cm
