// Pockets: the few pixels of partial coverage a drawn view's silhouette encloses among its
// strokes, filled as the paper between strokes is.
#pragma once
#include <cstddef>

#include "core/views.h"

namespace cm {

/// @brief Fills the pockets of a drawn view's coverage: regions of coverage under one half
/// (8-connected) that the background does not reach (none touches the coverage's window,
/// beyond which all is background) and holding less paper than the gaps between strokes
/// (kStrokeGapArea, silhouette_holes.h: their pixels' uncovered shares, 1 - coverage,
/// summed) become object (coverage 1). Partly covered pixels among
/// marker strokes, and those a reconciled view's resampling makes, escape the fill of the
/// paper between strokes, which works on the blank pixels; a pocket that small is no opening
/// the hull could resolve, but each would carve a thin tunnel along the view's rays. Not for
/// photographs nor views whose holes are all kept. Returns the number of pockets filled;
/// `cov` is untouched when there are none.
std::size_t fill_pockets(Coverage& cov);

} // namespace cm
