// The ink of concept art: outlines, interior lines and hatching, found as what is thin,
// dark and of high contrast. Texturing leaves it out of the colours it takes from a
// drawing, and the colour error of a textured mesh leaves it out of the drawing's pixels.
#pragma once
#include <vector>

#include "core/views.h"

namespace cm {

/// @brief Ink mask of an image: 1 where a pixel is a thin dark stroke (black top-hat of
/// the luminance over a square of side about `line_width` above `line_contrast`), with
/// `fringe` grown by one pixel for the anti-aliased fringe. Only pixels where `inside` is
/// set are tested.
std::vector<char> find_ink(const Image& img, const std::vector<char>& inside, float line_width, float line_contrast,
                           bool fringe = true);

/// The ink mask grown by one pixel (8-connected) inside `inside`: the stroke with its fringe.
std::vector<char> grow_ink(const std::vector<char>& ink, const std::vector<char>& inside, int w, int h);

} // namespace cm
