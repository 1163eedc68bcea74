// Visual hull carving into a sparse OpenVDB grid (hull.carve).
#pragma once
#include <memory>
#include <optional>

#include "core/algorithm.h"
#include "core/volume.h"

namespace cm {

/// The parameters of hull.carve, and the padding of the box.
struct CarveOptions {
    int resolution; ///< cells along the longest side of the box
    /// Image pixels per cell in the finest view: when set it decides the resolution.
    std::optional<double> voxel_ratio;
    int pad = 2; ///< empty cells around the box (not a parameter)

    CarveOptions() { set_declared_defaults(*this); }
    /// `resolution` and `voxel_ratio`.
    void declare(ParamBinder& b);
};

struct CarveStats {
    int resolution = 0;
    double voxel_size = 0;
    Vec3d box_min, box_max;     ///< the region carved (before padding)
    bool box_estimated = false; ///< no bounds were given: found by a coarse carve
    bool box_touched = false;   ///< the estimated hull reaches the edge of the estimate
    std::size_t active_voxels = 0, active_tiles = 0, leaf_count = 0, grid_bytes = 0; ///< of the carved grid
    /// The resolution, voxel size and the grid's figures; a warning when the estimated box
    /// is touched by the hull.
    void report(Metrics& m) const;
};

/// What a carve at a resolution will hold, from a coarse carve (estimate_surface()).
struct SurfaceEstimate {
    double surface_cells = 0; ///< cells with inside and outside corners
    int resolution = 0;       ///< the resolution the carve will use
    /// Bytes the stages after the carve will keep at their peak (kPipelineBytesPerSurfaceCell).
    double peak_bytes() const;
    /// `estimated_surface_cells` and `estimated_peak_bytes`.
    void report(Metrics& m) const;
};

/// Resolution (cells along the longest side of [lo, hi]) that `voxel_ratio` pixels of
/// the finest view per voxel give; the finest view is measured at the box centre.
/// `tables`: the views' silhouette tables when at hand (none are made for this).
int resolution_from_ratio(const Views& views, Vec3d lo, Vec3d hi, double voxel_ratio,
                          const std::shared_ptr<const SilhouetteTables>& tables = nullptr);

/// The box to carve (carve_region()).
struct CarveRegion {
    Vec3d lo, hi;
    bool estimated = false; ///< the views have no bounds: found by a coarse carve
    bool touched = false;   ///< the estimated hull reaches the edge of the region searched
};

/// The box to carve: the views' bounds, or for views without bounds an estimate from a
/// coarse carve of a region every camera sees (its hulls read `tables`, the views' silhouette
/// tables; null: made for them). Throws cm::Error when none can be found.
CarveRegion carve_region(const Views& views, const std::shared_ptr<const SilhouetteTables>& tables = nullptr);

/// @brief Carves the visual hull of `views` in a sparse grid.
/// Boxes of grid points are decided at once where every view sees their projection all
/// inside or one view sees it all outside; leaf voxels are made only near the surface,
/// interior becomes active tiles (see volume.h for the guarantees). `tables` are the views'
/// silhouette tables (silhouette_tables()), made here when null; the volume carries them
/// (Volume::silhouette_tables) for the stages that ask the hull again.
/// @param progress reported between chunks; cm::Cancelled from it stops the carve.
/// @throw cm::Error for no views, a bad resolution, or an empty hull.
Result<std::shared_ptr<Volume>, CarveStats> carve(std::shared_ptr<const Views> views, const CarveOptions& opt,
                                                  std::shared_ptr<const SilhouetteTables> tables = nullptr,
                                                  Progress progress = {});

/// The number of surface cells (cells with inside and outside corners) a carve with `opt`
/// will have, from a coarse carve of the same box at `coarse` cells scaled by the square of
/// the ratio (the surface is two-dimensional), and the resolution it will use. Used to
/// estimate the memory of what follows before anything large is allocated. `tables` as for
/// carve().
SurfaceEstimate estimate_surface(std::shared_ptr<const Views> views, const CarveOptions& opt,
                                 std::shared_ptr<const SilhouetteTables> tables = nullptr, int coarse = 64);

/// Bytes the stages after the carve keep per surface cell at their peak (refinement,
/// extraction and smoothing of the paper pipeline), measured on the bundled example
/// at resolution 1024 (docs/hull.md).
constexpr double kPipelineBytesPerSurfaceCell = 260.0;

} // namespace cm
