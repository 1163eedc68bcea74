// hull.plausible: rounded, plausible volume inside the visual hull whose silhouettes are
// still exactly the drawings' (every line of sight keeps an occupied voxel).
#include "core/stage.h"
#include "plausible.h"

namespace cm {
namespace {

class HullPlausible : public Stage {
    PlausibleOptions opt_;

public:
    StageSignature signature() const override {
        return {
            "hull.plausible",
            "Remove the hull's implausible volume (outside the drawings' inflated depth profiles) while every "
            "line of sight keeps a voxel, so the silhouettes stay exact",
            {{"volume", DataKind::Volume, "the carved hull, refined or not (hull.carve, hull.marching_intersections)"},
             {"views", DataKind::Views,
              "the views whose lines of sight are kept; the volume's own views when not connected", true}},
            DataKind::Volume};
    }

    void declare(ParamBinder& b) override { opt_.declare(b); }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        std::shared_ptr<const Views> views = in.has("views") ? in.get<Views>("views") : vol->views;
        auto [out, st] = make_plausible(*vol, views, opt_, ctx.progress("plausible volume"));
        st.report(ctx);
        return std::shared_ptr<const Volume>(out);
    }
};

} // namespace

Stage* make_hull_plausible() { return new HullPlausible; }

} // namespace cm
