// What mesh.laplacian_smooth and mesh.taubin_smooth share: the ports and the run (the hull
// distance of the views when a constraint asks for it, smooth_mesh, its stats into the run).
#pragma once
#include <vector>

#include "core/stage.h"
#include "mesh_smooth.h"

namespace cm {

/// The ports: `mesh` and the optional `views` the hull constraint needs.
std::vector<PortSpec> smooth_ports();

/// Smooths the `mesh` input with `opt` (its method set by the stage). Throws cm::Error when
/// `constrain: hull` or `inside` is asked and the views input is not connected.
Data run_smooth(const Inputs& in, Context& ctx, const SmoothOptions& opt);

} // namespace cm
