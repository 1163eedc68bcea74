// Connected components of a pixel mask, and the components of a silhouette a user keeps
// (the last step of extract_silhouette).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "silhouette.h"

namespace cm {

/// @brief Connected components of the w x h `mask` (4- or 8-connected, `eight`): `lab` gets
/// each pixel's component (-1 outside the mask), `sizes` each component's pixel count;
/// returns their number. A component's label is the order of its first pixel in row order.
/// Filled a run of a row at a time: a run leaves one seed per run of unlabelled mask pixels
/// beside it in the rows above and below (diagonal neighbours too when 8-connected).
int mask_components(const std::vector<char>& mask, int w, int h, bool eight, std::vector<int>& lab,
                    std::vector<std::size_t>& sizes);

/// @brief Components of the w x h `coverage` (8-connected, coverage >= 0.5): drops specks and
/// separate marks a user would not keep (by `mode`, see SilhouetteOptions::keep), with the
/// fractional coverage that borders only them; counts what was kept and dropped in `res`.
void keep_components(int w, int h, const std::string& mode, std::vector<float>& coverage, SilhouetteResult& res);

} // namespace cm
