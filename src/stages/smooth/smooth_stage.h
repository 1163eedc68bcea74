// What mesh.laplacian_smooth and mesh.taubin_smooth share: the hull-constraint
// parameters and ports, and the run (copy the mesh, build the hull distance when
// asked, smooth, report). Each stage adds its own step parameters.
#pragma once
#include <vector>

#include "mesh_smooth.h"
#include "core/stage.h"

namespace cm {

/// `iterations`, `constrain` (none|hull) and `tolerance` (px of the finest view).
std::vector<ParamSpec> smooth_common_params(std::int64_t default_iterations);
/// The ports: `mesh` and the optional `views` the hull constraint needs.
std::vector<PortSpec> smooth_ports();
/// Throws cm::Error when `constrain: hull` is asked and the views input is not connected.
Data run_smooth_stage(const Inputs& in, Context& ctx, const ParamSet& params, SmoothOptions opt);

} // namespace cm
