// volume.write: writes the hull as an OpenVDB narrow-band level set (.vdb) that
// Houdini, Blender and any OpenVDB tool open: a float grid of signed distance in
// world units (negative inside), class GRID_LEVEL_SET, on the volume's transform.
//
// Two sources for the distance:
//  - the occupancy alone (default): openvdb::tools::topologyToLevelSet turns the
//    active voxels into a level set; the surface follows voxel faces, softened by a
//    few smoothing steps (the voxel staircase stays visible up close);
//  - with the optional `mesh` input (the Marching Cubes surface, which sits on the
//    exact crossings): openvdb::tools::meshToLevelSet at the volume's voxel size,
//    so the level set keeps the sub-voxel surface.
#include <filesystem>
#include <memory>
#include <sstream>

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/TopologyToLevelSet.h>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"

namespace cm {
namespace {

class VolumeWrite : public Stage {
    std::filesystem::path path_;
    std::string grid_name_;
    int half_width_ = 3, smoothing_steps_ = 2;
    bool occupancy_ = false;

public:
    StageSignature signature() const override {
        return {"volume.write",
                "Write the hull as an OpenVDB level set (.vdb) for Houdini, Blender and other OpenVDB tools",
                {{"volume", DataKind::Volume, "the hull (its occupancy and transform)"},
                 {"mesh", DataKind::Mesh,
                  "optional surface of the hull (e.g. the Marching Cubes mesh): the level set follows it "
                  "with sub-voxel accuracy instead of the voxel faces",
                  true}},
                DataKind::File};
    }
    void declare(ParamBinder& b) override {
        b.add(path_, ParamSpec::OutputPath("path", {".vdb"}, "output .vdb file"));
        b.add(grid_name_,
              ParamSpec::String("grid_name", std::string("surface"), "name of the level-set grid in the file"));
        b.add(half_width_, ParamSpec::Int("half_width", 3, 1, 64, "voxels", "narrow band half width"));
        b.add(smoothing_steps_,
              ParamSpec::Int("smoothing_steps", 2, 0, 64, "",
                             "occupancy source: smoothing passes over the level set (softens the voxel staircase)"));
        b.add(occupancy_, ParamSpec::Bool("occupancy", false, "also write the occupancy grid (bool) as \"occupancy\""));
    }
    void check() override {
        if (grid_name_.empty()) throw Error("grid_name must not be empty");
    }
    Data run(const Inputs& in, Context& ctx) override {
        openvdb::initialize();
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        const int half_width = half_width_;
        openvdb::FloatGrid::Ptr sdf;
        if (in.has("mesh")) {
            auto mesh = in.get<Mesh>("mesh");
            if (mesh->triangles.empty()) throw Error("the mesh input is empty");
            ctx.progress(0.1, "mesh to level set");
            const auto& xf = vol->transform();
            std::vector<openvdb::Vec3s> pts(mesh->positions.size());
            for (std::size_t i = 0; i < pts.size(); ++i) {
                const auto& p = mesh->positions[i];
                pts[i] = openvdb::Vec3s(xf.worldToIndex(openvdb::Vec3d(p.x, p.y, p.z)));
            }
            std::vector<openvdb::Vec3I> tris(mesh->triangles.size());
            for (std::size_t f = 0; f < tris.size(); ++f)
                tris[f] = openvdb::Vec3I(mesh->triangles[f][0], mesh->triangles[f][1], mesh->triangles[f][2]);
            std::vector<openvdb::Vec4I> quads;
            sdf = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
                ctx.interrupter(),
                openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I>(pts, tris), xf,
                float(half_width), float(half_width));
            ctx.metric("source", "mesh");
        } else {
            ctx.progress(0.1, "occupancy to level set");
            sdf = openvdb::tools::topologyToLevelSet(*vol->occupancy, half_width, 0, 0, smoothing_steps_,
                                                     &ctx.interrupter());
            ctx.metric("source", "occupancy");
        }
        ctx.check_cancel();
        if (!sdf || sdf->activeVoxelCount() == 0) throw Error("the level set is empty (the volume has no inside)");
        sdf->setGridClass(openvdb::GRID_LEVEL_SET);
        sdf->setName(grid_name_);
        sdf->insertMeta("creator", openvdb::StringMetadata("conceptmesh volume.write"));
        openvdb::GridPtrVec grids{sdf};
        if (occupancy_) {
            auto occ = vol->occupancy->deepCopy();
            occ->setName("occupancy");
            grids.push_back(occ);
        }
        ctx.progress(0.8, "writing");
        const auto tmp = ctx.output_file(path_);
        openvdb::io::File file(tmp.string());
        file.setCompression(openvdb::io::COMPRESS_BLOSC);
        file.write(grids);
        file.close();
        ctx.metric("path", path_.string());
        ctx.metric("active_voxels", double(sdf->activeVoxelCount()));
        ctx.metric("voxel_size", sdf->voxelSize()[0]);
        ctx.metric("bytes", double(std::filesystem::file_size(tmp)));
        auto out = std::make_shared<FileOutput>();
        out->paths.push_back(path_);
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_volume_write() { return new VolumeWrite; }

} // namespace cm
