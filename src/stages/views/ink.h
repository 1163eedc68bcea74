// The ink of a drawing as its colour distance to the paper shows it: the window it lies in,
// and faint ink along thin lines (hysteresis), so a thin pencil line on grainy paper, whose
// anti-aliased pixels the grain's threshold misses in part, is read whole.
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "background_model.h"
#include "sheet.h"

namespace cm {

/// @brief The window the analysis of a drawing can be confined to: the box of its ink
/// (pixels at colour distance `t` or more from the background `model`) grown by `margin`,
/// within the image; none when the drawing has no ink. Every step of the analysis reaches
/// less than the margin beyond the ink (gap closing its radius, the coverage of the outline
/// two pixels), so beyond the window every pixel is background reached from the border, and
/// the steps give the same answers on the window as on the whole image, at a fraction of the
/// pixels.
std::optional<SheetPanel> ink_window(const Image& img, const BackgroundModel& model, double t, int margin);

/// @brief The weaker threshold ink connected to clear ink needs: clean paper's 0.1 less
/// what the grain takes from faint ink (twice the paper's noise, the median colour distance
/// along the border: grain reaches about that much beyond its median), but at least four
/// times the noise (above the grain itself) and never above `t`, the threshold clear ink
/// needs. On paper without noise it is `t` (nothing changes).
double weak_ink_threshold(double t, double noise);

/// @brief Hysteresis along the strokes: the pixels of the w x h distances `d` at `weak` or
/// more that are 8-connected to a pixel at `t` or more through such pixels are ink too: their
/// distance is raised to `t`. Grain alone stays under `weak`; a faint 1 px line's pixels
/// (each some of the line, none all of it) lie between the two thresholds along stretches and
/// reach clear ink at both ends. Only in a drawing in thin lines: the width of its strokes
/// by their ink (the lower quartile of the runs of pixels at `weak` or more across them along
/// the rows and the columns, each pixel its distance over the full ink's, the 95th percentile
/// of the clear ink) at most 1.75 px; 1 px lines measure 0.7-1.6 so (more where lines run
/// together), 2 px lines 1.9-2.2. Wider strokes and filled shapes are whole by their clear
/// ink, and their faint pixels are their anti-aliased fringe: taken, they would widen them,
/// and nothing is raised. Returns how many pixels were raised.
std::size_t raise_weak_ink(std::vector<double>& d, double t, double weak, int w, int h);

} // namespace cm
