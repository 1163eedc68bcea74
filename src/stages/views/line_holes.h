// Holes in a line drawing: the blank regions inside its outlines, told apart by nesting.
#pragma once
#include <vector>

namespace cm {

/// @brief Which blank regions of a line drawing are holes. `region` labels the blank
/// regions the drawing encloses (-1 elsewhere; `count` of them), `barrier` marks the
/// strokes (ink with its gaps closed) and `bg` what the border reaches, all w x h. Walking
/// in from the border, each stroke crossed turns object into hole and back: a region
/// behind one stroke is the object's inside, behind two (the inside of a ring's inner
/// outline) a hole, and so on. A region no stroke leads to is inside.
std::vector<char> nested_holes(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                               const std::vector<char>& bg, int w, int h);

} // namespace cm
