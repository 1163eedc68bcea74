// The thin-part search of hull.marching_intersections: lattice edges whose two ends are
// outside the hull but which pass through it (a part thinner than a grid cell).
#pragma once
#include <cstddef>

#include "core/progress.h"
#include "core/volume.h"
#include "geometry/visual_hull.h"
#include "refine_lattice.h"

namespace cm::refining {

/// @brief Searches the thin edges of `occupancy`'s lattice points (those of the hull's clip
/// box, or the occupied region grown by a leaf without one) and stores them in `out` as the
/// grids "thin_enter" and "thin_leave" (replacing any it had): per lattice point and axis,
/// where its edge's inside interval starts and ends. Returns the number of thin edges.
/// `progress` runs from nblocks / total_work to 2 nblocks / total_work.
std::size_t add_thin_parts(Volume& out, const openvdb::BoolGrid& occupancy, const VisualHull& hull, const Lattice& lat,
                           std::size_t nblocks, double total_work, const Progress& progress);

} // namespace cm::refining
