// What an opening of a line drawing holds: the parts seen through it.
#pragma once
#include <cstddef>
#include <vector>

namespace cm {

/// @brief Which candidate openings of a line drawing are parts seen through a larger one.
/// `region` labels the blank regions (-1 elsewhere; `count` of them), `kind` is what
/// nested_holes says of each, `barrier` marks the strokes and `bg` what the border reaches,
/// all w x h. One line between two openings would be a part with no width: of two candidates
/// beside each other across a stroke (see link_regions) along at least a quarter of the
/// smaller one's rim, at most one is daylight. The smaller, at most half the larger's area
/// (to the strokes' centre lines), is the part: a leg behind the gap between two legs, seen
/// through it and bounded by its own outline there. Returns per region 1 for such a part.
std::vector<char> parts_seen_through(const std::vector<int>& region, int count, const std::vector<char>& kind,
                                     const std::vector<char>& barrier, const std::vector<char>& bg, int w, int h);

} // namespace cm
