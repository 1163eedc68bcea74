// mesh.write: writes the mesh to OBJ, PLY, STL, OFF, glTF binary or USD (format from the
// extension), under a temporary name that the host renames when the run succeeds.
// A textured mesh brings its material library and texture along with an OBJ, and its
// texture with a .usda (staged the same way); `height` or `unit_scale` sizes the model in
// the file (glTF, USD and Blender read one unit as one metre).
#include <filesystem>
#include <memory>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "mesh_file.h"

namespace cm {
namespace {

class MeshWrite : public Stage {
    std::filesystem::path path_;
    MeshFileOptions opt_;

public:
    StageSignature signature() const override {
        return {"mesh.write",
                "Write the mesh to a file: .obj, .ply, .stl, .off, .glb, .usda or .usdz (format from the "
                "extension)",
                {{"mesh", DataKind::Mesh, "the mesh to write"}},
                DataKind::File};
    }
    void declare(ParamBinder& b) override {
        b.add(path_, ParamSpec::OutputPath("path", mesh_extensions(), "output file; its extension picks the format"));
        opt_.declare(b);
    }
    void check() override {
        if (opt_.height > 0 && opt_.unit_scale != 1) throw Error("height and unit_scale both size the model; give one");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; nothing to write");
        MeshFile file(*mesh, opt_);
        MeshWriteOptions format = opt_.format;
        format.name = path_.stem().string(); // not the temporary file's name
        auto out = std::make_shared<FileOutput>();
        out->paths.push_back(path_);
        // Files beside the mesh (an OBJ's material library and texture, a .usda's texture)
        // are staged with it, under their final names in what refers to them.
        const MeshSideFiles side = mesh_side_files(path_, file.mesh());
        if (!side.material.empty()) {
            format.mtl_file = ctx.output_file(side.material);
            format.mtl_name = side.material.filename().string();
            out->paths.push_back(side.material);
        }
        if (!side.texture.empty()) {
            format.texture_file = ctx.output_file(side.texture);
            format.texture_name = side.texture.filename().string();
            out->paths.push_back(side.texture);
        }
        // The check comes first (about the first 40 % of the time, the writing the rest; both
        // look for a stop per chunk): a mesh with degenerate or crossing faces is refused
        // before any byte of it is written.
        const double checking = opt_.check ? 0.4 : 0.0;
        if (opt_.check) file.check(ctx.progress("checking").part(0, checking));
        file.refuse_broken_faces(path_);
        file.write(ctx.output_file(path_), path_, format, ctx.progress("writing").part(checking, 1.0));
        file.stats().report(ctx);
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_mesh_write() { return new MeshWrite; }

} // namespace cm
