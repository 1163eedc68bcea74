// The lofted prior of hull.plausible (`prior: loft`): per voxel, the cross-section of the
// object across each grid axis is taken as a superellipse inscribed in the box the hull's
// projections along the other two axes give there; the voxel follows the axis whose box is
// smallest (the most section-like), made square where the walls are straight and the view
// along the axis shows the box's sides as its outline.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "plausible_state.h"

namespace cm::plausible {

/// The lofted prior at a voxel.
struct LoftValue {
    float field = 0;  ///< cells outside the lofted section (<= 0 inside)
    float square = 0; ///< how square the section is, in [0, 1] (1: the hull decides)
    float fit = 0;    ///< how well the view along the section's axis covers its box, in [0, 1]
    float drop = 0;   ///< 1 in a box that pairs two parts' runs the evidence rules out (plausible_tracks.h)
};

/// @brief The lofted field of every voxel of `vox` (cells, <= 0 inside the lofted sections;
/// about the distance to the section's outline in cells). `round_exponent` is the exponent of
/// a rounded section (2: an ellipse).
std::vector<LoftValue> loft_field(const HullVoxels& vox, double round_exponent);

/// body(index, values, count) for each leaf of `vox`, in parallel: the lofted prior of the
/// leaf's voxels (values[k] that of voxel index[k]), all of them or, with `only` (per leaf,
/// LeafManager order), just those in it.
/// `proj`: the hull's projections (project_hull(), plausible_projection.h).
using LoftLeafBody = std::function<void(const std::uint32_t* index, const LoftValue* values, std::size_t count)>;
void loft_by_leaf(const HullVoxels& vox, const std::array<Projection, 3>& proj, double round_exponent,
                  const std::vector<LeafMask>* only, const LoftLeafBody& body);

} // namespace cm::plausible
