// volume.write's algorithm: the hull as an OpenVDB narrow-band level set (a float grid of
// signed distance in world units, negative inside, class GRID_LEVEL_SET, on the volume's
// transform) that Houdini, Blender and any OpenVDB tool open. OpenVDB's tools do the work
// and look at the node's Interrupter as they go.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include <openvdb/openvdb.h>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace cm {

/// The parameters of volume.write beside its path.
struct VolumeWriteOptions {
    std::string grid_name; ///< the level-set grid's name in the file
    int half_width;        ///< narrow band half width, in voxels
    int smoothing_steps;   ///< occupancy source: smoothing passes over the level set
    bool occupancy;        ///< also write the occupancy grid (bool) as "occupancy"

    VolumeWriteOptions() { set_declared_defaults(*this); }
    /// `grid_name`, `half_width`, `smoothing_steps` and `occupancy`.
    void declare(ParamBinder& b);
};

struct VolumeWriteStats {
    std::string source;              ///< what the level set follows: "mesh" or "occupancy"
    std::string path;                ///< the name the file goes by
    std::uint64_t active_voxels = 0; ///< of the level set
    double voxel_size = 0;
    std::uintmax_t bytes = 0; ///< the file's size
    /// source, path, active_voxels, voxel_size and bytes.
    void report(Metrics& m) const;
};

/// @brief The grids volume.write writes: the level set of the hull `vol` and, with
/// `opt.occupancy`, a copy of its occupancy. Two sources for the distance:
///  - the occupancy alone (`surface` null): openvdb::tools::topologyToLevelSet turns the
///    active voxels into a level set; the surface follows voxel faces, softened by
///    `opt.smoothing_steps` smoothing steps (the voxel staircase stays visible up close);
///  - `surface` (the Marching Cubes surface, which sits on the exact crossings):
///    openvdb::tools::meshToLevelSet at the volume's voxel size, so the level set keeps the
///    sub-voxel surface.
/// OpenVDB's tools look at `interrupter` (Context::interrupter()); a stop asked for meanwhile
/// is taken when they return. The stats hold the source and the level set's figures.
/// @throw cm::Cancelled; cm::Error for a volume without occupancy or an empty level set.
Result<openvdb::GridPtrVec, VolumeWriteStats> hull_grids(const Volume& vol, const Mesh* surface,
                                                         const VolumeWriteOptions& opt, Interrupter& interrupter);

/// Writes `grids` to the .vdb `file` (Blosc compression); returns the file's size in bytes.
std::uintmax_t write_grids(const openvdb::GridPtrVec& grids, const std::filesystem::path& file);

} // namespace cm
