// The output rules of a mesh leaving the tool (mesh_check.h: OutputCheck): the mesh
// check, crossing faces and coincident vertices.
#include <cmath>
#include <string>
#include <vector>

#include "geometry/mesh_check.h"

namespace cm {

bool OutputCheck::clean() const {
    return mesh.closed_manifold() && mesh.degenerate_faces == 0 && mesh.signed_volume > 0 && crossings.empty() &&
           coincident_vertices == 0;
}

std::vector<std::string> OutputCheck::broken() const {
    std::vector<std::string> out;
    auto add = [&](std::size_t n, const char* what) {
        if (n) out.push_back(std::to_string(n) + " " + what);
    };
    add(mesh.boundary_edges, "boundary edges");
    add(mesh.nonmanifold_edges, "non-manifold edges");
    add(mesh.nonmanifold_vertices, "non-manifold vertices");
    add(mesh.inconsistent_edges, "inconsistently oriented edges");
    add(mesh.degenerate_faces, "degenerate faces");
    add(crossings.size(), "self-intersecting face pairs");
    add(coincident_vertices, "coincident vertices (welded by an importer)");
    if (mesh.signed_volume <= 0)
        out.push_back("inward orientation (volume " + std::to_string(mesh.signed_volume) + ")");
    return out;
}

OutputCheck check_output(const Mesh& m, Progress progress) {
    progress(0);
    OutputCheck c{check_mesh(m), {}};
    progress(0.2);
    c.crossings = find_self_intersections(m, progress.part(0.4, 0.9));
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Vec3f d = hi - lo;
    const double diagonal = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
    progress(0.9);
    c.coincident_vertices = count_coincident_vertices(m, kCoincidentTolerance * diagonal);
    progress(1);
    return c;
}

} // namespace cm
