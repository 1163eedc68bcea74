// The 3D error of a reconstruction against the true model: the mean two-sided surface
// distance (area-weighted samples of each mesh, exact distance to the other mesh's
// triangles), for benchmarks and tests that have the model the views were made from.
#pragma once
#include <cstddef>

#include "core/mesh.h"

namespace cm {

struct SurfaceDistance {
    double recon_to_true = 0; ///< mean distance of the reconstruction's samples to the true surface
    double true_to_recon = 0; ///< mean distance of the true model's samples to the reconstruction
    double mean = 0;          ///< (recon_to_true + true_to_recon) / 2, world units
    double diag = 0;          ///< the true model's bounding-box diagonal
    double mean_pct = 0;      ///< 100 mean / diag
    /// Samples farther from the other mesh than the search reaches (1.25 diagonals): their
    /// distance is counted as that reach, so the mean is a lower bound when this is not 0.
    std::size_t beyond_reach = 0;
};

/// @brief Mean two-sided surface distance of `recon` and `truth`, both in one frame.
/// Each mesh gets `samples` area-weighted points (fixed seed); each point's distance to
/// the other mesh is the exact distance to the nearest of the triangles that OpenVDB's
/// closest-primitive grids (voxel diag/256 near the surface, coarser farther) name
/// around it. TBB-parallel over samples.
/// @throw cm::Error when a mesh has no triangles or no area.
SurfaceDistance surface_distance(const Mesh& recon, const Mesh& truth, int samples = 100000);

} // namespace cm
