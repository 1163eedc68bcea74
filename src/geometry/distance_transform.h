// Exact Euclidean distance transform of a binary image, shared by the families that need
// distances on silhouettes (the hull distance, gap closing in drawings).
#pragma once
#include <vector>

namespace cm {

/// Squared distance given to pixels when no seed exists.
constexpr float kEdtFar = 1e20f;

/// @brief Squared distance (pixels^2) from every pixel centre to the nearest pixel where
/// `seed` is true (row-major, w x h); kEdtFar everywhere when no pixel is a seed.
std::vector<float> squared_edt(const std::vector<char>& seed, int w, int h);

} // namespace cm
