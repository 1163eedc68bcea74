// The fill of a marker or hatched drawing under its strokes: the paper left showing between
// strokes (thin, light, of the paper's colour) found beside the ink, and the colour of the
// fill smoothed across the stroke pattern (a low-pass of the pixels that are neither).
// Texturing takes its colours from it; the benchmarks measure a texture against it.
#pragma once
#include <array>
#include <vector>

#include "core/views.h"

namespace cm {

/// @brief Paper slivers of an image: 1 where a pixel inside `inside` is a thin light
/// feature (white top-hat of the luminance over a square of side about `width` above
/// `contrast`) whose colour lies within `paper_distance` (RGB, Euclidean) of `paper`.
std::vector<char> find_paper_slivers(const Image& img, const std::vector<char>& inside,
                                     const std::array<float, 3>& paper, float width, float contrast,
                                     float paper_distance = 0.35f);

/// @brief Pale streaks of a marker fill: 1 where a pixel inside `inside` is a thin feature
/// (narrower than about `width`) whose colour lies on the way from its local fill `fill`
/// (per pixel) to `paper`, at least `toward` of the way there (and `min_step` RGB from the fill),
/// where the marker ran dry or the paper shows through thinly, and as streaks do, repeated:
/// at least `density` of the square of side 4 `width` + 1 around is such a pixel. Shading
/// drawn in the fill (gradients, bands wider than `width`, a lone lit edge) and a thin line
/// of another hue (not towards the paper) stay. So does hatching: a pale pixel within 1.5
/// `width` of the paper showing (a pixel within `paper_distance` of `paper`, or nearer it
/// than `paper_part` of its fill's distance) is the edge of strokes laid on paper, whose
/// paper is the drawing's lightness; a marker's strokes cover the paper around its streaks.
std::vector<char> find_pale_streaks(const Image& img, const std::vector<char>& inside,
                                    const std::vector<std::array<float, 3>>& fill, const std::array<float, 3>& paper,
                                    float width, float toward = 0.15f, float min_step = 0.04f, float density = 0.05f,
                                    float paper_distance = 0.2f, float paper_part = 0.4f);

/// @brief Leaves out of `ink` the coloured strokes: pixels whose saturation (largest minus
/// smallest of R, G, B) is at least `max_chroma`. Marker strokes and coloured hatching are the
/// fill as drawn, not ink; outlines and hatching in black, grey or pencil stay ink.
void keep_neutral_ink(const Image& img, std::vector<char>& ink, float max_chroma);

/// The mean colour of the pixels outside `inside` (the paper of a drawing flattened onto
/// it); white when every pixel is inside.
std::array<float, 3> paper_colour(const Image& img, const std::vector<char>& inside);

/// @brief The fill under the strokes: per pixel, the mean colour of the `keep` pixels in
/// the square of side 2 `radius` + 1 around it (a box low-pass normalised by the kept
/// pixels), and in `share` the fraction of that square (within the image) that is
/// `strokes` (how much of the neighbourhood is stroke). A pixel with no kept pixel around
/// keeps its own colour.
std::vector<std::array<float, 3>> fill_under_strokes(const Image& img, const std::vector<char>& keep,
                                                     const std::vector<char>& strokes, int radius,
                                                     std::vector<float>& share);

} // namespace cm
