#include "mesh_report.h"

#include <cstdio>

#include "geometry/mesh_check.h"

namespace cm {

void declare_check(ParamBinder& b, MeshCheckMode& mode) {
    b.add_auto_on_off(mode, "check",
                      "check the mesh (closed, manifold, outward, no degenerate faces) and report the counts; "
                      "auto: up to 5 million faces (the check costs more time and memory than the extraction)");
}

void report_mesh_check(const Mesh& mesh, MeshCheckMode mode, Context& ctx) {
    if (mode == MeshCheckMode::Off || (mode == MeshCheckMode::Auto && mesh.face_count() > kAutoCheckFaces)) return;
    const MeshCheck c = check_mesh(mesh);
    ctx.metric("boundary_edges", double(c.boundary_edges));
    ctx.metric("nonmanifold_edges", double(c.nonmanifold_edges));
    ctx.metric("nonmanifold_vertices", double(c.nonmanifold_vertices));
    ctx.metric("inconsistent_edges", double(c.inconsistent_edges));
    ctx.metric("degenerate_faces", double(c.degenerate_faces));
    ctx.metric("components", double(c.components));
    ctx.metric("euler", double(c.euler));
    ctx.metric("volume", c.signed_volume);
    ctx.metric("area", c.area);
    if (!c.closed_manifold() || c.degenerate_faces || c.signed_volume <= 0) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "the mesh fails its check: %zu boundary, %zu non-manifold and %zu inconsistent edges, "
                      "%zu non-manifold vertices, %zu degenerate faces, volume %g",
                      c.boundary_edges, c.nonmanifold_edges, c.inconsistent_edges, c.nonmanifold_vertices,
                      c.degenerate_faces, c.signed_volume);
        ctx.warn(buf);
    }
}

} // namespace cm
