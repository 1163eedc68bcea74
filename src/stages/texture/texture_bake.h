// Texturing a mesh from its views: charts and atlas (atlas.h), the colour of every
// texel and vertex from the views that see it (surface_colour.h), unseen parts from the
// nearest seen surface, and padding around the charts against bleeding.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/views.h"
#include "view_colours.h"

namespace cm {

/// The parameters of texture.project.
struct TextureOptions {
    bool texture;          ///< bake an atlas image; false: vertex colours only
    int texture_size;      ///< the atlas is texture_size x texture_size texels
    int padding;           ///< texels around each chart
    CleanOptions clean;    ///< how each drawing is cleaned (ink, border)
    double angle_power;    ///< SurfaceColourOptions::angle_power
    double conflict_de;    ///< SurfaceColourOptions::conflict_de (0: the weighted mean of the views)
    int balance_rounds;    ///< evaluations of the views' errors while weighting them (0: every weight 1)
    double balance_target; ///< views' mean delta E the weighting holds them to (view_balance.h)
    int min_island_faces;  ///< smaller chart islands join a neighbouring chart where they can

    TextureOptions() { set_declared_defaults(*this); }
    void declare(ParamBinder& b);
};

struct TextureStats {
    bool textured = false;       ///< an atlas was asked for (TextureOptions::texture)
    bool lines_stripped = false; ///< ink was looked for (CleanOptions::strokes is Strip)
    bool balanced = false;       ///< the views were weighted (balance_rounds > 0)
    std::size_t charts = 0;
    double texels_per_unit = 0;
    double seen_vertices = 0;                  ///< fraction of vertices some view sees
    double atlas_fill = 0;                     ///< fraction of the image covered by triangles
    std::vector<std::string> views;            ///< the views colours came from (those with a drawing)
    std::vector<std::size_t> line_pixels;      ///< per entry of `views`
    std::vector<std::size_t> sliver_pixels;    ///< per entry of `views`: paper between strokes left out
    std::vector<double> view_weight;           ///< per entry of `views` (view_balance.h)
    std::vector<double> view_error;            ///< estimated mean delta E against each drawing, ink left out
    std::vector<double> view_error_unbalanced; ///< the same with every view's weight 1
    /// seen_vertices (and a warning when under half), the atlas's figures when there is one,
    /// and per view: ink_pixels when ink was looked for, view_delta_e, and when the views
    /// were weighted view_weight and view_delta_e_unbalanced.
    void report(Metrics& m) const;
};

/// @brief A copy of `mesh` with per-vertex colours (linear RGBA), and with `opt.texture`
/// per-corner UVs and a base-colour texture (sRGB, as drawn). `progress` has the fraction
/// done between steps.
/// @throw cm::Error when no view has an image or the charts cannot fit the texture;
/// cm::Cancelled from `progress`.
Result<Mesh, TextureStats> project_texture(const Mesh& mesh, const Views& views, const TextureOptions& opt,
                                           Progress progress = {});

} // namespace cm
