// Umbrella-operator smoothing of triangle meshes: the paper's Laplacian relaxation
// and Taubin's lambda|mu smoothing, with an optional constraint that keeps every
// vertex within a tolerance of the visual hull. Jacobi updates on flat arrays
// (CSR one-rings), TBB-parallel over vertices.
#pragma once
#include <cstddef>
#include <functional>

#include "core/mesh.h"

namespace cm {

class HullDistance;

struct SmoothOptions {
    enum class Method { Laplacian, Taubin };
    Method method = Method::Laplacian;
    int iterations = 10;  ///< Taubin: one iteration is one lambda step and one mu step
    double factor = 1.0;  ///< Laplacian step: V' = V + factor * (mean of neighbours - V)
    double lambda = 0.63; ///< Taubin shrinking step (> 0)
    double mu = -0.67;    ///< Taubin inflating step (< -lambda)
    /// When set, each vertex stays within `tolerance` (world units) of the hull: a step
    /// that would leave the band is shortened by bisection along its direction.
    const HullDistance* hull = nullptr;
    double tolerance = 0.0;
    /// With `hull`: only the vertices that start within `tolerance` of the hull are kept
    /// within it; the others (a surface carved inside the hull, hull.plausible) move
    /// freely as long as they stay inside it (within `tolerance`).
    bool inside_free = false;
    /// With `hull`: a view that sees a vertex far inside its silhouette is not asked again
    /// until the vertex may have come near enough for its answer to matter (the same result
    /// either way, about a third of the samples with three views; false asks every view at
    /// every step).
    bool skip_far_views = true;
    /// Keep the surface valid: after smoothing, vertices of faces that cross another face,
    /// turn over (normal against the input's) or collapse to zero area are moved back
    /// towards their input positions (half the way, a quarter, then all the way) until no
    /// such face is left. The input must be free of them itself.
    bool guard = true;
    /// Called after each iteration with the fraction done; may throw to cancel.
    std::function<void(double)> progress;
};

struct SmoothStats {
    std::size_t clamped_steps = 0;  ///< vertex steps shortened by the hull constraint
    std::size_t skipping_steps = 0; ///< vertex steps that did not ask every view (skip_far_views)
    double max_hull_distance = 0;   ///< largest |hull distance| of a vertex at the end (constrained runs)
    std::size_t bad_faces = 0;      ///< guard: faces crossing, turned over or collapsed after smoothing
    std::size_t coincident = 0;     ///< guard: vertices drawn onto another vertex by smoothing
    std::size_t pulled_back = 0;    ///< guard: vertices moved back towards their input positions
    std::size_t guard_rounds = 0;   ///< guard: checks run (the first covers every face)
    std::size_t unresolved = 0;     ///< guard: bad faces left (only when the input had them)
};

/// @brief Smooths `mesh` in place (positions; normals are recomputed when present).
/// Vertices without neighbours do not move.
SmoothStats smooth_mesh(Mesh& mesh, const SmoothOptions& opt);
/// @brief The same from `in` into `out` (the rest of `in` copied as it is), without a copy
/// of the input positions beside the ones being smoothed.
SmoothStats smooth_mesh(const Mesh& in, Mesh& out, const SmoothOptions& opt);

} // namespace cm
