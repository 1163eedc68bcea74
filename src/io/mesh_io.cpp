#include "io/mesh_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

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

// Triangles a text .obj or .off file declares (an n-gon counts n - 2), so faces the reader
// could not take are not dropped in silence; -1 for other formats or an unreadable count.
long long declared_triangles(const fs::path& file) {
    const std::string ext = lower_extension(file);
    if (ext != ".obj" && ext != ".off") return -1;
    std::ifstream in(file);
    if (!in) return -1;
    long long total = 0;
    std::string line;
    if (ext == ".obj") {
        while (std::getline(in, line)) {
            if (line.size() < 2 || line[0] != 'f' || (line[1] != ' ' && line[1] != '\t')) continue;
            std::istringstream ss(line.substr(1));
            std::string tok;
            long long n = 0;
            while (ss >> tok) ++n;
            if (n >= 3) total += n - 2;
        }
        return total;
    }
    // OFF: "OFF" then "nv nf ne" (comments and blank lines aside), nv vertex lines, nf faces.
    long long nv = -1, nf = -1, seen = 0;
    while (std::getline(in, line)) {
        if (const auto c = line.find('#'); c != std::string::npos) line.erase(c);
        std::istringstream ss(line);
        if (nv < 0) {
            std::string first;
            if (!(ss >> first)) continue;
            if (first.find("OFF") != std::string::npos) {
                if (!(ss >> nv)) nv = -1;
                else if (!(ss >> nf)) return -1;
                continue;
            }
            std::istringstream again(line);
            if (!(again >> nv >> nf)) return -1;
            continue;
        }
        if (nf < 0) {
            if (!(ss >> nf)) continue;
            continue;
        }
        long long n = 0;
        if (!(ss >> n)) continue;
        if (seen++ < nv) continue;
        if (n >= 3) total += n - 2;
    }
    return total;
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
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw Error("cannot read mesh \"" + file.string() + "\": vertex " + std::to_string(v.idx() + 1) +
                        " has a coordinate that is not a finite number");
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
    // The reader leaves out a face whose index is out of range: say so rather than check a
    // different mesh. (An edge of more than two faces it keeps, on copies of its vertices, so
    // the check reports it as boundary edges.)
    if (const long long declared = declared_triangles(file); declared > 0 && declared > (long long)(om.n_faces()))
        throw Error("cannot read mesh \"" + file.string() + "\": " +
                    std::to_string(declared - (long long)om.n_faces()) + " of its " + std::to_string(declared) +
                    " triangles cannot be read (a vertex index out of range, or a face repeated)");
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
