// Dual Marching Cubes on exact Hermite data: one vertex per disc of surface in a cell,
// placed by a QEF over the cell's crossings and their normals, one quad per crossed edge.
#pragma once
#include <cstddef>
#include <functional>

#include "core/mesh.h"
#include "core/volume.h"
#include "marching_cubes.h"

namespace cm {

struct DualMcOptions {
    /// The topology: the Marching Cubes loops (ambiguity, thin parts, crossings).
    MarchingCubesOptions mc;
    /// Where the crossings' normals come from. Auto: the stored grids when the volume has
    /// them (refine's "normal_x/y/z"), else the views' outlines, else the Marching Cubes
    /// mesh's own vertex normals (an approximation, for volumes without views).
    enum class Normals { Auto, Views, Mesh };
    Normals normals = Normals::Auto;
    /// From the views: the outlines' directions averaged over a disc of this radius in
    /// pixels (hull_normal.h); 0 takes the outline's normal at the point.
    double normal_px = 3.0;
    /// Eigenvalues of the QEF under this fraction of its largest are dropped
    /// (pseudo-inverse): a flat or ruled patch keeps its vertex near the crossings' mean.
    double singular_ratio = 0.1;
    /// Adaptivity (in cells): the cells of an octree node are merged into one vertex when it
    /// lies within this distance of every crossing's tangent plane and the merge keeps the
    /// topology (dmc_octree.h); 0 keeps one vertex per disc of every cell.
    double max_error = 0.2;
    /// Undo merges whose polygons cross another part of the surface (dual_mc.cpp): on by
    /// default; off only to see what the merge alone makes.
    bool guard = true;
    /// Called on the calling thread with the fraction done; may throw to cancel.
    std::function<void(double)> progress;
};

struct DualMcStats {
    std::size_t cells = 0;              ///< surface discs (one vertex each)
    std::size_t multi_disc_cells = 0;   ///< discs that share their cell with another (manifold DMC)
    std::size_t split_loops = 0;        ///< discs cut in two: they shared two edges with a neighbour
    std::size_t quads = 0;              ///< crossed edges, one quad each
    std::size_t other_polygons = 0;     ///< edges whose ring of discs is not four (split as a fan)
    std::size_t clamped = 0;            ///< QEF minima outside their cell (weakest directions dropped)
    std::size_t rank[4] = {0, 0, 0, 0}; ///< discs by the QEF's rank: 0 (none), 1 flat, 2 crease, 3 corner
    std::size_t merged = 0;             ///< discs merged into a coarser vertex (adaptive)
    int levels = 0;                     ///< octree levels that merged anything
    int guard_rounds = 0;               ///< merges undone and redone because the merged mesh crossed itself
    const char* normals = "";           ///< "stored", "views" or "mesh"
    MarchingCubesStats mc;
};

/// @brief Extracts the boundary of `vol` as a closed, 2-manifold, outward triangle mesh by
/// dual contouring on the Marching Cubes loops: each loop (one disc of surface in one cell)
/// gets one vertex, at the minimum of the QEF of its crossings and their exact normals
/// (pseudo-inverse, clamped to the cell); each crossed lattice edge gets one quad joining
/// the discs of its four cells, split along the diagonal that bends it least.
/// @throw cm::Error when the occupancy is missing, the grids do not match, or normals are
/// asked from the views of a volume that has none.
Mesh dual_marching_cubes(const Volume& vol, const DualMcOptions& opt = {}, DualMcStats* stats = nullptr);

} // namespace cm
