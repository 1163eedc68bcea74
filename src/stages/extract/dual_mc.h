// Dual Marching Cubes on exact Hermite data: one vertex per disc of surface in a cell,
// placed by a QEF over the cell's crossings and their normals, one quad per crossed edge.
#pragma once
#include <cstddef>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/volume.h"
#include "marching_cubes.h"

namespace cm {

/// The parameters of extract.dual_marching_cubes (the Marching Cubes ones it offers among them).
struct DualMcOptions {
    /// The topology: the Marching Cubes loops (ambiguity, thin parts, crossings).
    MarchingCubesOptions mc;
    /// Where the crossings' normals come from. Auto: the stored grids when the volume has
    /// them (refine's "normal_x/y/z"), else the views' outlines, else the Marching Cubes
    /// mesh's own vertex normals (an approximation, for volumes without views).
    enum class Normals { Auto, Views, Mesh };
    Normals normals;
    /// From the views: the outlines' directions averaged over a disc of this radius in
    /// pixels (hull_normal.h); 0 takes the outline's normal at the point.
    double normal_px;
    /// Eigenvalues of the QEF under this fraction of its largest are dropped
    /// (pseudo-inverse): a flat or ruled patch keeps its vertex near the crossings' mean.
    double singular_ratio;
    /// Adaptivity (in cells): the cells of an octree node are merged into one vertex when it
    /// lies within this distance of every crossing's tangent plane and the merge keeps the
    /// topology (dmc_octree.h); 0 keeps one vertex per disc of every cell.
    double max_error;
    /// Remove crossing faces where they come from (dual_mc.cpp): undo merges whose polygons
    /// cross another part of the surface, put vertices of crossing faces at their mass point,
    /// split their quads the other way. On by default; off only to see what the extraction
    /// alone makes. Not a parameter.
    bool guard = true;

    DualMcOptions() { set_declared_defaults(*this); }
    /// `normals`, `normal_px`, `max_error`, `singular_ratio`, and Marching Cubes' `ambiguity`
    /// and `thin_parts`.
    void declare(ParamBinder& b);
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
    int guard_rounds = 0;               ///< rounds of the crossing guard (the mesh crossed itself)
    std::size_t relaxed = 0;            ///< vertices the guard put at their mass point
    std::size_t flipped = 0;            ///< quads the guard split along the other diagonal
    std::size_t crossings_left = 0;     ///< crossing face pairs the guard could not remove
    const char* normals = "";           ///< "stored", "views" or "mesh"
    MarchingCubesStats mc;

    /// The figures of extract.dual_marching_cubes, and warnings for crossed edges without a
    /// crossing and for crossing faces left.
    void report(Metrics& m) const;
};

/// @brief Extracts the boundary of `vol` as a closed, 2-manifold, outward triangle mesh by
/// dual contouring on the Marching Cubes loops: each loop (one disc of surface in one cell)
/// gets one vertex, at the minimum of the QEF of its crossings and their exact normals
/// (pseudo-inverse, clamped to the cell); each crossed lattice edge gets one quad joining
/// the discs of its four cells, split along the diagonal that bends it least.
/// @throw cm::Error when the occupancy is missing, the grids do not match, or normals are
/// asked from the views of a volume that has none.
Result<Mesh, DualMcStats> dual_marching_cubes(const Volume& vol, const DualMcOptions& opt = {}, Progress progress = {});

} // namespace cm
