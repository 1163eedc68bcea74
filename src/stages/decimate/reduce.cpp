// mesh.reduce: the paper's polygon reduction (method step 5). A vertex is a
// candidate while the normals of its faces stay within max_angle_deg of each
// other; the least important go first, I(V) = arccos(<N_a, N_b>) * sum_j |V_j - V|.
// With `constrain: silhouette` no collapse moves an outline away from the drawing.
#include <memory>

#include "core/error.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "decimate_stage.h"
#include "geometry/hard_surface.h"
#include "mesh_decimate.h"
#include "outline_guard.h"

namespace cm {
namespace {

class MeshReduce : public Stage {
    ReduceOptions opt_;
    FaceTarget target_;

public:
    StageSignature signature() const override {
        return {
            "mesh.reduce",
            "The paper's importance-based polygon reduction: flat regions lose triangles, sharp borders stay",
            {{"mesh", DataKind::Mesh,
              "the mesh to reduce (closed 2-manifold parts are reduced; "
              "vertices on boundaries or non-manifold edges stay)"},
             {"views", DataKind::Views, "the views whose silhouettes the outline keeps (constrain: silhouette)", true}},
            DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        opt_.declare_angle(b);
        target_.declare(b, 0.0);
        opt_.declare_limits(b);
    }
    void check() override { target_.check(); }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        ReduceOptions opt = opt_; // with this input's face target and, when asked, its views' outline guard
        std::unique_ptr<OutlineGuard> outline;
        if (opt.constrain == ReduceOptions::Constrain::Silhouette) {
            if (!in.has("views"))
                throw Error("constrain: silhouette needs the views input (inputs: { mesh: ..., views: <views node> })");
            outline = std::make_unique<OutlineGuard>(*in.get<Views>("views"), opt.tolerance_px);
            opt.outline = outline.get();
        }
        if (opt.hard_surface && opt.crease_straightness_deg > ReduceOptions::kHardCreaseStraightness) {
            if (!in.has("views"))
                throw Error("hard_surface needs the views input (inputs: { mesh: ..., views: <views node> })");
            const double hardness = hard_surface(*in.get<Views>("views"));
            ctx.metric("hardness", hardness);
            if (hardness >= 1.0) opt.crease_straightness_deg = ReduceOptions::kHardCreaseStraightness;
        }
        opt.target_faces = target_.count(src->face_count());
        auto [mesh, stats] = reduce_mesh(*src, opt, ctx.progress("reducing"));
        stats.report(ctx);
        return std::make_shared<const Mesh>(std::move(mesh));
    }
};

} // namespace

Stage* make_mesh_reduce() { return new MeshReduce; }

} // namespace cm
