// eval.preview: the contact sheet of a run's mesh against its input views, written
// beside the run's other outputs.
#include <filesystem>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/views.h"
#include "io/image_io.h"
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
        opt_.declare(b);
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto mesh = in.get<Mesh>("mesh");
        auto views = in.get<Views>("views");
        PreviewOptions opt = opt_;
        if (opt.title.empty()) opt.title = path_.stem().string();
        auto [sheet, stats] = make_preview_sheet(*mesh, *views, opt, ctx.progress("drawing").part(0, 0.9));
        ctx.progress(0.9, "writing");
        write_image(sheet, ctx.output_file(path_));
        ctx.metric("path", path_.string());
        stats.report(ctx);
        auto out = std::make_shared<FileOutput>();
        out->paths.push_back(path_);
        return std::shared_ptr<const FileOutput>(out);
    }
};

} // namespace

Stage* make_eval_preview() { return new EvalPreview; }

} // namespace cm
