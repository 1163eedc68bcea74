// The checks of a mesh: its topology (closed, 2-manifold, oriented, degenerate faces) for
// tests and run reports, and the output rules every mesh leaving the tool must meet
// (mesh.write and `conceptmesh check`).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/progress.h"
#include "geometry/mesh_intersect.h"

namespace cm {

/// Topology facts of a triangle mesh, for tests and run reports.
struct MeshCheck {
    std::size_t boundary_edges = 0;       ///< edges with one face
    std::size_t nonmanifold_edges = 0;    ///< edges with more than two faces
    std::size_t nonmanifold_vertices = 0; ///< vertices whose faces form more than one fan
    std::size_t inconsistent_edges = 0;   ///< edges used twice in the same direction
    std::size_t degenerate_faces = 0;     ///< repeated index or zero area
    std::size_t components = 0;
    double signed_volume = 0; ///< > 0 for an outward closed mesh
    double area = 0;
    long euler = 0; ///< V - E + F
    bool closed_manifold() const {
        return boundary_edges == 0 && nonmanifold_edges == 0 && nonmanifold_vertices == 0 && inconsistent_edges == 0;
    }
};
MeshCheck check_mesh(const Mesh& m);

/// The output rules of a mesh leaving the tool: closed, 2-manifold, consistently oriented,
/// outward, no degenerate face, no crossing faces (mesh.write and `conceptmesh check`).
struct OutputCheck {
    MeshCheck mesh;
    std::vector<FacePair> crossings;
    /// Vertices with another vertex within kCoincidentTolerance of the bounding-box diagonal:
    /// an importer that merges by distance (Blender, most engines) welds them, and the
    /// welded mesh may be non-manifold where this one is not.
    std::size_t coincident_vertices = 0;
    bool clean() const;
    /// One phrase per broken rule ("3 boundary edges", ...); empty when clean.
    std::vector<std::string> broken() const;
};
/// The output rules measured on `mesh`; `progress` hears of each step (and per chunk of the
/// crossing test), and a stop there ends the check (cm::Cancelled).
OutputCheck check_output(const Mesh& mesh, Progress progress = {});

} // namespace cm
