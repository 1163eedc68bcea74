// mesh.quadric_decimate: Garland-Heckbert quadric error decimation to a face
// count or an error, with normal-deviation and aspect-ratio guards; the same
// manifold-keeping collapse engine as mesh.reduce (docs/mesh.md says why).
#include <memory>

#include "core/mesh.h"
#include "core/stage.h"
#include "decimate_stage.h"
#include "mesh_decimate.h"

namespace cm {
namespace {

class QuadricDecimate : public Stage {
    QuadricOptions opt_;
    FaceTarget target_;

public:
    StageSignature signature() const override {
        return {"mesh.quadric_decimate",
                "Garland-Heckbert quadric decimation to a face count or an error, keeping the mesh 2-manifold",
                {{"mesh", DataKind::Mesh, "the mesh to decimate"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        target_.declare(b, 0.1);
        b.add(opt_.max_error, ParamSpec::Float("max_error", 0.0, 0.0, 1e30, "world units",
                                               "stop before a collapse would move the surface further than this "
                                               "(root mean square distance to the original planes); 0: no limit"));
        b.add(opt_.max_normal_deviation_deg, ParamSpec::Float("max_normal_deviation_deg", 45.0, 1.0, 180.0, "deg",
                                                              "refuse collapses that turn a face by more than this"));
        b.add(opt_.max_aspect_ratio, ParamSpec::Float("max_aspect_ratio", 20.0, 0.0, 1e6, "",
                                                      "refuse collapses that make a face thinner than this (1 = "
                                                      "equilateral); 0: off"));
        b.add(opt_.no_crossings, crossing_guard_param());
    }
    void check() override {
        target_.check();
        if (target_.faces == 0 && target_.ratio == 0 && opt_.max_error == 0)
            throw Error("give a target: target_faces, target_ratio or max_error");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        auto out = std::make_shared<Mesh>();
        QuadricOptions opt = opt_;
        opt.target_faces = target_.count(src->face_count());
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
