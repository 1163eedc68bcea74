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

#include "core/algorithm.h"
#include "core/mesh.h"

namespace cm {

class OutlineGuard;

/// The parameters of mesh.reduce (all but the face target, which the stage turns into
/// `target_faces` for its input), and what the stage sets for a run.
struct ReduceOptions {
    enum class Constrain { None, Silhouette };
    /// A vertex is a candidate while the largest angle between the normals of its
    /// faces is under this (the paper: 5 to 40 degrees); a collapse may not turn a
    /// face by more than this either.
    double max_angle_deg;
    /// A vertex in the middle of a crease whose two edges continue each other within this
    /// (degrees) is a candidate too, and goes along the crease; 0: off (the paper).
    double crease_straightness_deg;
    /// With `crease_straightness_deg` over kHardCreaseStraightness: on a machined part (the
    /// views' hardness is 1, geometry/hard_surface.h) it is kHardCreaseStraightness. The stage
    /// reads the hardness from its views input.
    bool hard_surface;
    /// `crease_straightness_deg` on a machined part with `hard_surface` (pipelines/paper.yaml's).
    static constexpr double kHardCreaseStraightness = 2.0;
    /// A collapse may not give a face a normal further than this (degrees) from every normal
    /// the removed vertex's faces had: flat sides stay flat beside a crease, where a collapse
    /// would otherwise tilt them by up to max_angle_deg; 0: off (the paper).
    double keep_planes_deg;
    double max_aspect_ratio; ///< refuse collapses making a face thinner than this (1 = equilateral); 0: off
    bool no_crossings;       ///< see DecimateStats::restarts
    /// Silhouette: the stage guards the outline in each of its views (`outline`), within
    /// `tolerance_px` pixels of the drawn silhouette.
    Constrain constrain;
    double tolerance_px;
    std::size_t target_faces = 0; ///< stop at or below this many faces; 0: until no vertex can go. Not a parameter.
    /// Optional: collapses that would move an outline away from the drawn silhouettes are
    /// refused (outline_guard.h); it must outlive the call. Not a parameter.
    const OutlineGuard* outline = nullptr;

    ReduceOptions() { set_declared_defaults(*this); }
    /// Every parameter (the defaults); the stage declares its face target between the two parts.
    void declare(ParamBinder& b) {
        declare_angle(b);
        declare_limits(b);
    }
    /// `max_angle_deg`.
    void declare_angle(ParamBinder& b);
    /// `max_aspect_ratio`, `guard`, `constrain` and `tolerance`.
    void declare_limits(ParamBinder& b);
};

/// The parameters of mesh.quadric_decimate (all but the face target, which the stage turns
/// into `target_faces` for its input).
struct QuadricOptions {
    std::size_t target_faces = 0; ///< stop at or below this many faces; 0: no face target. Not a parameter.
    double max_error;             ///< stop when the cheapest collapse moves the surface more (world units); 0: no limit
    double max_normal_deviation_deg; ///< refuse collapses turning a face more than this
    double max_aspect_ratio;         ///< refuse collapses making a face thinner than this; 0: off
    bool no_crossings;               ///< see DecimateStats::restarts

    QuadricOptions() { set_declared_defaults(*this); }
    /// `max_error`, `max_normal_deviation_deg`, `max_aspect_ratio` and `guard`.
    void declare(ParamBinder& b);
};

struct DecimateStats {
    std::size_t faces_before = 0, faces_after = 0;
    std::size_t vertices = 0; ///< of the result
    std::size_t collapses = 0;
    std::size_t locked_vertices = 0; ///< on a boundary or non-manifold edge, kept as they are
    /// With `no_crossings`: the result is checked for faces crossing each other; where
    /// some do, the reduction runs again from the input with the input vertices in those
    /// faces' boxes kept (frozen), until none is left. Restarts made, vertices frozen,
    /// and the crossing pairs left (only when the input had its own, or after 6 restarts).
    std::size_t restarts = 0, frozen_vertices = 0, crossings_left = 0;

    /// Face counts, ratio, collapses and the crossing guard's figures; a warning for crossings
    /// left and for locked vertices.
    void report(Metrics& m) const;
};

struct QuadricStats : DecimateStats {
    double max_error = 0;         ///< largest sqrt(quadric error) of a collapse made
    std::size_t target_faces = 0; ///< the face target of the run (0: none)

    /// DecimateStats' figures and max_error; a warning when the run stopped above its target.
    void report(Metrics& m) const;
};

/// @brief The paper's reduction: least important vertex first, importance
/// I(V) = arccos(<N_a, N_b>) * sum_j ||V_j - V||, each removed by a collapse into the
/// neighbour that keeps the face normals best. Per-vertex attributes of surviving
/// vertices are kept; normals are recomputed when present.
Result<Mesh, DecimateStats> reduce_mesh(const Mesh& input, const ReduceOptions& opt, Progress progress = {});
/// The same in place.
DecimateStats reduce_mesh_in_place(Mesh& mesh, const ReduceOptions& opt, Progress progress = {});

/// @brief Garland-Heckbert quadric decimation (half-edge collapses, so surviving
/// vertices keep their positions and attributes).
Result<Mesh, QuadricStats> quadric_decimate(const Mesh& input, const QuadricOptions& opt, Progress progress = {});
/// The same in place.
QuadricStats quadric_decimate_in_place(Mesh& mesh, const QuadricOptions& opt, Progress progress = {});

} // namespace cm
