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

    void declare(ParamBinder& b) override { opt_.declare(b); }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        std::shared_ptr<const Views> views = in.has("views") ? in.get<Views>("views") : vol->views;
        auto [out, st] = refine(*vol, views, opt_, ctx.progress("crossings"));
        st.report(ctx);
        return std::shared_ptr<const Volume>(out);
    }
};

} // namespace

Stage* make_hull_marching_intersections() { return new HullMarchingIntersections; }

} // namespace cm
