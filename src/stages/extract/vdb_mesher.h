// OpenVDB's mesher (tools::volumeToMesh) on a level set made from the hull: the
// reference extractor that TDs who use OpenVDB already know.
#pragma once
#include <cstddef>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace cm {

/// The parameters of extract.vdb_volume_to_mesh.
struct VdbMesherOptions {
    /// volumeToMesh's adaptivity in [0, 1]: 0 keeps one quad per crossed edge, larger
    /// merges flat regions into larger polygons.
    double adaptivity;
    /// Level of the surface in world units: 0 is the hull, > 0 grows it, < 0 shrinks it.
    double isovalue;
    /// Use the volume's exact crossings for the level set (else each crossing sits at the
    /// middle of its edge).
    bool use_crossings;
    /// volumeToMesh's relaxDisorientedTriangles.
    bool relax;

    VdbMesherOptions() { set_declared_defaults(*this); }
    /// `adaptivity`, `isovalue`, `crossings` and `relax`.
    void declare(ParamBinder& b);
};

struct VdbMesherStats {
    std::size_t quads = 0;           ///< polygons volumeToMesh gave as quads (split into two triangles)
    std::size_t triangles = 0;       ///< polygons it gave as triangles
    std::size_t band_voxels = 0;     ///< voxels of the level set near the surface
    std::size_t level_set_bytes = 0; ///< memory of the level set
    bool refined = false;            ///< the level set was made from the volume's crossings

    /// The figures of extract.vdb_volume_to_mesh.
    void report(Metrics& m) const;
};

/// @brief The level set of the hull: a float grid on the occupancy's transform, negative
/// inside, whose values at the grid points next to the surface are the distances (world
/// units) to the nearest crossing on their edges, so that linear interpolation along an
/// edge puts the zero at the crossing. Solid interior stays as tiles.
/// @throw cm::Error when the occupancy is missing.
openvdb::FloatGrid::Ptr hull_level_set(const Volume& vol, bool use_crossings);

/// @brief volumeToMesh on hull_level_set(): triangles (quads split along the shorter
/// diagonal), oriented outward, in world space. Reports 0.05 as it starts (OpenVDB's mesher
/// reports nothing).
/// @throw cm::Error when the occupancy is missing or the surface is empty.
Result<Mesh, VdbMesherStats> vdb_volume_to_mesh(const Volume& vol, const VdbMesherOptions& opt = {},
                                                Progress progress = {});

} // namespace cm
