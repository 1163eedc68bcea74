// eval.preview: the contact sheet of a run's mesh against its input views, written
// beside the run's other outputs.
#include <filesystem>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "io/image_io.h"
#include "metrics/silhouette_error.h"
#include "preview_sheet.h"

namespace fs = std::filesystem;

namespace cm {
namespace {

class EvalPreview : public Stage {
    fs::path path_;
    PreviewOptions opt_;

public:
    StageSignature signature() const override {
        return {"eval.preview",
                "Contact sheet: per view the input drawing, the mesh drawn from that view, and an overlay of the "
                "silhouettes",
                {{"mesh", DataKind::Mesh, "the mesh to show"},
                 {"views", DataKind::Views, "the input views (cameras and silhouettes)"}},
                DataKind::File};
    }
    void declare(ParamBinder& b) override {
        b.add(path_, ParamSpec::OutputPath("path", {".png"}, "output image (.png)"));
        b.add(opt_.panel,
              ParamSpec::Int("panel", 320, 32, 4096, "px", "size of each panel (the sheet has three panels per view)"));
        b.add(opt_.title,
              ParamSpec::String("title", std::string(), "printed at the top of the sheet; empty: the file's name"));
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        PreviewOptions opt = opt_;
        if (opt.title.empty()) opt.title = path_.stem().string();
        ctx.progress(0, "drawing");
        opt.progress = [&ctx](double f) { ctx.progress(0.9 * f); };
        opt.check = [&ctx] { ctx.check_cancel(); };
        // The renders of eval.silhouette_error on the same mesh, when it made them first.
        const auto renders = shared_silhouette_error(mesh, *views, opt.check);
        const SilhouetteError& err = renders->error;
        const Image sheet = make_preview_sheet(*mesh, *views, opt, *renders);
        ctx.progress(0.9, "writing");
        write_image(sheet, ctx.output_file(path_));
        ctx.metric("path", path_.string());
        ctx.metric("xor_pct", err.xor_pct);
        ctx.metric("mean_iou", err.mean_iou);
        auto out = std::make_shared<FileOutput>();
        out->paths.push_back(path_);
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_eval_preview() { return new EvalPreview; }

} // namespace cm
