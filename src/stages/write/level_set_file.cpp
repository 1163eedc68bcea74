#include "level_set_file.h"

#include <vector>

#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/TopologyToLevelSet.h>

#include "core/error.h"
#include "core/params.h"

namespace cm {

void VolumeWriteOptions::declare(ParamBinder& b) {
    b.add(grid_name, ParamSpec::String("grid_name", std::string("surface"), "name of the level-set grid in the file"));
    b.add(half_width, ParamSpec::Int("half_width", 3, 1, 64, "voxels", "narrow band half width"));
    b.add(smoothing_steps,
          ParamSpec::Int("smoothing_steps", 2, 0, 64, "",
                         "occupancy source: smoothing passes over the level set (softens the voxel staircase)"));
    b.add(occupancy, ParamSpec::Bool("occupancy", false, "also write the occupancy grid (bool) as \"occupancy\""));
}

void VolumeWriteStats::report(Metrics& m) const {
    m.metric("source", source);
    m.metric("path", path);
    m.count("active_voxels", active_voxels);
    m.metric("voxel_size", voxel_size);
    m.metric("bytes", double(bytes));
}

namespace {

// The level set of `surface` at the volume's voxel size, on its transform.
openvdb::FloatGrid::Ptr surface_level_set(const Volume& vol, const Mesh& surface, int half_width,
                                          Interrupter& interrupter) {
    const auto& xf = vol.transform();
    std::vector<openvdb::Vec3s> pts(surface.positions.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& p = surface.positions[i];
        pts[i] = openvdb::Vec3s(xf.worldToIndex(openvdb::Vec3d(p.x, p.y, p.z)));
    }
    std::vector<openvdb::Vec3I> tris(surface.triangles.size());
    for (std::size_t f = 0; f < tris.size(); ++f)
        tris[f] = openvdb::Vec3I(surface.triangles[f][0], surface.triangles[f][1], surface.triangles[f][2]);
    return openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I>(pts, tris), xf,
        float(half_width), float(half_width));
}

} // namespace

Result<openvdb::GridPtrVec, VolumeWriteStats> hull_grids(const Volume& vol, const Mesh* surface,
                                                         const VolumeWriteOptions& opt, Interrupter& interrupter) {
    openvdb::initialize();
    if (!vol.occupancy) throw Error("the volume has no occupancy grid");
    Result<openvdb::GridPtrVec, VolumeWriteStats> r;
    VolumeWriteStats& stats = r.stats;
    openvdb::FloatGrid::Ptr sdf;
    if (surface) {
        sdf = surface_level_set(vol, *surface, opt.half_width, interrupter);
        stats.source = "mesh";
    } else {
        sdf =
            openvdb::tools::topologyToLevelSet(*vol.occupancy, opt.half_width, 0, 0, opt.smoothing_steps, &interrupter);
        stats.source = "occupancy";
    }
    interrupter.check();
    if (!sdf || sdf->activeVoxelCount() == 0) throw Error("the level set is empty (the volume has no inside)");
    sdf->setGridClass(openvdb::GRID_LEVEL_SET);
    sdf->setName(opt.grid_name);
    sdf->insertMeta("creator", openvdb::StringMetadata("conceptmesh volume.write"));
    stats.active_voxels = sdf->activeVoxelCount();
    stats.voxel_size = sdf->voxelSize()[0];
    r.value.push_back(sdf);
    if (opt.occupancy) {
        auto occ = vol.occupancy->deepCopy();
        occ->setName("occupancy");
        r.value.push_back(occ);
    }
    return r;
}

std::uintmax_t write_grids(const openvdb::GridPtrVec& grids, const std::filesystem::path& file) {
    openvdb::io::File out(file.string());
    out.setCompression(openvdb::io::COMPRESS_BLOSC);
    out.write(grids);
    out.close();
    return std::filesystem::file_size(file);
}

} // namespace cm
