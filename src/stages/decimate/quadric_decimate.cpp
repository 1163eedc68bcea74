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
        opt_.declare(b);
    }
    void check() override {
        target_.check();
        if (target_.faces == 0 && target_.ratio == 0 && opt_.max_error == 0)
            throw Error("give a target: target_faces, target_ratio or max_error");
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        QuadricOptions opt = opt_; // with this input's face target
        opt.target_faces = target_.count(src->face_count());
        auto [mesh, stats] = quadric_decimate(*src, opt, ctx.progress("decimating"));
        stats.report(ctx);
        return std::make_shared<const Mesh>(std::move(mesh));
    }
};

} // namespace

Stage* make_mesh_quadric_decimate() { return new QuadricDecimate; }

} // namespace cm
