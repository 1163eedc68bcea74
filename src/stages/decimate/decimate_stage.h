// What mesh.reduce and mesh.quadric_decimate share: the face-target parameters,
// turning them into a face count, and reporting what a decimation did.
#pragma once
#include <cstddef>
#include <cstdint>

#include "core/params.h"

namespace cm {

class Context;
struct Mesh;
struct DecimateStats;

/// `target_faces` and `target_ratio` (0: unset), bound together.
struct FaceTarget {
    Param<std::int64_t> faces;
    Param<double> ratio;

    void declare(ParamBinder& b, double default_ratio);
    /// Throws cm::Error when both are given.
    void check() const;
    /// The face count to stop at for a mesh of `input_faces` faces; 0 when no target is set.
    std::size_t count(std::size_t input_faces) const;
};

/// `guard`: keep the result free of crossing faces (DecimateStats::restarts).
ParamSpec crossing_guard_param();
/// Face counts, ratio, collapses and the crossing guard's figures into the run report; a
/// warning for locked vertices and for crossings left.
void report_decimation(Context& ctx, const DecimateStats& st, const Mesh& out);

} // namespace cm
