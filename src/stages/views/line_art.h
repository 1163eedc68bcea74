// The steps of a line drawing's silhouette that work on its strokes: the rim the gap
// closing's barrier adds outside the ink, and where the outline lies within its stroke (an
// artist draws the stroke along the object's edge, so the edge is the stroke's centre line,
// not its outer edge).
#pragma once
#include <cstddef>
#include <vector>

namespace cm {

/// @brief The barrier's rim outside the ink (`closed` but not `ink`, see close_ink) becomes
/// background (`bg` true) where it touches `from` (8-connected): one step, so it cannot pass
/// a bridged break. All w x h, row-major; `from` may be `bg` itself.
void give_back_barrier_rim(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                           const std::vector<char>& from, int w, int h);

/// What pull_to_stroke_centre measured and did.
struct StrokeCentre {
    double stroke_width = 0;          ///< the outline stroke's width, median over the outline (px); 0: none measured
    std::size_t samples = 0;          ///< outline pixels the width was measured at
    double pulled_px = 0;             ///< coverage taken off the silhouette (pixels)
    std::size_t thin_held = 0;        ///< pixels of parts thinner than two strokes kept by their core
    std::size_t pockets_opened = 0;   ///< pixels of paper outside the outline the gap closing had shut
    std::size_t corners_dropped = 0;  ///< stray cores at the outer corner of a stroke turning a sharp corner
    double ink_width = 0;             ///< thin lines: the width measured from the ink (px); 0: not measured
    std::size_t ink_placed = 0;       ///< thin lines: pixels placed from the ink (see place_thin_outline)
    std::size_t paper_given_back = 0; ///< enclosed paper the placement left under one half (give_back_enclosed_paper)
};

/// @brief Moves the silhouette of a line drawing from its strokes' outer edge to their
/// centre line. `bg` marks the background (what the border reaches, and the holes), `ink`
/// the ink (w x h, row-major); `coverage` (the silhouette as extracted, with its
/// anti-aliased outer edge) is pulled in from the background by half the local width of
/// the outline stroke; `close_gaps` is the gap closing's width (gaps.h).
///
/// The width is measured where the outline stroke has the object's blank inside behind it:
/// there the stroke spans from the background to that blank, and its width is the distance
/// from an outer edge pixel to the blank (pixel centres). Samples over 1.5 times the median
/// (strokes merged with others, in junctions and thin parts) are left out; the rest are
/// averaged over a window of 10 px around each pixel, so a wavering pen is followed, and the
/// median stands in where no sample lies near. The ink's anti-aliased fringe, which widens
/// the thresholded stroke on both sides, is taken off.
///
/// Paper outside the outline that the gap closing shut (the wedge where two strokes meet at
/// a concave corner: a blank piece beside the background, within the closing's disc and a
/// stroke of it, and no larger than a square twice that) goes back to the background.
///
/// A part thinner than two strokes (two outlines touching, or a part drawn as a single
/// stroke) keeps a core a quarter stroke each side of its middle line (the ridge of the
/// distance to the background, where the background lies close on both sides), all of it
/// when thinner still: it is kept, never cut away. Nothing beyond the image counts as
/// background, so an object cut by the frame keeps its edge there.
StrokeCentre pull_to_stroke_centre(std::vector<float>& coverage, const std::vector<char>& bg,
                                   const std::vector<char>& ink, double close_gaps, int w, int h);

/// @brief The object's paper the outline's placement (pull_to_stroke_centre,
/// place_thin_outline) left enclosed: pieces (8-connected) of coverage under one half in
/// `coverage` that hold no background pixel (`bg`, w x h, row-major) take back their
/// coverage from `before` (the silhouette before the placement). Such a piece is the paper
/// between the outline and a line run 1-2 px inside it, which the placement takes for the
/// outline's own inner edge; it is enclosed by ink and the object, and the region judge,
/// which decides the holes, left it inside. Returns the number of pixels given back.
std::size_t give_back_enclosed_paper(std::vector<float>& coverage, const std::vector<float>& before,
                                     const std::vector<char>& bg, int w, int h);

} // namespace cm
