// Holes of line art confirmed across opposite views: a region a line drawing encloses is
// surface detail unless the view from the other side shows the same opening.
#pragma once
#include <string>
#include <vector>

#include "core/views.h"
#include "silhouette_holes.h"

namespace cm {

/// @brief Opens the hole candidates of line art (EnclosedRegion::candidate, with their pixels)
/// that the opposite view also holds: two views whose directions are opposite (within about
/// 8 degrees) with image axes parallel or reversed; a candidate of one and one of the other
/// match when their centres, placed in their silhouettes' boxes and mirrored as the axes
/// are, lie within 10 % of the box and their areas, relative to the box, within a factor
/// of 2; a gap between parts (EnclosedRegion::between_parts), bounded by the silhouette's
/// own outline which both views draw alike, within 2 % and 15 %. Both are opened (coverage 0) and marked as holes. `regions[i]` belongs to
/// `views[i]`. Returns a note per pair of matched candidates.
std::vector<std::string> open_confirmed_holes(std::vector<View>& views,
                                              std::vector<std::vector<EnclosedRegion>>& regions);

} // namespace cm
