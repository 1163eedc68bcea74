// views.load: reads the views manifest and its drawings, extracts each
// silhouette, sets up the cameras and aligns hand-drawn views.
#include <cctype>
#include <filesystem>
#include <memory>

#include "core/stage.h"
#include "core/views.h"
#include "io/image_io.h"
#include "load.h"

namespace fs = std::filesystem;

namespace cm {
namespace {

// A view's name as a file name in the report folder: a name holding a path ("../../x",
// "/tmp/x") must not write outside that folder, so only letters, digits and "-_." stay.
std::string file_stem_for(const std::string& name) {
    std::string s;
    for (char c : name) s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
    if (s.find_first_not_of('.') == std::string::npos) s = "view" + s; // "", ".", ".."
    return s;
}

class ViewsLoad : public Stage {
    fs::path manifest_;
    LoadViewsOptions opt_;
    bool save_silhouettes_ = false;

public:
    StageSignature signature() const override {
        return {"views.load",
                "Read the views manifest and its drawings: silhouettes, cameras, alignment",
                {},
                DataKind::Views};
    }
    void declare(ParamBinder& b) override {
        b.add(manifest_,
              ParamSpec::Path("manifest", std::nullopt, "the views manifest (YAML): which image is which view"));
        opt_.declare(b);
        b.add(save_silhouettes_,
              ParamSpec::Bool("save_silhouettes", false,
                              "write each extracted silhouette as <view>.silhouette.png beside the run report"));
    }
    void check() override {
        std::error_code ec;
        if (!fs::exists(manifest_, ec)) throw Error("manifest \"" + manifest_.string() + "\" does not exist");
    }

    Data run(const Inputs&, Context& ctx) override {
        // Reading the views is the first 80 % (load_views()), aligning them the rest.
        auto [views, stats] =
            load_views(manifest_, opt_,
                       Progress([&ctx](double f) { ctx.progress(f, f < 0.8 ? "reading" : "aligning"); },
                                [&ctx] { ctx.check_cancel(); }));
        for (const auto& n : stats.notes) ctx.info(n);
        stats.report(ctx);
        if (save_silhouettes_) {
            for (const auto& v : views.views) {
                const fs::path out = ctx.side_output_dir() / (file_stem_for(v.name) + ".silhouette.png");
                write_image(silhouette_image(v), ctx.output_file(out));
            }
        }
        return std::make_shared<const Views>(std::move(views));
    }
};

} // namespace

Stage* make_views_load() { return new ViewsLoad; }

} // namespace cm
