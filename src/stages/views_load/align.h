// Alignment of orthographic views through their shared axes (see
// ../conventions/views.md): front/right share Y, front/top share X, right/top share Z.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

struct AlignOptions {
    std::optional<double> height, width, depth;   ///< real size; else 1 unit = 1 px of the first view
    double tolerance = 0.02;                      ///< relative disagreement that raises a warning
};

/// Sets scale and image origin of every orthographic camera so that the world is
/// the output frame (Y up, front +Z, pivot at the bottom centre of the box), and
/// fills views.bounds. Appends warnings for disagreeing views. Throws cm::Error
/// for an empty silhouette, naming the view.
void align_views(Views& views, const AlignOptions& opt, std::vector<std::string>& warnings);

} // namespace cm
