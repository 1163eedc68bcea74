#include "mesh_file.h"

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "core/params.h"

namespace cm {

void MeshFileOptions::declare(ParamBinder& b) {
    format.declare(b);
    b.add(check, ParamSpec::Bool("check", true,
                                 "check the mesh first (closed, 2-manifold, outward, no degenerate faces, no "
                                 "self-intersections): figures in the run report; degenerate or crossing faces "
                                 "are an error and nothing is written, another broken rule a warning"));
    b.add(height, ParamSpec::Float("height", 0, 0, 1e9, "m",
                                   "scale the model to this height (Y extent) in the file; 0: keep its size "
                                   "(the views' real size when the manifest gives one, else one unit per "
                                   "pixel of the first view)"));
    b.add(unit_scale, ParamSpec::Float("unit_scale", 1, 1e-9, 1e9, "",
                                       "multiply every coordinate by this (e.g. 0.01: centimetre units to "
                                       "metres); not with height"));
}

void MeshFileStats::report(Metrics& m) const {
    if (scale != 1) m.metric("scale", scale);
    m.metric("height", height);
    m.count("faces", faces);
    m.count("vertices", vertices);
    m.metric("path", path);
    m.metric("bytes", double(bytes));
    if (caps.found) {
        m.count("flat_caps_flipped", caps.flipped);
        m.count("flat_caps_left", caps.left);
    }
    if (!check) return;
    // The output rules, measured on what is written; broken rules become one warning.
    const MeshCheck& c = check->mesh;
    m.count("boundary_edges", c.boundary_edges);
    m.count("nonmanifold_edges", c.nonmanifold_edges + c.nonmanifold_vertices);
    m.count("degenerate_faces", c.degenerate_faces);
    m.count("self_intersections", check->crossings.size());
    m.metric("volume", c.signed_volume);
    m.count("components", c.components);
    // A closed 2-manifold's tunnels: each component's Euler characteristic is 2 - 2 genus,
    // so the mesh's V - E + F = 2 components - 2 genus (genus summed over its components).
    if (c.closed_manifold()) m.count("genus", std::size_t(std::max(0L, 2 * long(c.components) - c.euler) / 2));
    const std::vector<std::string> broken = check->broken();
    if (broken.empty()) return;
    std::string text = "\"" + path + "\" is not a clean closed mesh: ";
    for (std::size_t i = 0; i < broken.size(); ++i) text += (i ? ", " : "") + broken[i];
    m.warn(text);
}

MeshFile::MeshFile(const Mesh& mesh, const MeshFileOptions& opt) : input_(mesh) {
    double scale = opt.unit_scale;
    if (opt.height > 0) {
        Vec3f lo, hi;
        mesh.bounds(lo, hi);
        if (!(hi.y > lo.y)) throw Error("the mesh has no height to scale to " + std::to_string(opt.height) + " m");
        scale = opt.height / double(hi.y - lo.y);
    }
    stats_.scale = scale;
    const bool normals = opt.format.normals;
    if (scale != 1 || (normals && mesh.normals.size() != mesh.positions.size())) {
        Mesh& changed = changed_.emplace(mesh);
        for (auto& p : changed.positions) p = Vec3f(Vec3d(p) * scale);
        if (normals && changed.normals.size() != changed.positions.size()) changed.compute_normals();
    }
    // Flat caps (a corner on the opposite edge, where a row of vertices lies on a straight
    // crease) are flipped away: sized to metres or rounded to the file's digits they would be
    // faces of no area, which importers and the check take for broken ones.
    std::vector<std::uint32_t> caps = find_flat_caps(this->mesh());
    if (!caps.empty()) stats_.caps = flip_flat_caps(changed_ ? *changed_ : changed_.emplace(mesh), std::move(caps));
}

void MeshFile::write(const std::filesystem::path& file, const std::filesystem::path& path,
                     const MeshWriteOptions& format, Progress progress) {
    const Mesh& m = mesh();
    write_mesh(m, file, format, progress);
    Vec3f lo, hi;
    m.bounds(lo, hi);
    stats_.height = double(hi.y - lo.y);
    stats_.faces = m.face_count();
    stats_.vertices = m.vertex_count();
    stats_.path = path.string();
    stats_.bytes = std::filesystem::file_size(file);
}

void MeshFile::check(Progress progress) { stats_.check = check_output(mesh(), progress); }

void MeshFile::refuse_broken_faces(const std::filesystem::path& path) const {
    if (!stats_.check) return;
    const std::size_t degenerate = stats_.check->mesh.degenerate_faces, crossing = stats_.check->crossings.size();
    if (degenerate == 0 && crossing == 0) return;
    std::string what;
    if (degenerate) what = std::to_string(degenerate) + " degenerate faces";
    if (crossing) what += (what.empty() ? "" : " and ") + std::to_string(crossing) + " pairs of crossing faces";
    throw Error("\"" + path.string() + "\" not written: the mesh has " + what +
                " (made by a stage before mesh.write; check: false writes it unchecked)");
}

} // namespace cm
