// OpenMesh's colour property (Vec3uc) trips GCC 12's -Wmaybe-uninitialized inside
// std::vector; a false positive in library code, silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "io/mesh_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "core/data.h"
#include "core/error.h"
#include "core/views.h"
#include "io/gltf_io.h"
#include "io/image_io.h"
#include "io/number_text.h"
#include "io/progress_stream.h"
#include "io/usd_io.h"

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

// A text .obj or .off checked line by line before OpenMesh reads it: OpenMesh leaves out a
// vertex it cannot parse ("nan") and a face with an index out of range, and says nothing.
// Throws cm::Error naming the file and the line.
void check_text_mesh(const fs::path& file) {
    const std::string ext = lower_extension(file);
    if (ext != ".obj" && ext != ".off") return;
    std::ifstream in(file);
    if (!in) return; // the reader says why
    auto fail = [&](long long line, const std::string& why) {
        throw Error("cannot read mesh \"" + file.string() + "\": line " + std::to_string(line) + ": " + why);
    };
    auto finite_numbers = [&](std::istringstream& ss, int n, long long line) {
        for (int k = 0; k < n; ++k) {
            std::string tok;
            if (!(ss >> tok)) fail(line, "a vertex needs 3 coordinates");
            char* end = nullptr;
            const double x = std::strtod(tok.c_str(), &end);
            if (end == tok.c_str() || *end != '\0') fail(line, "\"" + tok + "\" is not a number");
            if (!std::isfinite(x)) fail(line, "vertex coordinate \"" + tok + "\" is not a finite number");
        }
    };
    std::string line;
    long long ln = 0;
    if (ext == ".obj") {
        std::vector<std::pair<long long, std::string>> faces; // checked once every vertex is counted
        long long nv = 0;
        while (std::getline(in, line)) {
            ++ln;
            if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) continue;
            std::istringstream ss(line.substr(2));
            if (line[0] == 'v') {
                finite_numbers(ss, 3, ln);
                ++nv;
            } else if (line[0] == 'f') {
                faces.emplace_back(ln, line.substr(2));
            }
        }
        for (const auto& [fl, text] : faces) {
            std::istringstream ss(text);
            std::string tok;
            while (ss >> tok) {
                char* end = nullptr;
                const long long i = std::strtoll(tok.c_str(), &end, 10);
                if (end == tok.c_str()) fail(fl, "face index \"" + tok + "\" is not a number");
                const long long v = i < 0 ? nv + i + 1 : i; // negative: counted from the last vertex
                if (v < 1 || v > nv)
                    fail(fl, "face index " + std::to_string(i) + " is out of range (the file has " +
                                 std::to_string(nv) + " vertices)");
            }
        }
        return;
    }
    // OFF: "OFF", "nv nf ne", nv vertex lines, nf face lines "n i1 ... in" (0-based).
    long long nv = -1, nf = -1, seen = 0;
    while (std::getline(in, line)) {
        ++ln;
        if (const auto c = line.find('#'); c != std::string::npos) line.erase(c);
        std::istringstream ss(line);
        std::string first;
        if (!(ss >> first)) continue;
        if (nv < 0) {
            if (first.find("OFF") != std::string::npos) {
                if (!(ss >> nv)) nv = -1;
                else if (!(ss >> nf)) return;
                continue;
            }
            std::istringstream again(line);
            if (!(again >> nv >> nf)) return; // the reader says why
            continue;
        }
        std::istringstream row(line);
        if (seen < nv) {
            finite_numbers(row, 3, ln);
        } else if (seen < nv + nf) {
            long long n = 0;
            row >> n;
            for (long long k = 0; k < n; ++k) {
                long long i = -1;
                if (!(row >> i)) fail(ln, "a face of " + std::to_string(n) + " vertices lists fewer");
                if (i < 0 || i >= nv)
                    fail(ln, "face index " + std::to_string(i) + " is out of range (the file has " +
                                 std::to_string(nv) + " vertices, numbered from 0)");
            }
        }
        ++seen;
    }
}

std::uint8_t srgb8(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    const float s = c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return std::uint8_t(std::lround(s * 255.0f));
}

// Every this many elements a writer reports its progress (and may be stopped).
constexpr std::size_t kProgressEvery = 1 << 16;

bool has_uvs(const Mesh& m) {
    return m.corner_uvs.size() == m.triangles.size() * 3 || (!m.uvs.empty() && m.uvs.size() == m.positions.size());
}

// OBJ by hand: v, then vt (per corner or per vertex) and vn when the mesh has them, and with
// a texture the material library and the texture beside it (OpenMesh writes neither per-corner
// UVs nor a map_Kd).
void write_obj(const Mesh& mesh, const fs::path& file, const MeshWriteOptions& wo, const Progress& progress) {
    const std::string name = wo.name.empty() ? file.stem().string() : wo.name;
    const MeshSideFiles side = mesh_side_files(file, mesh); // the default names; none without a texture
    const fs::path mtl_file = wo.mtl_file.empty() ? side.material : wo.mtl_file;
    const fs::path tex_file = wo.texture_file.empty() ? side.texture : wo.texture_file;
    const std::string mtl_name = wo.mtl_name.empty() ? side.material.filename().string() : wo.mtl_name;
    const std::string tex_name = wo.texture_name.empty() ? side.texture.filename().string() : wo.texture_name;
    const bool with_tex = has_texture_map(mesh);
    const bool corner = mesh.corner_uvs.size() == mesh.triangles.size() * 3;
    const bool with_uvs = has_uvs(mesh);
    const bool with_normals = wo.normals && mesh.normals.size() == mesh.positions.size();
    std::string o;
    o.reserve(mesh.positions.size() * (with_normals ? 80 : 40) + mesh.triangles.size() * 40);
    o += "# conceptmesh\n";
    if (with_tex) o += "mtllib " + mtl_name + "\n";
    o += "o " + name + "\n";
    // Building the text takes most of the time; the file then goes out in chunks.
    const Progress build = progress.part(0, 0.7);
    const double total = double(mesh.positions.size() * 3 + mesh.triangles.size()) + 1;
    std::size_t done = 0;
    auto tick = [&] {
        if (build && ++done % kProgressEvery == 0) build(double(done) / total);
    };
    auto row = [&](const char* tag, const float* x, int n) {
        tick();
        o += tag;
        for (int k = 0; k < n; ++k) {
            o += ' ';
            append_float(o, x[k]);
        }
        o += '\n';
    };
    for (const auto& p : mesh.positions) row("v", &p.x, 3);
    if (with_uvs)
        for (const auto& t : corner ? mesh.corner_uvs : mesh.uvs) row("vt", t.data(), 2);
    if (with_normals)
        for (const auto& n : mesh.normals) row("vn", &n.x, 3);
    if (with_tex) o += "usemtl " + name + "\n";
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
        tick();
        o += 'f';
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = mesh.triangles[f][std::size_t(k)] + 1;
            o += ' ';
            append_index(o, v);
            if (!with_uvs && !with_normals) continue;
            o += '/';
            if (with_uvs) append_index(o, corner ? 3 * f + std::size_t(k) + 1 : v);
            if (with_normals) {
                o += '/';
                append_index(o, v);
            }
        }
        o += '\n';
    }
    write_file_bytes(file, o, progress.part(0.7, with_tex ? 0.9 : 1.0));
    if (!with_tex) return;
    write_file_bytes(mtl_file, "# conceptmesh\nnewmtl " + name +
                                   "\nKa 0 0 0\nKd 1 1 1\nKs 0 0 0\nNs 0\nd 1\nillum 1\nmap_Kd " + tex_name + "\n");
    const std::vector<unsigned char> png = encode_png(*mesh.texture, 3);
    write_file_bytes(tex_file, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()),
                     progress.part(0.9, 1.0));
}

} // namespace

void MeshWriteOptions::declare(ParamBinder& b) {
    b.add(binary, ParamSpec::Bool("binary", true, "binary PLY/STL (smaller, faster); ASCII when false"));
    b.add(normals, ParamSpec::Bool("normals", true, "write per-vertex normals where the format holds them"));
}

bool has_texture_map(const Mesh& m) { return m.texture && !m.texture->empty() && has_uvs(m); }

MeshSideFiles mesh_side_files(const fs::path& file, const Mesh& mesh) {
    MeshSideFiles side;
    const std::string ext = lower_extension(file);
    if ((ext != ".obj" && ext != ".usda") || !has_texture_map(mesh)) return side;
    side.texture = file.parent_path() / (file.stem().string() + "_basecolor.png");
    if (ext == ".obj") side.material = fs::path(file).replace_extension(".mtl");
    return side;
}

const std::vector<std::string>& mesh_extensions() {
    static const std::vector<std::string> extensions = {".obj", ".ply", ".stl", ".off", ".glb", ".usda", ".usdz"};
    return extensions;
}

bool mesh_format_supported(const fs::path& file) {
    const auto& known = mesh_extensions();
    return std::find(known.begin(), known.end(), lower_extension(file)) != known.end();
}

bool mesh_readable(const fs::path& file) { return mesh_format_supported(file) && !is_usd_file(file); }

Mesh read_mesh(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("cannot read mesh \"" + file.string() + "\": no such file");
    if (!mesh_readable(file))
        throw Error("cannot read mesh \"" + file.string() + "\": unknown format (use .obj, .ply, .stl, .off or .glb)");
    if (lower_extension(file) == ".glb") return read_glb(file);
    check_text_mesh(file);
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

void write_mesh(const Mesh& mesh, const fs::path& file, const MeshWriteOptions& wo, Progress progress) {
    if (!mesh_format_supported(file))
        throw Error("cannot write mesh \"" + file.string() +
                    "\": unknown format (use .obj, .ply, .stl, .off, .glb, .usda or .usdz)");
    if (is_usd_file(file)) return write_usd(mesh, file, wo, progress);
    if (lower_extension(file) == ".glb") {
        if (mesh.triangles.empty()) throw Error("cannot write mesh \"" + file.string() + "\": the mesh is empty");
        return write_glb(mesh, file, wo.normals, wo.name, progress);
    }
    const std::string ext = lower_extension(file);
    if (ext == ".obj") return write_obj(mesh, file, wo, progress);
    quiet_openmesh();
    // Filling OpenMesh's structure is about a third of the time; the file goes out in chunks.
    const Progress build = progress.part(0, 0.3);
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
    const bool with_colors = ext == ".ply" && mesh.colors.size() == mesh.positions.size();
    if (with_colors) {
        om.request_vertex_colors();
        for (std::size_t i = 0; i < mesh.colors.size(); ++i) {
            const auto& c = mesh.colors[i];
            om.set_color(OMesh::VertexHandle(int(i)), OMesh::Color(srgb8(c[0]), srgb8(c[1]), srgb8(c[2])));
        }
    }
    std::vector<OMesh::VertexHandle> vh(3);
    const std::size_t nf = mesh.triangles.size();
    for (std::size_t f = 0; f < nf; ++f) {
        if (build && f % kProgressEvery == 0) build(double(f) / double(nf));
        const auto& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) vh[k] = OMesh::VertexHandle(int(t[k]));
        if (!om.add_face(vh).is_valid())
            throw Error("cannot write mesh \"" + file.string() +
                        "\": the mesh is not 2-manifold (OpenMesh refused a face)");
    }
    OpenMesh::IO::Options opt;
    if (with_normals) opt += OpenMesh::IO::Options::VertexNormal;
    if (with_colors) opt += OpenMesh::IO::Options::VertexColor;
    const std::string& e = ext;
    if (wo.binary && (e == ".ply" || e == ".stl")) opt += OpenMesh::IO::Options::Binary;
    if (e == ".stl") {
        om.request_face_normals();
        om.update_face_normals();
        opt += OpenMesh::IO::Options::FaceNormal;
    }
    // Through a stream of our own, so a stop takes effect within a chunk of the file.
    const bool binary = opt.check(OpenMesh::IO::Options::Binary);
    const std::uint64_t nv = mesh.positions.size();
    const std::uint64_t expected =
        e == ".stl" ? (binary ? 84 + 50 * std::uint64_t(nf) : 250 * std::uint64_t(nf))
        : binary    ? 512 + nv * (12 + (with_normals ? 12 : 0) + (with_colors ? 3 : 0)) + 13 * std::uint64_t(nf)
                    : nv * (with_normals ? 80 : 40) + 24 * std::uint64_t(nf);
    ProgressFileStream out(file, expected, progress.part(0.3, 1.0));
    if (!out.is_open()) throw Error("cannot write mesh \"" + file.string() + "\": " + std::strerror(errno));
    const bool wrote = OpenMesh::IO::write_mesh(om, out, e, opt, 9);
    if (!out.finish() || !wrote) throw Error("cannot write mesh \"" + file.string() + "\": " + std::strerror(errno));
}

} // namespace cm
