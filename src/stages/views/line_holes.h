// Holes in a line drawing: the blank regions inside its outlines, told apart by nesting and
// by what lies across their strokes.
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

namespace cm {

/// What nested_holes says of a region.
enum NestedKind : char {
    kNestedInside = 0, ///< the object's inside (or surface detail)
    kNestedHole = 1,   ///< behind an even number of strokes
    kBetweenParts = 2, ///< behind one stroke, bounded by the outlines of parts: a gap between them
};

/// @brief What lies across the strokes from each region. Each stroke pixel (of `barrier`)
/// belongs to the nearest region or to the outside background (steps through strokes);
/// where the stroke pixels of two owners meet, they are across a stroke from each other.
/// The lengths are counted in stroke pixels of the region's own side.
struct RegionLinks {
    std::vector<std::size_t> outside;                             ///< length facing the outside
    std::vector<std::vector<std::pair<int, std::size_t>>> beside; ///< (other region, length)
};
RegionLinks link_regions(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                         const std::vector<char>& bg, int w, int h);

/// @brief Which blank regions of a line drawing are holes. `region` labels the blank
/// regions the drawing encloses (-1 elsewhere; `count` of them), `barrier` marks the
/// strokes (ink with its gaps closed) and `bg` what the border reaches, all w x h. Walking
/// in from the border, each stroke crossed turns object into hole and back: a region
/// behind one stroke is the object's inside, behind two (the inside of a ring's inner
/// outline) a hole, and so on. A region no stroke leads to is inside.
///
/// A region behind one stroke may be a gap between parts rather than the inside: the space
/// between an arm and the body, closed where the hand touches the hip, or between a
/// camel's legs, closed by the belly above and the crossing knees below. Such a region is
/// bounded by the outlines of the parts around it: its strokes face the outside along at
/// most a tenth of their length, and it comes to the outside somewhere (where the parts
/// touch) or lies between two or more other regions. A closed loop of detail (a circle on
/// a face, an eye) lies within one region and faces no outside, even when a line joins it
/// to the outline, and the inside of a part faces the outside along its outline. Like the
/// nested holes, these are candidates, opened on further evidence (see judge_line_regions).
///
/// Returns per region kNestedInside, kNestedHole or kBetweenParts.
std::vector<char> nested_holes(const std::vector<int>& region, int count, const std::vector<char>& barrier,
                               const std::vector<char>& bg, int w, int h);

} // namespace cm
