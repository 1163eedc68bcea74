// conceptmesh check MESH: the quality rules of an output mesh in one table — closed,
// 2-manifold, outward, no degenerate faces, no self-intersections — for a run's result
// or a mesh from elsewhere. Exit code 1 when a rule is broken, so scripts can gate on it.
#include <algorithm>
#include <array>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/tool_common.h"
#include "core/mesh.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_intersect.h"
#include "io/mesh_io.h"

namespace cm::cli {

namespace {

struct CheckOptions {
    std::string mesh;
    bool json = false;
    int list = 0;
};

std::array<float, 3> face_centre(const Mesh& mesh, std::uint32_t f) {
    const auto& t = mesh.triangles[f];
    const Vec3f c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) * (1.0f / 3.0f);
    return {c.x, c.y, c.z};
}

nlohmann::json check_json(const CheckOptions& o, const Mesh& mesh, const OutputCheck& check, std::size_t shown) {
    const MeshCheck& c = check.mesh;
    const std::vector<FacePair>& pairs = check.crossings;
    nlohmann::json j = {{"mesh", o.mesh},
                        {"ok", check.clean()},
                        {"vertices", mesh.vertex_count()},
                        {"faces", mesh.face_count()},
                        {"components", c.components},
                        {"boundary_edges", c.boundary_edges},
                        {"nonmanifold_edges", c.nonmanifold_edges},
                        {"nonmanifold_vertices", c.nonmanifold_vertices},
                        {"inconsistent_edges", c.inconsistent_edges},
                        {"degenerate_faces", c.degenerate_faces},
                        {"self_intersections", pairs.size()},
                        {"coincident_vertices", check.coincident_vertices},
                        {"volume", c.signed_volume},
                        {"area", c.area},
                        {"euler", c.euler}};
    if (o.list > 0) {
        j["crossing_pairs"] = nlohmann::json::array();
        for (std::size_t i = 0; i < shown; ++i)
            j["crossing_pairs"].push_back(
                {{"faces", {pairs[i][0], pairs[i][1]}},
                 {"centres", {face_centre(mesh, pairs[i][0]), face_centre(mesh, pairs[i][1])}}});
    }
    return j;
}

void print_check_table(const CheckOptions& o, const Mesh& mesh, const OutputCheck& check, std::size_t shown) {
    const MeshCheck& c = check.mesh;
    const std::vector<FacePair>& pairs = check.crossings;
    const std::size_t crossings = pairs.size();
    auto row = [](const char* what, auto value, bool good) {
        std::cout << std::left << std::setw(22) << what << std::right << std::setw(14) << value << "  "
                  << (good ? "ok" : "FAIL") << "\n";
    };
    std::cout << o.mesh << ": " << mesh.vertex_count() << " vertices, " << mesh.face_count() << " faces, "
              << c.components << " component" << (c.components == 1 ? "" : "s") << ", Euler " << c.euler << "\n";
    row("boundary edges", c.boundary_edges, c.boundary_edges == 0);
    row("non-manifold edges", c.nonmanifold_edges, c.nonmanifold_edges == 0);
    row("non-manifold vertices", c.nonmanifold_vertices, c.nonmanifold_vertices == 0);
    row("inconsistent edges", c.inconsistent_edges, c.inconsistent_edges == 0);
    row("degenerate faces", c.degenerate_faces, c.degenerate_faces == 0);
    row("self-intersections", crossings, crossings == 0);
    row("coincident vertices", check.coincident_vertices, check.coincident_vertices == 0);
    row("volume", c.signed_volume, c.signed_volume > 0);
    for (std::size_t i = 0; i < shown; ++i) {
        const auto a = face_centre(mesh, pairs[i][0]), b = face_centre(mesh, pairs[i][1]);
        std::cout << "  crossing: faces " << pairs[i][0] << " and " << pairs[i][1] << " near (" << a[0] << ", " << a[1]
                  << ", " << a[2] << ") / (" << b[0] << ", " << b[1] << ", " << b[2] << ")\n";
    }
    if (shown < crossings && o.list > 0) std::cout << "  ... and " << crossings - shown << " more pairs\n";
    std::cout << (check.clean() ? "closed, 2-manifold, outward, clean" : "not a clean closed mesh") << "\n";
}

int run_check(const CheckOptions& o) {
    const Mesh mesh = read_mesh(o.mesh);
    const OutputCheck check = check_output(mesh);
    const std::size_t shown = std::min(check.crossings.size(), std::size_t(o.list));
    if (o.json) std::cout << check_json(o, mesh, check, shown).dump(2) << "\n";
    else print_check_table(o, mesh, check, shown);
    return check.clean() ? 0 : 1;
}

} // namespace

void add_check_command(CLI::App& app, GlobalOptions&, std::function<int()>& action) {
    auto* cmd = app.add_subcommand(
        "check",
        "Check a mesh: closed, 2-manifold, outward, no degenerate faces, no self-intersections (exit 1 if not)");
    auto o = std::make_shared<CheckOptions>();
    cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .stl .off .glb)")->required();
    cmd->add_flag("--json", o->json, "Print a JSON object");
    cmd->add_option("--list", o->list, "Also give where the first N crossing face pairs are (face ids and centres)")
        ->check(CLI::NonNegativeNumber);
    set_action(cmd, action, [o] { return run_check(*o); });
}

} // namespace cm::cli
