// Line art drawn in thin lines (about a pixel wide): where the outline lies within its
// anti-aliased stroke, read from the amount of ink across the stroke rather than from the
// stroke's thresholded shape.
#pragma once
#include <vector>

#include "line_art.h"

namespace cm {

/// @brief Places the outline of line art drawn in thin lines at its strokes' centre line from
/// the ink itself. `coverage` is the silhouette after pull_to_stroke_centre, `bg` the
/// background (what the border reaches, and the holes), `dist` each pixel's colour distance
/// to the paper and `t` the ink's threshold on it (all w x h, row-major); `stroke` receives
/// the width measured (ink_width) and the pixels placed (ink_placed).
///
/// A 1 px line is anti-aliased over two pixels, neither of them full ink, so its thresholded
/// width is 1 or 2 px by turns along the outline (or 1.41 on a slant), and half of it taken
/// off the outer edge puts the outline a pixel in or a pixel out by turns. The amount of ink
/// does not jitter: each pixel's ink fraction is its distance to the paper over the full
/// ink's (the drawing's strongest ink, 95th percentile), and across a stroke along a row or a
/// column the outline lies where half of the stroke's ink is passed. A pixel is inside when
/// the ink up to its centre (from the background) is at least half the stroke's; a pixel
/// at exactly half (a 1 px stroke on one pixel) is inside in every ink colour, the float
/// rounding of its ink fraction aside.
///
/// A crossing counts when it is a single stroke from the background to the object's blank
/// inside, or the outline stroke with a line just inside it run into it (the stroke then
/// ends at the first valley of the ink: under half its peak, rising after); a part drawn as
/// one stroke or two outlines merged is left to pull_to_stroke_centre. Each pixel takes the
/// crossing, along its row or its column, that passes the stroke most squarely (the least
/// ink). Only strokes up to 1.3 px wide by their ink (the lower quartile of the crossings)
/// are placed so: wider ones are measured well by their thresholded shape.
void place_thin_outline(std::vector<float>& coverage, const std::vector<char>& bg, const std::vector<double>& dist,
                        double t, int w, int h, StrokeCentre& stroke);

} // namespace cm
