// How far the textured mesh, seen through each view's camera, is from that view's drawing,
// measured at the view's own pixels (where the mesh shows and the drawing has a colour:
// ink and the eroded border left out), and the views' weights that make the worst view's
// error smallest. Where the drawings disagree about a point (a hull surface the real
// object does not have, seen by two views that each show something else there), every
// colour costs some view; balancing spends that cost where a view can afford it.
#pragma once
#include <cstddef>
#include <vector>

#include "core/mesh.h"
#include "surface_colour.h"

namespace cm {

struct ViewBalance {
    std::vector<double> weight;       ///< per sampler, for ViewSampler::weight
    std::vector<double> error_before; ///< per sampler: mean delta E with every weight 1
    std::vector<double> error;        ///< per sampler: mean delta E with `weight`
};

/// @brief Mean CIE76 delta E per view between the colours `surface_colour` gives the
/// surface points the view's pixels show (with the views' weights) and the drawing there,
/// over the pixels where the drawing has a colour (confidence > 0); with `rounds` > 0 also
/// weights, found in that many rounds (first every view's pixels counting alike, then the
/// views with more error weighing more), that make the largest of them smallest. With
/// `rounds` 0, `weight` is all 1. `samples`: about how many pixels of all views are taken
/// (every pixel when the views have fewer, else a regular grid of them).
ViewBalance balance_views(const Mesh& mesh, const std::vector<ViewSampler>& views, const SurfaceColourOptions& opt,
                          int rounds, std::size_t samples = 300000);

} // namespace cm
