// Exact crossings of the visual hull with the lattice edges (hull.marching_intersections).
#pragma once
#include <cstddef>
#include <functional>
#include <memory>

#include "core/volume.h"

namespace cm {

struct RefineOptions {
    bool thin = true;   ///< also look for edges whose two outside ends pass through the hull
};

struct RefineStats {
    std::size_t crossings = 0;        ///< edges with differing ends
    std::size_t thin_crossings = 0;   ///< outside-outside edges that pass through the hull
    std::size_t unresolved = 0;       ///< crossings the silhouettes could not place (set at the changing end)
};

/// @brief Finds, for every lattice edge whose ends differ in occupancy, where it leaves
/// the visual hull of `views` (the intersection of the per-view inside intervals along
/// the edge, each found on the sub-pixel silhouette model), and the thin parts between
/// two outside grid points. The occupancy grid is shared with the input, not copied.
/// @param progress called between chunks with a fraction in [0, 1]; may throw to cancel.
/// @throw cm::Error when the volume has no occupancy or no views are given.
std::shared_ptr<Volume> refine(const Volume& in, std::shared_ptr<const Views> views, const RefineOptions& opt,
                               const std::function<void(double)>& progress = {}, RefineStats* stats = nullptr);

} // namespace cm
