#include "mesh_report.h"

#include <cstdio>

#include "geometry/mesh_check.h"

namespace cm {

void MeshCheckOptions::declare(ParamBinder& b) {
    b.add_auto_on_off(mode, "check",
                      "check the mesh (closed, manifold, outward, no degenerate faces) and report the counts; "
                      "auto: up to 5 million faces (the check costs more time and memory than the extraction)");
}

void report_mesh(const Mesh& mesh, const MeshCheckOptions& opt, Metrics& m) {
    m.count("faces", mesh.face_count());
    m.count("vertices", mesh.vertex_count());
    if (opt.mode == MeshCheckMode::Off || (opt.mode == MeshCheckMode::Auto && mesh.face_count() > kAutoCheckFaces))
        return;
    const MeshCheck c = check_mesh(mesh);
    m.count("boundary_edges", c.boundary_edges);
    m.count("nonmanifold_edges", c.nonmanifold_edges);
    m.count("nonmanifold_vertices", c.nonmanifold_vertices);
    m.count("inconsistent_edges", c.inconsistent_edges);
    m.count("degenerate_faces", c.degenerate_faces);
    m.count("components", c.components);
    m.metric("euler", double(c.euler));
    m.metric("volume", c.signed_volume);
    m.metric("area", c.area);
    if (!c.closed_manifold() || c.degenerate_faces || c.signed_volume <= 0) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "the mesh fails its check: %zu boundary, %zu non-manifold and %zu inconsistent edges, "
                      "%zu non-manifold vertices, %zu degenerate faces, volume %g",
                      c.boundary_edges, c.nonmanifold_edges, c.inconsistent_edges, c.nonmanifold_vertices,
                      c.degenerate_faces, c.signed_volume);
        m.warn(buf);
    }
}

} // namespace cm
