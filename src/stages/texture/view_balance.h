// How far the textured mesh, seen through each view's camera, is from that view's drawing,
// measured at the view's own pixels (where the mesh shows and the drawing has a colour:
// ink and the border left out), and the views' weights that hold every view's error to a
// target, or make the worst view's error smallest where that cannot be. Where the drawings
// disagree about a point (a hull surface the real object does not have, seen by two views
// that each show something else there), every colour costs some view; balancing spends
// that cost where a view can afford it.
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
/// over the pixels where the drawing has a colour (not ink, not within 3 px of the
/// silhouette's border, as `compare` judges), on a grid of about `samples` pixels of all
/// views; with `rounds` > 0 also the views' weights, from that many evaluations: first
/// every view's pixels counting alike (the sum of the views' errors made small), then, when
/// a view's error is over `target`, a search for the weights that bring every view's error
/// to at most `target`, or, where that cannot be, the worst view's as low as it goes, and
/// then the sum. With `rounds` 0,
/// `weight` is all 1. The weights are scaled to a mean of 1.
ViewBalance balance_views(const Mesh& mesh, const std::vector<ViewSampler>& views, const SurfaceColourOptions& opt,
                          int rounds, double target, std::size_t samples = 300000);

} // namespace cm
