// views.load: reads the views manifest and its drawings, extracts each
// silhouette, sets up the cameras and aligns hand-drawn views.
#include <filesystem>

#include <tbb/parallel_for.h>

#include "align.h"
#include "core/image_io.h"
#include "core/stage.h"
#include "core/views.h"
#include "manifest.h"
#include "silhouette.h"

namespace fs = std::filesystem;

namespace cm {
namespace {

class ViewsLoad : public Stage {
public:
    StageInfo info() const override {
        return {"views.load",
                "Read the views manifest and its drawings: silhouettes, cameras, alignment",
                {},
                DataKind::Views,
                {ParamSpec::Path("manifest", std::nullopt, "the views manifest (YAML): which image is which view"),
                 ParamSpec::Enum("keep", "auto", {"auto", "largest", "all"},
                                 "which separate marks to keep: auto drops specks and small marks (a view's own keep wins)"),
                 ParamSpec::Float("align_tolerance", 0.02, 0.0, 1.0, "ratio",
                                  "relative disagreement between views on a shared axis that raises a warning"),
                 ParamSpec::Bool("save_silhouettes", false,
                                 "write each extracted silhouette as <view>.silhouette.png beside the run report")}};
    }

    void prepare(const ParamSet& p) override {
        Stage::prepare(p);
        const fs::path m = p.get_string("manifest");
        std::error_code ec;
        if (!fs::exists(m, ec)) throw Error("manifest \"" + m.string() + "\" does not exist");
    }

    Data run(const Inputs&, Context& ctx) override {
        const Manifest man = read_manifest(params_.get_string("manifest"));
        auto views = std::make_shared<Views>();
        views->manifest = man.file;
        views->views.resize(man.views.size());
        std::size_t perspective = 0;
        for (const auto& mv : man.views) perspective += mv.matrix.has_value();
        if (perspective != 0 && perspective != man.views.size())
            throw Error(man.file.string() + ": mixes calibrated (matrix) and drawn views; use one kind per manifest");
        views->calibrated = perspective != 0;

        std::vector<std::string> errors(man.views.size());
        std::vector<std::string> notes(man.views.size());
        std::atomic<int> done{0};
        tbb::parallel_for(std::size_t(0), man.views.size(), [&](std::size_t i) {
            const ManifestView& mv = man.views[i];
            View& v = views->views[i];
            try {
                v.name = mv.key;
                v.source = mv.image;
                ImageInfo info;
                v.image = read_image(mv.image, &info);
                v.width = v.image.width;
                v.height = v.image.height;
                SilhouetteOptions so;
                so.background = mv.background;
                so.threshold = mv.threshold.value_or(-1.0);
                so.keep = mv.keep != "auto" ? mv.keep : params_.get_string("keep");
                SilhouetteResult s = extract_silhouette(v.image, info, so);
                v.coverage = std::move(s.coverage);
                if (s.components_dropped)
                    notes[i] = "view \"" + v.name + "\": dropped " + std::to_string(s.components_dropped) +
                               " separate mark(s) away from the object (keep: all keeps them)";
                if (mv.matrix) v.camera = Camera::perspective(*mv.matrix);
                else if (mv.view) v.camera = *Camera::named(*mv.view);
                else v.camera = Camera::from_azimuth_elevation(mv.azimuth.value_or(0), mv.elevation.value_or(0));
            } catch (const std::exception& e) {
                errors[i] = "view \"" + mv.key + "\": " + e.what();
            }
            ++done;
        });
        for (const auto& e : errors)
            if (!e.empty()) throw Error(e);
        for (const auto& n : notes)
            if (!n.empty()) ctx.info(n);
        ctx.progress(0.8, "aligning");

        for (const auto& v : views->views) {
            std::size_t inside = 0;
            for (float c : v.coverage) inside += c >= 0.5f;
            if (inside == 0)
                throw Error("view \"" + v.name + "\" (" + v.source.string() + ") has an empty silhouette: no object was found in it");
        }
        if (views->calibrated) {
            if (man.bounds) {
                views->has_bounds = true;
                views->bounds_min = {(*man.bounds)[0], (*man.bounds)[1], (*man.bounds)[2]};
                views->bounds_max = {(*man.bounds)[3], (*man.bounds)[4], (*man.bounds)[5]};
            }
        } else {
            AlignOptions ao;
            ao.height = man.height;
            ao.width = man.width;
            ao.depth = man.depth;
            ao.tolerance = params_.get_float("align_tolerance");
            std::vector<std::string> warnings;
            align_views(*views, ao, warnings);
            for (const auto& w : warnings) ctx.warn(w);
        }

        if (params_.get_bool("save_silhouettes")) {
            for (const auto& v : views->views) {
                Image img;
                img.width = v.width;
                img.height = v.height;
                img.channels = 1;
                img.pixels = v.coverage;
                const fs::path out = ctx.side_output_dir() / (v.name + ".silhouette.png");
                write_image(img, ctx.output_file(out));
            }
        }
        ctx.metric("views", double(views->views.size()));
        for (const auto& v : views->views) {
            double area = 0;
            for (float c : v.coverage) area += c;
            ctx.metric("silhouette_area_px." + v.name, area);
        }
        if (views->has_bounds) {
            const Vec3d e = views->bounds_max - views->bounds_min;
            ctx.metric_json("bounds_size", "[" + std::to_string(e.x) + "," + std::to_string(e.y) + "," + std::to_string(e.z) + "]");
        }
        return std::shared_ptr<const Views>(views);
    }
};

} // namespace

Stage* make_views_load() { return new ViewsLoad; }

} // namespace cm
