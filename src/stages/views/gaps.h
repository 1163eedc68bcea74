// Gap closing for line art: the breaks of a sketchy outline bridged before the background
// is flooded from the border, as the "close gaps" option of a paint program's fill tool.
#pragma once
#include <cstddef>
#include <vector>

namespace cm {

/// The gap closed by default in a drawing of w x h pixels: 0.4 % of its larger side, at
/// least 3 px.
double default_close_gaps(int w, int h);

/// @brief A barrier against the border flood: the ink (w x h, row-major) dilated by a disc
/// of radius gap / 2 + 1 and eroded by one pixel less, so breaks in a stroke up to `gap`
/// pixels wide (or that many pixels along a diagonal stroke) are bridged while an opening
/// about two pixels wider keeps a passage. The
/// barrier runs up to one pixel outside the ink; the flood takes that pixel back. Beyond
/// the image is blank, so the border closes nothing. `gap` <= 0 gives the ink itself.
std::vector<char> close_ink(const std::vector<char>& ink, int w, int h, double gap);

/// @brief In a line drawing, strokes that run past the outline (overshoots, construction
/// lines reaching out) are thin spurs of ink on the filled object: the object (`bg` false)
/// opened with the closing's disc loses them. Pieces of ink (`ink`) the opening removes
/// that are larger than a corner's rounding become background (`bg` true). Returns the
/// number of pixels removed.
std::size_t remove_thin_spurs(std::vector<char>& bg, const std::vector<char>& ink, int w, int h, double gap);

/// @brief A slit the artist drew as two lines stays open: the paper the gap closing bridged
/// between two strokes (`closed` but not `ink`, w x h, row-major) where it comes to the
/// background (`bg` true) without reaching any enclosed paper the closing left open, and
/// where the strokes along it have the object's paper behind them (both sides outlines of
/// parts, as between a foot and a shin or between toes), becomes background. A break in an
/// outline is not such a slit (its bridge reaches the inside behind it), nor the paper
/// between doubled strokes (the outer stroke has the background behind it). Returns the
/// number of pixels opened.
std::size_t open_drawn_slits(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                             int w, int h);

} // namespace cm
