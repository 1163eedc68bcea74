#include "io/mesh_io.h"

#include <algorithm>
#include <cstring>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "core/data.h"
#include "core/error.h"
#include "io/gltf_io.h"

namespace fs = std::filesystem;

namespace cm {

namespace {
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// OpenMesh logs to stdout/stderr on its own ("[OBJWriter] : write file", reader
// complaints); conceptmesh reports its own one-line errors instead.
void quiet_openmesh() {
    static const bool done = [] {
        omlog().disable();
        omout().disable();
        omerr().disable();
        return true;
    }();
    (void)done;
}

} // namespace

const std::vector<std::string>& mesh_extensions() {
    static const std::vector<std::string> extensions = {".obj", ".ply", ".stl", ".off", ".glb"};
    return extensions;
}

bool mesh_format_supported(const fs::path& file) {
    const auto& known = mesh_extensions();
    return std::find(known.begin(), known.end(), lower_extension(file)) != known.end();
}

Mesh read_mesh(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("cannot read mesh \"" + file.string() + "\": no such file");
    if (!mesh_format_supported(file))
        throw Error("cannot read mesh \"" + file.string() + "\": unknown format (use .obj, .ply, .stl, .off or .glb)");
    if (lower_extension(file) == ".glb") return read_glb(file);
    quiet_openmesh();
    OMesh om;
    OpenMesh::IO::Options opt;
    if (!OpenMesh::IO::read_mesh(om, file.string(), opt))
        throw Error("cannot read mesh \"" + file.string() + "\": the file is not a valid mesh");
    Mesh m;
    m.positions.reserve(om.n_vertices());
    for (auto v : om.vertices()) {
        const auto& p = om.point(v);
        m.positions.emplace_back(p[0], p[1], p[2]);
    }
    m.triangles.reserve(om.n_faces());
    for (auto f : om.faces()) {
        std::uint32_t idx[3];
        int k = 0;
        for (auto v : om.fv_range(f)) {
            if (k < 3) idx[k] = std::uint32_t(v.idx());
            ++k;
        }
        if (k == 3) m.triangles.push_back({idx[0], idx[1], idx[2]});
    }
    if (m.triangles.empty()) throw Error("cannot read mesh \"" + file.string() + "\": it has no faces");
    return m;
}

void write_mesh(const Mesh& mesh, const fs::path& file, const MeshWriteOptions& wo) {
    if (!mesh_format_supported(file))
        throw Error("cannot write mesh \"" + file.string() + "\": unknown format (use .obj, .ply, .stl, .off or .glb)");
    if (lower_extension(file) == ".glb") {
        if (mesh.triangles.empty()) throw Error("cannot write mesh \"" + file.string() + "\": the mesh is empty");
        return write_glb(mesh, file, wo.normals, wo.name);
    }
    quiet_openmesh();
    OMesh om;
    om.reserve(mesh.positions.size(), mesh.triangles.size() * 3 / 2, mesh.triangles.size());
    for (const auto& p : mesh.positions) om.add_vertex(OMesh::Point(p.x, p.y, p.z));
    const bool with_normals =
        wo.normals && mesh.normals.size() == mesh.positions.size() && lower_extension(file) != ".stl";
    if (with_normals) {
        om.request_vertex_normals();
        for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
            const auto& n = mesh.normals[i];
            om.set_normal(OMesh::VertexHandle(int(i)), OMesh::Normal(n.x, n.y, n.z));
        }
    }
    std::vector<OMesh::VertexHandle> vh(3);
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) vh[k] = OMesh::VertexHandle(int(t[k]));
        if (!om.add_face(vh).is_valid())
            throw Error("cannot write mesh \"" + file.string() +
                        "\": the mesh is not 2-manifold (OpenMesh refused a face)");
    }
    OpenMesh::IO::Options opt;
    if (with_normals) opt += OpenMesh::IO::Options::VertexNormal;
    const std::string e = lower_extension(file);
    if (wo.binary && (e == ".ply" || e == ".stl")) opt += OpenMesh::IO::Options::Binary;
    if (e == ".stl") {
        om.request_face_normals();
        om.update_face_normals();
        opt += OpenMesh::IO::Options::FaceNormal;
    }
    if (!OpenMesh::IO::write_mesh(om, file.string(), opt, 9))
        throw Error("cannot write mesh \"" + file.string() + "\": " + std::strerror(errno));
}

} // namespace cm
