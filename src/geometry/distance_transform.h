// Exact Euclidean distance transform of a binary image, shared by the families that need
// distances on silhouettes (the hull distance, gap closing in drawings).
#pragma once
#include <functional>
#include <vector>

namespace cm {

/// Squared distance given to pixels when no seed exists.
constexpr float kEdtFar = 1e20f;

/// @brief Squared distance (pixels^2) from every pixel centre to the nearest pixel where
/// `seed` is true (row-major, w x h); kEdtFar everywhere when no pixel is a seed.
std::vector<float> squared_edt(const std::vector<char>& seed, int w, int h);

/// The same over a w x h array of seeds (nonzero: seed).
std::vector<float> squared_edt(const char* seed, int w, int h);

/// @brief The squared distances of a signed distance field near its border: per pixel of a
/// w x h mask (1: inside, 0: outside), the squared distance to the nearest pixel of the other
/// kind, as squared_edt() of the other kind's pixels gives it (kEdtFar when there is none),
/// for every inside pixel and for the outside pixels within `reach` (>= 1) of an inside one;
/// the other outside pixels get infinity (not worked out: a caller that needs them asks
/// squared_edt() of the inside). One column pass serves both kinds, and only the inside
/// pixels' stretch of each row takes the row pass: the outside pixels near the border take the
/// few columns within reach. Row y goes to `row(y, values)` (w values), from the worker
/// threads, the rows in any order.
void squared_edt_signed(const char* inside, int w, int h, int reach, const std::function<void(int, const float*)>& row);

} // namespace cm
