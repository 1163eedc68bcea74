// Polygon reduction by half-edge collapses on flat arrays, with a priority queue
// and lazy re-scoring. Two orderings share one collapse engine:
//  - reduce_mesh(): the paper's importance (method step 5, after Zhu et al. 2005);
//  - quadric_decimate(): Garland-Heckbert quadric error.
// Every collapse keeps a closed 2-manifold closed and 2-manifold: the edge must
// have two faces and pass the link condition, and no face may flip, collapse to
// zero area or turn by more than the allowed normal deviation. Vertices on a
// boundary or a non-manifold edge are never moved or removed. Faces of distant parts
// that end up crossing are caught after the run (a restart keeps that region).
#pragma once
#include <cstddef>
#include <functional>

#include "core/mesh.h"

namespace cm {

class OutlineGuard;

struct ReduceOptions {
    /// A vertex is a candidate while the largest angle between the normals of its
    /// faces is under this (the paper: 5 to 40 degrees); a collapse may not turn a
    /// face by more than this either.
    double max_angle_deg = 15.0;
    std::size_t target_faces = 0;  ///< stop at or below this many faces; 0: until no vertex can go
    double max_aspect_ratio = 0.0; ///< refuse collapses making a face thinner than this (1 = equilateral); 0: off
    bool no_crossings = true;      ///< see DecimateStats::restarts
    /// Optional: collapses that would move an outline away from the drawn silhouettes are
    /// refused (outline_guard.h); it must outlive the call.
    const OutlineGuard* outline = nullptr;
    std::function<void(double)> progress; ///< fraction done; may throw to cancel
};

struct QuadricOptions {
    std::size_t target_faces = 0; ///< stop at or below this many faces; 0: no face target
    double max_error = 0.0;       ///< stop when the cheapest collapse moves the surface more (world units); 0: no limit
    double max_normal_deviation_deg = 45.0; ///< refuse collapses turning a face more than this
    double max_aspect_ratio = 20.0;         ///< refuse collapses making a face thinner than this; 0: off
    bool no_crossings = true;               ///< see DecimateStats::restarts
    std::function<void(double)> progress;
};

struct DecimateStats {
    std::size_t faces_before = 0, faces_after = 0;
    std::size_t collapses = 0;
    std::size_t locked_vertices = 0; ///< on a boundary or non-manifold edge, kept as they are
    double max_error = 0;            ///< quadric: largest sqrt(quadric error) of a collapse made
    /// With `no_crossings`: the result is checked for faces crossing each other; where
    /// some do, the reduction runs again from the input with the input vertices in those
    /// faces' boxes kept (frozen), until none is left. Restarts made, vertices frozen,
    /// and the crossing pairs left (only when the input had its own, or after 6 restarts).
    std::size_t restarts = 0, frozen_vertices = 0, crossings_left = 0;
};

/// @brief The paper's reduction: least important vertex first, importance
/// I(V) = arccos(<N_a, N_b>) * sum_j ||V_j - V||, each removed by a collapse into the
/// neighbour that keeps the face normals best. Per-vertex attributes of surviving
/// vertices are kept; normals are recomputed when present.
DecimateStats reduce_mesh(Mesh& mesh, const ReduceOptions& opt);
/// The same into `out`, leaving `input` as it is (one copy fewer for a caller that keeps it).
DecimateStats reduce_mesh(const Mesh& input, Mesh& out, const ReduceOptions& opt);

/// @brief Garland-Heckbert quadric decimation (half-edge collapses, so surviving
/// vertices keep their positions and attributes).
DecimateStats quadric_decimate(Mesh& mesh, const QuadricOptions& opt);
/// The same into `out`, leaving `input` as it is.
DecimateStats quadric_decimate(const Mesh& input, Mesh& out, const QuadricOptions& opt);

} // namespace cm
