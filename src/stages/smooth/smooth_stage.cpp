#include "smooth_stage.h"

#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/mesh.h"
#include "core/views.h"
#include "geometry/hull_distance.h"

namespace cm {

namespace {

// The enclosed volume (the divergence theorem over the faces), for the volume_change_pct
// metric: one parallel pass, where a full check_mesh (edges sorted, fans per vertex)
// cost more than the smoothing itself on a million faces. Deterministic reduce: the sum is
// added up in one order whatever the thread count, so reports are byte-identical.
double signed_volume(const Mesh& m) {
    return tbb::parallel_deterministic_reduce(
               tbb::blocked_range<std::size_t>(0, m.triangles.size(), 1 << 14), 0.0,
               [&](const tbb::blocked_range<std::size_t>& r, double acc) {
                   for (std::size_t f = r.begin(); f != r.end(); ++f) {
                       const auto& t = m.triangles[f];
                       acc += dot(Vec3d(m.positions[t[0]]), cross(Vec3d(m.positions[t[1]]), Vec3d(m.positions[t[2]])));
                   }
                   return acc;
               },
               [](double a, double b) { return a + b; }) /
           6.0;
}

} // namespace

void SmoothCommon::declare(ParamBinder& b, std::int64_t default_iterations) {
    b.add(iterations, ParamSpec::Int("iterations", default_iterations, 0, 10000, "",
                                     "smoothing iterations (Taubin: one lambda step and one mu step each)"));
    b.add(constrain,
          ParamSpec::Enum("constrain", "none", {"none", "hull", "inside"},
                          "hull: keep every vertex within `tolerance` of the visual hull of the views "
                          "(needs the views input), so the drawn outline is kept; inside: the vertices on "
                          "the hull stay on it, the others move freely inside it (a surface carved inside "
                          "the hull: hull.plausible)"),
          {Constrain::None, Constrain::Hull, Constrain::Inside});
    b.add(tolerance_px, ParamSpec::Float("tolerance", 0.5, 0.0, 100.0, "px",
                                         "hull constraint: largest distance of a vertex from the hull, in pixels of "
                                         "the finest view"));
    b.add(guard, ParamSpec::Bool("guard", true,
                                 "keep the surface valid: vertices of faces that would cross another face, turn "
                                 "over or collapse, and vertices drawn onto another vertex, are moved back towards "
                                 "their input positions"));
}

std::vector<PortSpec> smooth_ports() {
    return {{"mesh", DataKind::Mesh, "the mesh to smooth"},
            {"views", DataKind::Views, "the views whose visual hull bounds the vertices (constrain: hull)", true}};
}

Data SmoothCommon::run(const Inputs& in, Context& ctx, SmoothOptions opt) const {
    auto src = in.get<Mesh>("mesh");
    opt.iterations = iterations;
    std::unique_ptr<HullDistance> hull;
    if (constrain != Constrain::None) {
        const char* name = constrain == Constrain::Hull ? "hull" : "inside";
        if (!in.has("views"))
            throw Error(std::string("constrain: ") + name +
                        " needs the views input (inputs: { mesh: ..., views: <views node> })");
        auto views = in.get<Views>("views");
        hull = std::make_unique<HullDistance>(*views);
        opt.hull = hull.get();
        opt.tolerance = tolerance_px * hull->finest_pixel();
        opt.inside_free = constrain == Constrain::Inside;
    }
    opt.guard = guard;
    opt.progress = [&ctx](double f) { ctx.progress(f, "smoothing"); };
    auto out = std::make_shared<Mesh>();
    const double v0 = signed_volume(*src);
    const SmoothStats st = smooth_mesh(*src, *out, opt);
    const double v1 = signed_volume(*out);
    ctx.metric("vertices", double(out->vertex_count()));
    ctx.metric("faces", double(out->face_count()));
    ctx.metric("volume_before", v0);
    ctx.metric("volume_after", v1);
    if (v0 != 0) ctx.metric("volume_change_pct", 100.0 * (v1 - v0) / v0);
    if (opt.guard) {
        ctx.metric("guard_bad_faces", double(st.bad_faces));
        ctx.metric("guard_coincident", double(st.coincident));
        ctx.metric("guard_pulled_back", double(st.pulled_back));
        ctx.metric("guard_rounds", double(st.guard_rounds));
        if (st.unresolved)
            ctx.warn(std::to_string(st.unresolved) +
                     " faces of the input cross another face, turn over or collapse; smoothing left them as they were");
    }
    if (hull) {
        ctx.metric("clamped_steps", double(st.clamped_steps));
        ctx.metric("max_hull_distance_px", st.max_hull_distance / hull->finest_pixel());
    }
    return std::shared_ptr<const Mesh>(std::move(out));
}

} // namespace cm
