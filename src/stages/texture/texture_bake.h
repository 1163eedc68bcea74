// Texturing a mesh from its views: charts and atlas (atlas.h), the colour of every
// texel and vertex from the views that see it (surface_colour.h), unseen parts from the
// nearest seen surface, and padding around the charts against bleeding.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/views.h"
#include "view_colours.h"

namespace cm {

struct TextureOptions {
    bool texture = true; ///< bake an atlas image; false: vertex colours only
    int texture_size = 2048;
    int padding = 4; ///< texels around each chart
    CleanOptions clean;
    double angle_power = 2;
    double conflict_de = 0;    ///< SurfaceColourOptions::conflict_de (0: the weighted mean of the views)
    int balance_rounds = 0;    ///< rounds of view weighting against the worst view's error (0: every weight 1)
    double balance_target = 3; ///< views' mean delta E the weighting holds them to (view_balance.h)
    int min_island_faces = 8;  ///< smaller chart islands join a neighbouring chart where they can
};

struct TextureStats {
    std::size_t charts = 0;
    double texels_per_unit = 0;
    double seen_vertices = 0;                  ///< fraction of vertices some view sees
    double atlas_fill = 0;                     ///< fraction of the image covered by triangles
    std::vector<std::string> views;            ///< the views colours came from (those with a drawing)
    std::vector<std::size_t> line_pixels;      ///< per entry of `views`
    std::vector<double> view_weight;           ///< per entry of `views` (view_balance.h)
    std::vector<double> view_error;            ///< estimated mean delta E against each drawing, ink left out
    std::vector<double> view_error_unbalanced; ///< the same with every view's weight 1
};

/// @brief A copy of `mesh` with per-vertex colours (linear RGBA), and with `opt.texture`
/// per-corner UVs and a base-colour texture (sRGB, as drawn). `progress(fraction)` is
/// called between steps (it may throw to cancel).
/// @throw cm::Error when no view has an image or the charts cannot fit the texture.
Mesh project_texture(const Mesh& mesh, const Views& views, const TextureOptions& opt, TextureStats& stats,
                     const std::function<void(double)>& progress = {});

} // namespace cm
