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
#include "mesh_decimate.h"
#include "outline_guard.h"

namespace cm {
namespace {

class MeshReduce : public Stage {
    enum class Constrain { None, Silhouette };
    ReduceOptions opt_;
    FaceTarget target_;
    Constrain constrain_ = Constrain::None;
    double tolerance_px_ = 1.0;

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
        b.add(opt_.max_angle_deg, ParamSpec::Float("max_angle_deg", 15.0, 0.1, 89.0, "deg",
                                                   "largest angle between the face normals around a removable vertex "
                                                   "(the paper: 5 to 40; larger reduces more)"));
        target_.declare(b, 0.0);
        b.add(opt_.max_aspect_ratio, ParamSpec::Float("max_aspect_ratio", 0.0, 0.0, 1e6, "",
                                                      "refuse collapses that make a face thinner than this (1 = "
                                                      "equilateral); 0: off, as in the paper"));
        b.add(opt_.no_crossings, crossing_guard_param());
        b.add(constrain_,
              ParamSpec::Enum("constrain", "none", {"none", "silhouette"},
                              "silhouette: refuse collapses that would move the mesh's outline in a view more than "
                              "`tolerance` away from the drawn silhouette (needs the views input)"),
              {Constrain::None, Constrain::Silhouette});
        b.add(tolerance_px_, ParamSpec::Float("tolerance", 1.0, 0.0, 100.0, "px",
                                              "silhouette constraint: how far the outline may move inside or "
                                              "outside the drawn silhouette, in pixels of each view"));
    }
    void check() override { target_.check(); }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        auto out = std::make_shared<Mesh>();
        ReduceOptions opt = opt_;
        std::unique_ptr<OutlineGuard> outline;
        if (constrain_ == Constrain::Silhouette) {
            if (!in.has("views"))
                throw Error("constrain: silhouette needs the views input (inputs: { mesh: ..., views: <views node> })");
            outline = std::make_unique<OutlineGuard>(*in.get<Views>("views"), tolerance_px_);
            opt.outline = outline.get();
        }
        opt.target_faces = target_.count(src->face_count());
        opt.progress = [&ctx](double f) { ctx.progress(f, "reducing"); };
        const DecimateStats st = reduce_mesh(*src, *out, opt);
        report_decimation(ctx, st, *out);
        return std::shared_ptr<const Mesh>(std::move(out));
    }
};

} // namespace

Stage* make_mesh_reduce() { return new MeshReduce; }

} // namespace cm
