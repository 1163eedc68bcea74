// mesh.quadric_decimate: Garland-Heckbert quadric error decimation to a face
// count or an error, with normal-deviation and aspect-ratio guards; the same
// manifold-keeping collapse engine as mesh.reduce (docs/mesh.md says why).
#include <memory>

#include "decimate_stage.h"
#include "core/mesh.h"
#include "mesh_decimate.h"
#include "core/stage.h"

namespace cm {
namespace {

class QuadricDecimate : public Stage {
public:
    StageInfo info() const override {
        auto params = face_target_params(0.1);
        params.push_back(ParamSpec::Float("max_error", 0.0, 0.0, 1e30, "world units",
                                          "stop before a collapse would move the surface further than this "
                                          "(root mean square distance to the original planes); 0: no limit"));
        params.push_back(ParamSpec::Float("max_normal_deviation_deg", 45.0, 1.0, 180.0, "deg",
                                          "refuse collapses that turn a face by more than this"));
        params.push_back(ParamSpec::Float("max_aspect_ratio", 20.0, 0.0, 1e6, "",
                                          "refuse collapses that make a face thinner than this (1 = equilateral); 0: off"));
        params.push_back(crossing_guard_param());
        return {"mesh.quadric_decimate",
                "Garland-Heckbert quadric decimation to a face count or an error, keeping the mesh 2-manifold",
                {{"mesh", DataKind::Mesh, "the mesh to decimate"}},
                DataKind::Mesh, params};
    }
    void check() override {
        check_face_target(params_);
        if (params_.get_int("target_faces") == 0 && params_.get_float("target_ratio") == 0 && params_.get_float("max_error") == 0)
            throw Error("give a target: target_faces, target_ratio or max_error");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        auto out = std::make_shared<Mesh>();
        QuadricOptions opt;
        opt.target_faces = face_target(params_, src->face_count());
        opt.max_error = params_.get_float("max_error");
        opt.max_normal_deviation_deg = params_.get_float("max_normal_deviation_deg");
        opt.max_aspect_ratio = params_.get_float("max_aspect_ratio");
        opt.no_crossings = params_.get_bool("guard");
        opt.progress = [&ctx](double f) { ctx.progress(f, "decimating"); };
        const DecimateStats st = quadric_decimate(*src, *out, opt);
        report_decimation(ctx, st, *out);
        ctx.metric("max_error", st.max_error);
        if (opt.target_faces && st.faces_after > opt.target_faces)
            ctx.warn("stopped at " + std::to_string(st.faces_after) + " faces, above the target of " +
                     std::to_string(opt.target_faces) + ": no further collapse passes the guards");
        return std::shared_ptr<const Mesh>(std::move(out));
    }
};

} // namespace

Stage* make_mesh_quadric_decimate() { return new QuadricDecimate; }

} // namespace cm
