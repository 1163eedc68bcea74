// The window around a drawing's ink its analysis is confined to.
#pragma once
#include <optional>

#include "background_model.h"
#include "io/image_io.h"
#include "sheet.h"

namespace cm {

// A window of an image: the rectangle sheets cut their panels by (sheet.h).
using Window = SheetPanel;

/// @brief The window the analysis of a drawing can be confined to: the box of its ink
/// (pixels the background's colour does not explain) grown by `margin`, within the image;
/// none when the drawing has no ink. Every step of the analysis reaches less than the margin
/// beyond the ink (gap closing its radius, the coverage of the outline two pixels), so beyond
/// the window every pixel is background reached from the border, and the steps give the
/// same answers on the window as on the whole image, at a fraction of the pixels.
std::optional<Window> ink_window(const Image& img, const BackgroundModel& model, double t, int margin);

} // namespace cm
