// Gap closing for line art: the breaks of a sketchy outline bridged before the background
// is flooded from the border, as the "close gaps" option of a paint program's fill tool.
#pragma once
#include <vector>

namespace cm {

/// The gap closed by default in a drawing of w x h pixels: 0.4 % of its larger side, at
/// least 3 px.
double default_close_gaps(int w, int h);

/// @brief The ink (w x h, row-major) closed with a disc of radius (gap + 1) / 2: breaks in a
/// stroke up to `gap` pixels wide are bridged, while an opening wider than that keeps a
/// passage (a disc that fits in it stays out of the result). Beyond the image is blank, so
/// the border does not close anything. `gap` <= 0 gives the ink itself.
std::vector<char> close_ink(const std::vector<char>& ink, int w, int h, double gap);

} // namespace cm
