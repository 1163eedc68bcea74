// What mesh.reduce and mesh.quadric_decimate share: the face-target parameters,
// turning them into a face count, and reporting what a decimation did.
#pragma once
#include <cstddef>
#include <vector>

#include "core/params.h"

namespace cm {

class Context;
struct Mesh;
struct DecimateStats;

/// `target_faces` and `target_ratio` (0: unset).
std::vector<ParamSpec> face_target_params(double default_ratio);
/// `guard`: keep the result free of crossing faces (DecimateStats::restarts).
ParamSpec crossing_guard_param();
/// Throws cm::Error when both are given.
void check_face_target(const ParamSet& p);
/// The face count to stop at for a mesh of `faces` faces; 0 when no target is set.
std::size_t face_target(const ParamSet& p, std::size_t faces);
/// Face counts, ratio, collapses and the crossing guard's figures into the run report; a
/// warning for locked vertices and for crossings left.
void report_decimation(Context& ctx, const DecimateStats& st, const Mesh& out);

} // namespace cm
