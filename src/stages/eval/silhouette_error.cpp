// eval.silhouette_error: re-renders the mesh through every input view's camera and
// compares with the input silhouette (xor_pct over the silhouette area, and IoU).
#include <nlohmann/json.hpp>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"

namespace cm {
namespace {

class EvalSilhouetteError : public Stage {
    double max_xor_pct_ = -1.0;

public:
    StageSignature signature() const override {
        return {"eval.silhouette_error",
                "Silhouette error of the mesh against the input views: xor_pct (100 |S xor R| / |S|) and IoU, per view "
                "and overall",
                {{"mesh", DataKind::Mesh, "the mesh to check"},
                 {"views", DataKind::Views, "the input views (cameras and silhouettes)"}},
                DataKind::Report};
    }
    void declare(ParamBinder& b) override {
        b.add(max_xor_pct_,
              ParamSpec::Float("max_xor_pct", -1.0, -1.0, 1e6, "%",
                               "fail the run when the overall xor_pct is above this (negative: never fail)"));
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; there is nothing to compare");
        ctx.progress(0.0, "rendering");
        // The renders of eval.preview on the same mesh, when it made them first.
        const auto renders = shared_silhouette_error(mesh, *views, [&ctx] { ctx.check_cancel(); });
        const SilhouetteError& e = renders->error;
        nlohmann::json j;
        j["xor_pct"] = e.xor_pct;
        j["mean_iou"] = e.mean_iou;
        j["views"] = nlohmann::json::array();
        for (const auto& v : e.views) {
            j["views"].push_back({{"view", v.view},
                                  {"xor_pct", v.xor_pct},
                                  {"iou", v.iou},
                                  {"input_px", v.input_px},
                                  {"render_px", v.render_px},
                                  {"xor_px", v.xor_px}});
            ctx.metric("xor_pct." + v.view, v.xor_pct);
            ctx.metric("iou." + v.view, v.iou);
        }
        ctx.metric("xor_pct", e.xor_pct);
        ctx.metric("mean_iou", e.mean_iou);
        ctx.metric_json("views", j["views"].dump());
        const double limit = max_xor_pct_;
        if (limit >= 0 && e.xor_pct > limit)
            throw Error("the silhouette error xor_pct " + std::to_string(e.xor_pct) + "% is above max_xor_pct " +
                        std::to_string(limit) + "%");
        auto out = std::make_shared<Report>();
        out->json = j.dump();
        return std::shared_ptr<const Report>(out);
    }
};

} // namespace

Stage* make_eval_silhouette_error() { return new EvalSilhouetteError; }

} // namespace cm
