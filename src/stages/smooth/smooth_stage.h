// What mesh.laplacian_smooth and mesh.taubin_smooth share: the hull-constraint
// parameters and ports, and the run (copy the mesh, build the hull distance when
// asked, smooth, report). Each stage adds its own step parameters.
#pragma once
#include <cstdint>
#include <vector>

#include "core/stage.h"
#include "mesh_smooth.h"

namespace cm {

/// `iterations`, `constrain` (none|hull|inside), `tolerance` (px of the finest view) and `guard`,
/// bound together, and the run both stages share.
struct SmoothCommon {
    enum class Constrain { None, Hull, Inside };
    int iterations = 0;
    Constrain constrain = Constrain::None;
    double tolerance_px = 0;
    bool guard = true;

    void declare(ParamBinder& b, std::int64_t default_iterations);
    /// Smooths a copy of the `mesh` input with `opt` (its method and step set by the stage).
    /// Throws cm::Error when `constrain: hull` or `inside` is asked and the views input is not connected.
    Data run(const Inputs& in, Context& ctx, SmoothOptions opt) const;
};

/// The ports: `mesh` and the optional `views` the hull constraint needs.
std::vector<PortSpec> smooth_ports();

} // namespace cm
