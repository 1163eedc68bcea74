// What mesh.reduce and mesh.quadric_decimate share: the face-target parameters
// and turning them into a face count.
#pragma once
#include <cstddef>
#include <vector>

#include "core/params.h"

namespace cm {

/// `target_faces` and `target_ratio` (0: unset).
std::vector<ParamSpec> face_target_params(double default_ratio);
/// Throws cm::Error when both are given.
void check_face_target(const ParamSet& p);
/// The face count to stop at for a mesh of `faces` faces; 0 when no target is set.
std::size_t face_target(const ParamSet& p, std::size_t faces);

} // namespace cm
