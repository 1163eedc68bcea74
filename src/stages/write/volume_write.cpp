// volume.write: writes the hull as an OpenVDB narrow-band level set (.vdb) that
// Houdini, Blender and any OpenVDB tool open: a float grid of signed distance in
// world units (negative inside), class GRID_LEVEL_SET, on the volume's transform.
//
// The level set follows the occupancy's voxel faces, or the optional mesh input's exact
// surface (level_set_file.h).
#include <filesystem>
#include <memory>

#include "core/stage.h"
#include "level_set_file.h"

namespace cm {
namespace {

class VolumeWrite : public Stage {
    std::filesystem::path path_; ///< the .vdb file, as the run names it (written under a temporary name)
    VolumeWriteOptions opt_;

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
        opt_.declare(b);
    }
    void check() override {
        if (opt_.grid_name.empty()) throw Error("grid_name must not be empty");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        std::shared_ptr<const Mesh> mesh;
        if (in.has("mesh")) {
            mesh = in.get<Mesh>("mesh");
            if (mesh->triangles.empty()) throw Error("the mesh input is empty");
        }
        ctx.progress(0.1, mesh ? "mesh to level set" : "occupancy to level set");
        auto [grids, stats] = hull_grids(*vol, mesh.get(), opt_, ctx.interrupter());
        ctx.progress(0.8, "writing");
        stats.bytes = write_grids(grids, ctx.output_file(path_));
        stats.path = path_.string();
        stats.report(ctx);
        return std::make_shared<const FileOutput>(FileOutput{{path_}});
    }
};

} // namespace

Stage* make_volume_write() { return new VolumeWrite; }

} // namespace cm
