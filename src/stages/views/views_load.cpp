// views.load: reads the views manifest and its drawings, extracts each
// silhouette, sets up the cameras and aligns hand-drawn views.
#include <cctype>
#include <filesystem>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

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
        b.add(opt_.keep, ParamSpec::Enum("keep", "auto", {"auto", "largest", "all"},
                                         "which separate marks to keep: auto drops specks and small marks (a "
                                         "view's own keep wins)"));
        b.add(opt_.align_tolerance,
              ParamSpec::Float("align_tolerance", 0.02, 0.0, 1.0, "ratio",
                               "relative disagreement between views on a shared axis that raises a warning"));
        b.add(save_silhouettes_,
              ParamSpec::Bool("save_silhouettes", false,
                              "write each extracted silhouette as <view>.silhouette.png beside the run report"));
    }
    void check() override {
        std::error_code ec;
        if (!fs::exists(manifest_, ec)) throw Error("manifest \"" + manifest_.string() + "\" does not exist");
    }

    Data run(const Inputs&, Context& ctx) override {
        LoadViewsReport report;
        auto views = std::make_shared<Views>(
            load_views(manifest_, opt_, report, [&](double f) { ctx.progress(f, f < 0.8 ? "reading" : "aligning"); }));
        for (const auto& n : report.notes) ctx.info(n);
        for (const auto& w : report.warnings) ctx.warn(w);

        if (save_silhouettes_) {
            for (const auto& v : views->views) {
                const fs::path out = ctx.side_output_dir() / (file_stem_for(v.name) + ".silhouette.png");
                write_image(silhouette_image(v), ctx.output_file(out));
            }
        }
        ctx.metric("views", double(views->views.size()));
        for (const auto& v : views->views) {
            // Summed in fixed blocks of rows (the same figure on every run and machine).
            const double area = tbb::parallel_deterministic_reduce(
                tbb::blocked_range<std::size_t>(0, v.coverage.size(), std::size_t(1) << 16), 0.0,
                [&](const tbb::blocked_range<std::size_t>& r, double sum) {
                    // In pixel order, leaving out the zeros beyond the window (adding them
                    // changes no sum).
                    const Coverage& c = v.coverage;
                    const std::size_t W = std::size_t(c.width());
                    for (std::size_t y = r.begin() / W; y * W < r.end(); ++y) {
                        const float* row = c.window_row(int(y));
                        if (!row) continue;
                        const std::size_t left = y * W + std::size_t(c.x0());
                        const std::size_t a = std::max(r.begin(), left);
                        const std::size_t b = std::min(r.end(), left + std::size_t(c.window_width()));
                        for (std::size_t i = a; i < b; ++i) sum += row[i - left];
                    }
                    return sum;
                },
                [](double x, double y) { return x + y; });
            ctx.metric("silhouette_area_px." + v.name, area);
        }
        if (views->has_bounds) {
            const Vec3d e = views->bounds_max - views->bounds_min;
            ctx.metric_json("bounds_size",
                            "[" + std::to_string(e.x) + "," + std::to_string(e.y) + "," + std::to_string(e.z) + "]");
        }
        return std::shared_ptr<const Views>(views);
    }
};

} // namespace

Stage* make_views_load() { return new ViewsLoad; }

} // namespace cm
