// eval.silhouette_error: re-renders the mesh through every input view's camera and
// compares with the input silhouette (xor_pct over the silhouette area, and IoU).
#include <string>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "metrics/silhouette_error.h"

namespace cm {
namespace {

// The parameter of the stage: a limit that turns a bad result into a failed run.
struct ErrorLimit {
    double max_xor_pct; ///< negative: never fail

    ErrorLimit() { set_declared_defaults(*this); }
    void declare(ParamBinder& b) {
        b.add(max_xor_pct,
              ParamSpec::Float("max_xor_pct", -1.0, -1.0, 1e6, "%",
                               "fail the run when the overall xor_pct is above this (negative: never fail)"));
    }
};

class EvalSilhouetteError : public Stage {
    ErrorLimit opt_;

public:
    StageSignature signature() const override {
        return {"eval.silhouette_error",
                "Silhouette error of the mesh against the input views: xor_pct (100 |S xor R| / |S|) and IoU, per view "
                "and overall",
                {{"mesh", DataKind::Mesh, "the mesh to check"},
                 {"views", DataKind::Views, "the input views (cameras and silhouettes)"}},
                DataKind::Report};
    }
    void declare(ParamBinder& b) override { opt_.declare(b); }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        if (mesh->triangles.empty()) throw Error("the mesh is empty; there is nothing to compare");
        const Progress progress = ctx.progress("rendering");
        progress(0);
        const SilhouetteError e = silhouette_error(*mesh, *views, progress);
        e.report(ctx);
        const double limit = opt_.max_xor_pct;
        if (limit >= 0 && e.xor_pct > limit)
            throw Error("the silhouette error xor_pct " + std::to_string(e.xor_pct) + "% is above max_xor_pct " +
                        std::to_string(limit) + "%");
        auto out = std::make_shared<Report>();
        out->json = e.json();
        return std::shared_ptr<const Report>(out);
    }
};

} // namespace

Stage* make_eval_silhouette_error() { return new EvalSilhouetteError; }

} // namespace cm
