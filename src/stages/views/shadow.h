// Ground shadows: the soft grey shadow drawn or photographed under an object is background.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "background_model.h"
#include "io/image_io.h"

namespace cm {

/// @brief Makes a ground shadow background. `bg` (1 = background, row-major like the RGBA
/// image) is what the border reaches; `background` is the background colour the model gives
/// each pixel. Shadow-like pixels are darker than their background by a factor in
/// [0.35, 0.97] with the background's hue (each channel within 0.06 of the scaled
/// background colour), and not next to anything else of the object. A connected region of
/// them touching the background is a ground shadow when it lies under the object: its
/// lowest row at or below the object's, its centre below the object's centre, and at most
/// half the object's height. A region with blank paper of the object (enclosed, the
/// background's colour) within 4 px of at least half its pixels is grey pencil line art
/// (lines, or lines merged with slivers of paper between them), not a shadow, and stays.
/// Returns the number of pixels made background.
std::size_t remove_ground_shadow(const Image& img, const BackgroundField& background, std::vector<char>& bg);

} // namespace cm
