// Marching Cubes over a sparse occupancy grid with exact edge crossings.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace cm {

/// The parameters of extract.marching_cubes (the dual extractors offer some of them).
struct MarchingCubesOptions {
    /// How an ambiguous face (inside corners on one diagonal) is resolved:
    /// Geometric pairs its four crossings so the two surface segments are shortest
    /// (the inside joins across the face when its crossings lie near the outside corners);
    /// Separate always cuts the inside corners apart; Join always connects them.
    enum class Ambiguity { Geometric, Separate, Join };
    Ambiguity ambiguity;
    /// Use the volume's exact crossings (else edge midpoints, plain binary Marching Cubes).
    bool use_crossings;
    /// Use the thin-part grids ("thin_enter"/"thin_leave") so parts thinner than a cell stay.
    bool use_thin;
    /// Crossings closer than this fraction of an edge to a grid point are moved out to it,
    /// so vertices never coincide and no triangle collapses.
    double min_edge_fraction;

    MarchingCubesOptions() { set_declared_defaults(*this); }
    /// The parameters of extract.marching_cubes: `ambiguity`, `crossings`, `thin_parts` and
    /// `min_edge_fraction`.
    void declare(ParamBinder& b);
    /// `ambiguity`, its doc starting with `what` (the faces it is about, for the stage).
    void declare_ambiguity(ParamBinder& b, const std::string& what);
    /// `thin_parts`.
    void declare_thin_parts(ParamBinder& b);
};

struct MarchingCubesStats {
    std::size_t blocks = 0;            ///< 8^3 blocks of cells with surface
    std::size_t surface_cells = 0;     ///< cells with mixed corners
    std::size_t ambiguous_faces = 0;   ///< face evaluations with a diagonal pattern (each face seen twice)
    std::size_t joined_faces = 0;      ///< of those, resolved by joining the inside
    std::size_t centroid_vertices = 0; ///< extra vertices for loops with no valid diagonal triangulation
    std::size_t missing_crossings = 0; ///< crossed edges without a valid crossing value (midpoint used)
    std::size_t thin_points = 0;       ///< grid points made inside to keep thin parts
    std::size_t thin_shifted = 0;      ///< vertices moved onto the near face of a thin part
    std::size_t thin_put_back = 0;     ///< of those, put back on their edges (their faces crossed another)
    bool refined = false;              ///< the vertices sit at the volume's crossings (use_crossings, and it has them)

    /// The figures of extract.marching_cubes, and a warning for crossed edges without a crossing.
    void report(Metrics& m) const;
};

/// The cell structure behind a Marching Cubes mesh, for the dual extractors: every loop is
/// one disc of surface inside one cell (the cell's part of one surface component).
struct MarchingCubesPatches {
    std::vector<std::uint32_t> triangle_loop; ///< per triangle: its loop
    std::vector<openvdb::Coord> loop_cell;    ///< per loop: its cell (the cell's lowest grid point)
    /// Per vertex: the lattice edge it sits on, as start point and axis (axis -1 for the extra
    /// centre vertex of a loop).
    std::vector<std::array<std::int32_t, 4>> vertex_edge;
};

/// @brief Extracts the boundary of `vol.occupancy` as a closed, 2-manifold, outward
/// triangle mesh in world space (the volume's transform). One vertex per crossed
/// lattice edge, placed at the exact crossing when the volume is refined.
/// TBB-parallel over 8^3 blocks of cells.
/// @throw cm::Error when the occupancy is missing or its grids do not match.
Result<Mesh, MarchingCubesStats> marching_cubes(const Volume& vol, const MarchingCubesOptions& opt = {},
                                                Progress progress = {});

/// What marching_cubes_loops() returns: the mesh, the loops behind its triangles, its stats.
struct MarchingCubesLoops {
    Mesh mesh;
    MarchingCubesPatches patches;
    MarchingCubesStats stats;
};

/// @brief marching_cubes(), with the loops behind the triangles (for the dual extractors).
MarchingCubesLoops marching_cubes_loops(const Volume& vol, const MarchingCubesOptions& opt = {},
                                        Progress progress = {});

} // namespace cm
