// Umbrella-operator smoothing of triangle meshes: the paper's Laplacian relaxation
// and Taubin's lambda|mu smoothing, with an optional constraint that keeps every
// vertex within a tolerance of the visual hull. Jacobi updates on flat arrays
// (CSR one-rings), TBB-parallel over vertices; the guard (smooth_guard.h) then keeps
// the surface valid.
#pragma once
#include <cstddef>

#include <vector>

#include "core/algorithm.h"
#include "core/camera.h"
#include "core/mesh.h"

namespace cm {

class HullDistance;

/// The parameters of mesh.laplacian_smooth and mesh.taubin_smooth (declare_common() and each
/// method's own), and the method, which the stage sets.
struct SmoothOptions {
    enum class Method { Laplacian, Taubin };
    enum class Constrain { None, Hull, Inside };
    Method method = Method::Laplacian;
    int iterations; ///< Taubin: one iteration is one lambda step and one mu step
    double factor;  ///< Laplacian step: V' = V + factor * (mean of neighbours - V)
    double lambda;  ///< Taubin shrinking step (> 0)
    double mu;      ///< Taubin inflating step (< -lambda)
    /// Hull: each vertex stays within `tolerance_px` (pixels of the finest view) of the visual
    /// hull: a step that would leave the band is shortened by bisection along its direction.
    /// Inside: only the vertices that start within the tolerance of the hull are kept within
    /// it; the others (a surface carved inside the hull, hull.plausible) move freely as long
    /// as they stay inside it (within the tolerance). Both need the hull.
    Constrain constrain;
    double tolerance_px;
    /// Keep the surface valid: after smoothing, vertices of faces that cross another face,
    /// turn over (normal against the input's) or collapse to zero area are moved back
    /// towards their input positions (half the way, a quarter, then all the way) until no
    /// such face is left. The input must be free of them itself.
    bool guard;
    /// Hold sharp creases: a vertex on an edge whose two faces meet at more than this
    /// (degrees) smooths along its crease only (or stays, where creases end or meet), and a
    /// vertex beside one stays in its plane (smooth_creases.h); 0: off (the paper).
    double crease_angle_deg;
    /// With `crease_angle_deg`: hold only the creases that reach at least this many mean edge
    /// lengths of the input (a carved hull's short steps and facets are smoothed); 0: every
    /// crease.
    double crease_reach;
    /// With `crease_reach`: the views' cameras; a short crease's edges along a line of sight of
    /// one of them (an outline's corner swept along it) are held. The stage sets them from its
    /// views input. Not a parameter.
    std::vector<Camera> crease_views;
    /// With `crease_angle_deg`: on a machined part (the views' hardness is 1,
    /// geometry/hard_surface.h: hull.plausible keeps the hull whole) no crease is held, as in
    /// the paper. The stage reads the hardness from its views input.
    bool hard_surface;
    /// With a hull: a view that sees a vertex far inside its silhouette is not asked again
    /// until the vertex may have come near enough for its answer to matter (the same result
    /// either way, about a third of the samples with three views; false asks every view at
    /// every step). Not a parameter.
    bool skip_far_views = true;

    SmoothOptions() { set_declared_defaults(*this); }
    /// Every parameter (the defaults); a stage declares the common ones and its method's.
    void declare(ParamBinder& b) {
        declare_common(b);
        declare_laplacian(b);
        declare_taubin(b);
    }
    /// `iterations`, `constrain`, `tolerance`, `guard`, `creases`, `crease_reach` and `hard_surface`.
    void declare_common(ParamBinder& b);
    /// `factor`.
    void declare_laplacian(ParamBinder& b);
    /// `lambda` and `mu`.
    void declare_taubin(ParamBinder& b);
};

struct SmoothStats {
    std::size_t vertices = 0, faces = 0;
    double volume_before = 0, volume_after = 0; ///< enclosed volume of the input and the result
    bool constrained = false;                   ///< a hull constraint held the vertices
    double finest_pixel = 0;                    ///< of the hull's views (constrained runs)
    std::size_t clamped_steps = 0;              ///< vertex steps shortened by the hull constraint
    std::size_t skipping_steps = 0;             ///< vertex steps that did not ask every view (skip_far_views)
    double max_hull_distance = 0;               ///< largest |hull distance| of a vertex at the end (constrained runs)
    bool guarded = false;                       ///< the guard ran
    std::size_t bad_faces = 0;                  ///< guard: faces crossing, turned over or collapsed after smoothing
    std::size_t coincident = 0;                 ///< guard: vertices drawn onto another vertex by smoothing
    std::size_t pulled_back = 0;                ///< guard: vertices moved back towards their input positions
    std::size_t guard_rounds = 0;               ///< guard: checks run (the first covers every face)
    std::size_t unresolved = 0;                 ///< guard: bad faces left (only when the input had them)
    bool creases = false;                       ///< the crease hold ran
    std::size_t crease_vertices = 0;            ///< creases: vertices moving along their crease only
    std::size_t crease_held = 0;                ///< creases: vertices held (crease ends and meetings)
    std::size_t short_creases = 0;              ///< creases: short creases smoothed (crease_reach)
    /// Vertices, faces, the volume before and after and its change, the guard's figures (and a
    /// warning for faces it could not mend) and the constraint's (max_hull_distance_px).
    void report(Metrics& m) const;
};

/// @brief Smooths `in` (positions; normals recomputed when present; the rest copied as it is).
/// Vertices without neighbours do not move. `hull` is the visual hull of the views, which
/// `opt.constrain` Hull and Inside need. @throw cm::Error for a constraint without a hull;
/// cm::Cancelled from `progress` (called after each iteration).
Result<Mesh, SmoothStats> smooth_mesh(const Mesh& in, const SmoothOptions& opt, const HullDistance* hull = nullptr,
                                      Progress progress = {});
/// @brief The same, in place.
SmoothStats smooth_mesh_in_place(Mesh& mesh, const SmoothOptions& opt, const HullDistance* hull = nullptr,
                                 Progress progress = {});

} // namespace cm
