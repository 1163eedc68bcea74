// hull.marching_intersections: exact crossings of the visual hull with the grid
// edges (paper step 2), found on the silhouettes at sub-pixel precision.
#include "core/stage.h"
#include "refine.h"

namespace cm {
namespace {

class HullMarchingIntersections : public Stage {
    RefineOptions opt_;

public:
    StageSignature signature() const override {
        return {"hull.marching_intersections",
                "Find where the silhouette cones cross each grid edge of the hull surface, at sub-pixel precision",
                {{"volume", DataKind::Volume, "the carved hull (hull.carve)"},
                 {"views", DataKind::Views, "the views to intersect with; the volume's own views when not connected",
                  true}},
                DataKind::Volume};
    }

    void declare(ParamBinder& b) override {
        b.add_auto_on_off(opt_.thin, "thin",
                          "keep parts thinner than a cell (edges whose two outside ends pass through the hull); "
                          "auto: when a cell spans more than a pixel of the finest view");
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        std::shared_ptr<const Views> views = in.has("views") ? in.get<Views>("views") : vol->views;
        RefineStats st;
        auto out = refine(
            *vol, views, opt_, [&](double f) { ctx.progress(f, "crossings"); }, &st);
        ctx.metric("crossings", double(st.crossings));
        ctx.metric("thin_crossings", double(st.thin_crossings));
        ctx.metric("cell_px", st.cell_px);
        ctx.metric("thin_searched", st.thin_searched ? "yes" : "no");
        if (st.unresolved) {
            ctx.metric("unresolved_crossings", double(st.unresolved));
            ctx.warn(std::to_string(st.unresolved) +
                     " crossing(s) could not be placed from the silhouettes (the views differ from the ones carved?); "
                     "they sit at the grid point");
        }
        ctx.metric("grid_bytes", double(out->crossings->tree().memUsage()));
        return std::shared_ptr<const Volume>(out);
    }
};

} // namespace

Stage* make_hull_marching_intersections() { return new HullMarchingIntersections; }

} // namespace cm
