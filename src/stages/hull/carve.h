// Visual hull carving into a sparse OpenVDB grid (hull.carve).
#pragma once
#include <functional>
#include <memory>

#include "core/volume.h"

namespace cm {

struct CarveOptions {
    int resolution = 256;   ///< cells along the longest side of the box
    double voxel_ratio = 0; ///< > 0: image pixels per voxel (decides the resolution)
    int pad = 2;            ///< empty cells around the box
};

struct CarveStats {
    int resolution = 0;
    double voxel_size = 0;
    Vec3d box_min, box_max;     ///< the region carved (before padding)
    bool box_estimated = false; ///< no bounds were given: found by a coarse carve
    bool box_touched = false;   ///< the estimated hull reaches the edge of the estimate
};

/// Resolution (cells along the longest side of [lo, hi]) that `voxel_ratio` pixels of
/// the finest view per voxel give; the finest view is measured at the box centre.
/// `tables`: the views' silhouette tables when at hand (none are made for this).
int resolution_from_ratio(const Views& views, Vec3d lo, Vec3d hi, double voxel_ratio,
                          const std::shared_ptr<const SilhouetteTables>& tables = nullptr);

/// The box to carve: the views' bounds, or for views without bounds an estimate from a
/// coarse carve of a region every camera sees (its hulls read `tables`, the views' silhouette
/// tables; null: made for them). Throws cm::Error when none can be found.
void carve_region(const Views& views, Vec3d& lo, Vec3d& hi, CarveStats* stats = nullptr,
                  const std::shared_ptr<const SilhouetteTables>& tables = nullptr);

/// @brief Carves the visual hull of `views` in a sparse grid.
/// Boxes of grid points are decided at once where every view sees their projection all
/// inside or one view sees it all outside; leaf voxels are made only near the surface,
/// interior becomes active tiles (see volume.h for the guarantees). `tables` are the views'
/// silhouette tables (silhouette_tables()), made here when null; the volume carries them
/// (Volume::silhouette_tables) for the stages that ask the hull again.
/// @param progress called between chunks with a fraction in [0, 1]; may throw to cancel.
/// @throw cm::Error for no views, a bad resolution, or an empty hull.
std::shared_ptr<Volume> carve(std::shared_ptr<const Views> views, const CarveOptions& opt,
                              const std::function<void(double)>& progress = {}, CarveStats* stats = nullptr,
                              std::shared_ptr<const SilhouetteTables> tables = nullptr);

/// The number of surface cells (cells with inside and outside corners) a carve at
/// `resolution` will have, from a coarse carve of the same box at `coarse` cells scaled
/// by the square of the ratio (the surface is two-dimensional). Used to estimate the
/// memory of what follows before anything large is allocated.
/// `resolution`, when given, receives the resolution the carve will use; `tables` as for carve().
double estimate_surface_cells(std::shared_ptr<const Views> views, const CarveOptions& opt, int* resolution = nullptr,
                              int coarse = 64, std::shared_ptr<const SilhouetteTables> tables = nullptr);

/// Bytes the stages after the carve keep per surface cell at their peak (refinement,
/// extraction and smoothing of the paper pipeline), measured on the bundled example
/// at resolution 1024 (docs/hull.md).
constexpr double kPipelineBytesPerSurfaceCell = 260.0;

} // namespace cm
