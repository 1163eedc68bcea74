// The mesh check every extractor runs on its output and reports (run-report figures and a
// warning when the mesh fails).
#pragma once
#include "core/mesh.h"
#include "core/params.h"
#include "core/stage.h"
#include "geometry/mesh_check.h"

namespace cm {

/// When to run the check: on, off, or auto (meshes up to kAutoCheckFaces faces).
enum class MeshCheckMode { Auto, On, Off };
constexpr std::size_t kAutoCheckFaces = 5'000'000;

/// Declares the `check` parameter bound to `mode`.
void declare_check(ParamBinder& b, MeshCheckMode& mode);

/// Runs check_mesh() when `mode` asks for it and reports its counts as metrics of `ctx`;
/// a mesh that is not closed, manifold and outward is a warning naming the counts.
void report_mesh_check(const Mesh& mesh, MeshCheckMode mode, Context& ctx);

} // namespace cm
