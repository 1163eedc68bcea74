// mesh.write: writes the mesh to OBJ, PLY, STL, OFF or glTF binary (format from
// the extension), under a temporary name that the host renames when the run succeeds.
// A textured mesh brings its material library and texture along with an OBJ (staged
// the same way); `height` or `unit_scale` sizes the model in the file (glTF and Blender
// read one unit as one metre).
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"

namespace cm {
namespace {

// The output rules, measured on what is written; broken rules become one warning.
void report_check(const Mesh& m, const std::filesystem::path& path, Context& ctx) {
    const OutputCheck check = check_output(m, [&ctx](double f) { ctx.progress(0.6 + 0.4 * f, "checking"); });
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
    double height_ = 0, unit_scale_ = 1;

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
        b.add(height_, ParamSpec::Float("height", 0, 0, 1e9, "m",
                                        "scale the model to this height (Y extent) in the file; 0: keep its size "
                                        "(the views' real size when the manifest gives one, else one unit per "
                                        "pixel of the first view)"));
        b.add(unit_scale_, ParamSpec::Float("unit_scale", 1, 1e-9, 1e9, "",
                                            "multiply every coordinate by this (e.g. 0.01: centimetre units to "
                                            "metres); not with height"));
    }
    void check() override {
        if (height_ > 0 && unit_scale_ != 1) throw Error("height and unit_scale both size the model; give one");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; nothing to write");
        MeshWriteOptions opt = opt_;
        opt.name = path_.stem().string(); // not the temporary file's name
        Mesh changed;
        const Mesh* m = mesh.get();
        double scale = unit_scale_;
        if (height_ > 0) {
            Vec3f lo, hi;
            mesh->bounds(lo, hi);
            if (!(hi.y > lo.y)) throw Error("the mesh has no height to scale to " + std::to_string(height_) + " m");
            scale = height_ / double(hi.y - lo.y);
        }
        if (scale != 1 || (opt.normals && mesh->normals.size() != mesh->positions.size())) {
            changed = *mesh;
            for (auto& p : changed.positions) p = Vec3f(Vec3d(p) * scale);
            if (opt.normals && changed.normals.size() != changed.positions.size()) changed.compute_normals();
            m = &changed;
        }
        auto out = std::make_shared<FileOutput>();
        const bool textured_obj = lower_extension(path_) == ".obj" && obj_has_material(*m);
        if (textured_obj) {
            const auto mtl = obj_material_path(path_), tex = obj_texture_path(path_);
            opt.mtl_file = ctx.output_file(mtl);
            opt.texture_file = ctx.output_file(tex);
            opt.mtl_name = mtl.filename().string();
            opt.texture_name = tex.filename().string();
        }
        const auto tmp = ctx.output_file(path_);
        // Writing is about the first 60 % of the time (the check the rest); both look for a
        // stop per chunk.
        const double writing = check_ ? 0.6 : 1.0;
        opt.progress = [&ctx, writing](double f) { ctx.progress(writing * f, "writing"); };
        write_mesh(*m, tmp, opt);
        if (scale != 1) ctx.metric("scale", scale);
        Vec3f lo, hi;
        m->bounds(lo, hi);
        ctx.metric("height", double(hi.y - lo.y));
        ctx.metric("faces", double(m->face_count()));
        ctx.metric("vertices", double(m->vertex_count()));
        ctx.metric("path", path_.string());
        ctx.metric("bytes", double(std::filesystem::file_size(tmp)));
        if (check_) report_check(*m, path_, ctx);
        out->paths.push_back(path_);
        if (textured_obj) {
            out->paths.push_back(obj_material_path(path_));
            out->paths.push_back(obj_texture_path(path_));
        }
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_mesh_write() { return new MeshWrite; }

} // namespace cm
