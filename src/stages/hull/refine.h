// Exact crossings of the visual hull with the lattice edges (hull.marching_intersections).
#pragma once
#include <cstddef>
#include <memory>

#include "core/algorithm.h"
#include "core/volume.h"
#include "geometry/visual_hull.h"

namespace cm {

/// The parameters of hull.marching_intersections (`thin`), and what a caller may add.
struct RefineOptions {
    /// Look for edges whose two outside ends pass through the hull (parts thinner than a
    /// cell). Auto: only when a cell spans more than `thin_auto_px` pixels of the finest
    /// view; on finer grids such parts are thinner than the silhouettes can show.
    enum class Thin { Auto, On, Off };
    Thin thin;
    double thin_auto_px = 1.0;
    /// Also store the exact outward normal of every crossing (add_normal_grids()).
    bool normals = false;
    /// Their smoothing radius in pixels (hull_normal()).
    double normal_px = 3.0;

    RefineOptions() { set_declared_defaults(*this); }
    /// `thin`.
    void declare(ParamBinder& b);
};

struct RefineStats {
    std::size_t crossings = 0;      ///< edges with differing ends
    std::size_t thin_crossings = 0; ///< outside-outside edges that pass through the hull
    std::size_t unresolved = 0;     ///< crossings the silhouettes could not place (set at the changing end)
    double cell_px = 0;             ///< grid spacing in pixels of the finest view (at the hull's centre)
    bool thin_searched = false;
    std::size_t grid_bytes = 0; ///< of the crossings grid
    /// The counts, the pitch and whether thin parts were searched; unresolved crossings with a
    /// warning.
    void report(Metrics& m) const;
};

/// @brief Stores the exact outward normal of the hull at every crossing of `vol` as the
/// extra grids "normal_x", "normal_y", "normal_z" (openvdb::Vec3fGrid on the crossings'
/// transform): grid a at p holds the normal where the edge p -> p + e_a crosses the hull,
/// active exactly where that crossing is set (see hull_normal.h). Replaces earlier ones.
/// @throw cm::Error when the volume has no crossings.
void add_normal_grids(Volume& vol, const VisualHull& hull, double normal_px = 3.0);

/// @brief Finds, for every lattice edge whose ends differ in occupancy, where it leaves
/// the visual hull of `views` (the intersection of the per-view inside intervals along
/// the edge, each found on the sub-pixel silhouette model), and the thin parts between
/// two outside grid points. The occupancy grid is shared with the input, not copied. `views`
/// null: the volume's own. The hull reads the input's silhouette tables when `views` are the
/// volume's own (else it makes them); the result carries them (Volume::silhouette_tables).
/// @param progress reported between chunks; cm::Cancelled from it stops the search.
/// @throw cm::Error when the volume has no occupancy or no views are given.
Result<std::shared_ptr<Volume>, RefineStats> refine(const Volume& in, std::shared_ptr<const Views> views,
                                                    const RefineOptions& opt, Progress progress = {});

} // namespace cm
