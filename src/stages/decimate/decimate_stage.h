// What mesh.reduce and mesh.quadric_decimate share: the face-target parameters and turning
// them into a face count.
#pragma once
#include <cstddef>
#include <cstdint>

#include "core/params.h"

namespace cm {

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

} // namespace cm
