// Alignment of orthographic views through their shared axes (see
// docs/conventions.md): front/right share Y, front/top share X, right/top share Z.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

struct AlignOptions {
    std::optional<double> height, width, depth; ///< real size; else 1 unit = 1 px of the first view
    double tolerance = 0.02;                    ///< relative disagreement that raises a warning
    /// Per view: its camera's scale and origin are fixed (given by the manifest) and kept as
    /// they are. Missing entries are false.
    std::vector<bool> fixed;
    /// The object's box in the fixed cameras' world (min xyz, max xyz); only with fixed cameras.
    std::optional<std::array<double, 6>> bounds;
};

/// Which world axis (0 = X, 1 = Y, 2 = Z) a unit vector lies along, or -1.
int axis_of(const Vec3d& a);

/// @brief Sets scale and image origin of every orthographic camera that is not fixed, and
/// fills views.bounds. Appends warnings for views that disagree on a shared axis.
///
/// Without fixed cameras the world is the output frame (Y up, front +Z, pivot at the bottom
/// centre of the box the silhouettes imply; 1 unit = 1 px of the first view, or the real
/// size). With fixed cameras the world is theirs: the other views are aligned to them
/// through the shared axes (an axis no fixed view measures is centred on 0, or stands on
/// Y = 0 for the height), and their silhouettes are checked against one another. The box is
/// opt.bounds when given, else the one the silhouettes imply.
/// @throw cm::Error for an empty silhouette, naming the view, or a real size with fixed cameras.
void align_views(Views& views, const AlignOptions& opt, std::vector<std::string>& warnings);

} // namespace cm
