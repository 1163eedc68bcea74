// The shape of a lofted section from the view along its axis (plausible_loft.cpp): inside the
// box the other two views give at a station, the view along the slicing axis shows where the
// object's sections lie (the union of them along the axis). Where it covers only part of the
// box (a body leaning across the box, a diagonal band in the top view), the ellipse inscribed
// in the whole box holds the box's empty corners; an ellipse with the centre, axes and
// orientation of the covered part follows the object instead.
#pragma once

#include <array>
#include <vector>

#include "plausible_projection.h"

namespace cm::plausible {

/// @brief A section fitted to the covered part of a box: centre and axes along the slicing
/// axis's b and c (the two other axes, b = (a + 1) % 3, c = (a + 2) % 3), in grid cells.
struct FittedSection {
    double cb = 0, cc = 0; ///< centre
    double eb = 1, ec = 0; ///< unit direction of the first axis (b, c)
    double r1 = 0, r2 = 0; ///< half-lengths along the first axis and across it (r1 >= r2)
    double compact = 0;    ///< covered area over the area of the ellipse of its moments, about 1 for one blob
    bool valid = false;
    /// The section's norm at (pb, pc): 1 on its outline, `exponent` 2 an ellipse.
    double norm(double pb, double pc, double exponent) const;
};

/// @brief Summed-area tables of the first and second moments of each projection's inside
/// pixels, for FittedSection in constant time per box.
class SectionMoments {
public:
    explicit SectionMoments(const std::array<Projection, 3>& proj);
    /// The section across axis a fitted to the part of the box (ib along b, ic along c) the
    /// projection along a covers.
    FittedSection fit(int a, const Interval& ib, const Interval& ic) const;

private:
    struct Tables {
        std::vector<double> m[6]; ///< 1, u, v, uu, vv, uv (local coordinates), (nu + 1) x (nv + 1)
    };
    const std::array<Projection, 3>& proj_;
    std::array<Tables, 3> t_;
};

} // namespace cm::plausible
