// mesh.write: writes the mesh to OBJ, PLY, STL, OFF or glTF binary (format from
// the extension), under a temporary name that the host renames when the run succeeds.
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/stage.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"

namespace cm {
namespace {

// The output rules, measured on what is written; broken rules become one warning.
void report_check(const Mesh& m, const std::filesystem::path& path, Context& ctx) {
    const OutputCheck check = check_output(m);
    const MeshCheck& c = check.mesh;
    ctx.metric("boundary_edges", double(c.boundary_edges));
    ctx.metric("nonmanifold_edges", double(c.nonmanifold_edges + c.nonmanifold_vertices));
    ctx.metric("degenerate_faces", double(c.degenerate_faces));
    ctx.metric("self_intersections", double(check.crossings.size()));
    ctx.metric("volume", c.signed_volume);
    const std::vector<std::string> broken = check.broken();
    if (broken.empty()) return;
    std::string text = "\"" + path.string() + "\" is not a clean closed mesh: ";
    for (std::size_t i = 0; i < broken.size(); ++i) text += (i ? ", " : "") + broken[i];
    ctx.warn(text);
}

class MeshWrite : public Stage {
    std::filesystem::path path_;
    MeshWriteOptions opt_;
    bool check_ = true;

public:
    StageSignature signature() const override {
        return {"mesh.write",
                "Write the mesh to a file: .obj, .ply, .stl, .off or .glb (format from the extension)",
                {{"mesh", DataKind::Mesh, "the mesh to write"}},
                DataKind::File};
    }
    void declare(ParamBinder& b) override {
        b.add(path_, ParamSpec::OutputPath("path", mesh_extensions(), "output file; its extension picks the format"));
        b.add(opt_.binary, ParamSpec::Bool("binary", true, "binary PLY/STL (smaller, faster); ASCII when false"));
        b.add(opt_.normals, ParamSpec::Bool("normals", true, "write per-vertex normals where the format holds them"));
        b.add(check_, ParamSpec::Bool("check", true,
                                      "check the mesh first (closed, 2-manifold, outward, no degenerate faces, no "
                                      "self-intersections): figures in the run report, a warning when a rule is "
                                      "broken"));
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; nothing to write");
        MeshWriteOptions opt = opt_;
        opt.name = path_.stem().string(); // not the temporary file's name
        Mesh with_normals;
        const Mesh* m = mesh.get();
        if (opt.normals && mesh->normals.size() != mesh->positions.size()) {
            with_normals = *mesh;
            with_normals.compute_normals();
            m = &with_normals;
        }
        const auto tmp = ctx.output_file(path_);
        write_mesh(*m, tmp, opt);
        ctx.metric("faces", double(m->face_count()));
        ctx.metric("vertices", double(m->vertex_count()));
        ctx.metric("path", path_.string());
        ctx.metric("bytes", double(std::filesystem::file_size(tmp)));
        if (check_) report_check(*m, path_, ctx);
        auto out = std::make_shared<FileOutput>();
        out->paths.push_back(path_);
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_mesh_write() { return new MeshWrite; }

} // namespace cm
