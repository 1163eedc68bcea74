#include "decimate_stage.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "mesh_decimate.h"

namespace cm {

void FaceTarget::declare(ParamBinder& b, double default_ratio) {
    b.add(faces,
          ParamSpec::Int("target_faces", 0, 0, 2e9, "faces", "stop at or below this many faces; 0: no face count"));
    b.add(ratio, ParamSpec::Float("target_ratio", default_ratio, 0.0, 1.0, "",
                                  "stop at or below this fraction of the input's faces; 0: no ratio"));
}

ParamSpec crossing_guard_param() {
    return ParamSpec::Bool("guard", true,
                           "keep the result free of self-intersections: where faces of nearby parts end up "
                           "crossing, reduce again from the input with the vertices there kept");
}

void FaceTarget::check() const {
    if (faces > 0 && ratio > 0 && faces.given && ratio.given) {
        std::ostringstream s;
        s << "give target_faces or target_ratio, not both (got " << faces.value << " and " << ratio.value << ")";
        throw Error(s.str());
    }
}

std::size_t FaceTarget::count(std::size_t input_faces) const {
    if (faces > 0 && (faces.given || ratio <= 0)) return std::size_t(faces.value);
    if (ratio > 0) return std::size_t(std::floor(ratio * double(input_faces)));
    return 0;
}

void report_decimation(Context& ctx, const DecimateStats& st, const Mesh& out) {
    ctx.metric("faces_before", double(st.faces_before));
    ctx.metric("faces", double(st.faces_after));
    ctx.metric("vertices", double(out.vertex_count()));
    ctx.metric("face_ratio", st.faces_before ? double(st.faces_after) / double(st.faces_before) : 1.0);
    ctx.metric("collapses", double(st.collapses));
    ctx.metric("guard_restarts", double(st.restarts));
    if (st.frozen_vertices) ctx.metric("guard_frozen_vertices", double(st.frozen_vertices));
    if (st.crossings_left)
        ctx.warn(std::to_string(st.crossings_left) + " pairs of faces cross each other in the result" +
                 (st.restarts ? " (the input's own, or more than the restarts could remove)" : ""));
    if (st.locked_vertices) {
        ctx.metric("locked_vertices", double(st.locked_vertices));
        ctx.warn(std::to_string(st.locked_vertices) +
                 " vertices lie on a boundary or a non-manifold edge and were kept as they are");
    }
}

} // namespace cm
