// What an opening of a line drawing holds: the parts seen through it, and the narrow tips of
// it that the gap closing shut.
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

/// @brief Gives an opened hole the paper that the gap closing shut next to it. `closed` is
/// the ink with its gaps closed (see close_ink), `ink` the ink itself, `region` the blank
/// regions and `hole` per region whether it was opened (its pixels already background in
/// `bg`). The closing's pixels off the ink (`closed`, not `ink`, not background) go to the
/// nearest blank owner through paper (4-connected steps, so no step crosses a line of ink):
/// an opened hole, another region or the outside (ties to the latter). Those nearest a hole
/// become background: where two lines of its outline converge to a narrow tip (the daylight
/// between two legs down to where the knees cross), the tip belongs to the opening; a break
/// the closing bridged is split halfway, so it stays closed. A region of the inside (not a
/// `candidate` nor a witness: those are judged on their own) under a candidate's size whose
/// paper meets only the holes' is a pocket left in such a tip and opens too. Returns the
/// pixels given.
std::size_t open_hole_tips(std::vector<char>& bg, const std::vector<char>& ink, const std::vector<char>& closed,
                           const std::vector<int>& region, const std::vector<char>& hole,
                           const std::vector<char>& candidate, int w, int h);

} // namespace cm
