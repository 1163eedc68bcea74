// The extent of a silhouette in its image, to a fraction of a pixel: what the alignment of
// drawn views measures (align.h).
#pragma once
#include "core/views.h"

namespace cm {

/// Sub-pixel extent of a silhouette along image x and y.
struct Extent {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

/// @brief The first and last columns (rows) with a pixel of coverage >= 0.5, moved by the
/// largest partial coverage of the column itself and of the one beyond: an anti-aliased
/// extreme lands to a fraction of a pixel, a binary one on the pixel edge (its expected
/// place). @throw cm::Error naming the view for an empty silhouette.
Extent silhouette_extent(const View& v);

} // namespace cm
