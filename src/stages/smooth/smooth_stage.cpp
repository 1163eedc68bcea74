#include "smooth_stage.h"

#include <memory>

#include "core/error.h"
#include "core/views.h"
#include "geometry/hard_surface.h"
#include "geometry/hull_distance.h"

namespace cm {

std::vector<PortSpec> smooth_ports() {
    return {{"mesh", DataKind::Mesh, "the mesh to smooth"},
            {"views", DataKind::Views, "the views whose visual hull bounds the vertices (constrain: hull)", true}};
}

Data run_smooth(const Inputs& in, Context& ctx, const SmoothOptions& opt) {
    auto src = in.get<Mesh>("mesh");
    std::unique_ptr<HullDistance> hull;
    if (opt.constrain != SmoothOptions::Constrain::None && in.has("views"))
        hull = std::make_unique<HullDistance>(*in.get<Views>("views"));
    SmoothOptions o = opt;
    if (o.hard_surface && o.crease_angle_deg > 0) {
        if (!in.has("views"))
            throw Error("hard_surface needs the views input (inputs: { mesh: ..., views: <views node> })");
        const double hardness = hard_surface(*in.get<Views>("views"));
        ctx.metric("hardness", hardness);
        if (hardness >= 1.0) o.crease_angle_deg = 0; // the hull kept whole: its creases are cut as in the paper
    }
    if (o.crease_reach > 0 && in.has("views"))
        for (const View& v : in.get<Views>("views")->views) o.crease_views.push_back(v.camera);
    auto [mesh, stats] = smooth_mesh(*src, o, hull.get(), ctx.progress("smoothing"));
    stats.report(ctx);
    return std::make_shared<const Mesh>(std::move(mesh));
}

} // namespace cm
