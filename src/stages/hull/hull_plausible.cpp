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

    void declare(ParamBinder& b) override {
        b.add(opt_.roundness,
              ParamSpec::Float("roundness", 1.0, 0.0, 1.0, "",
                               "0: the visual hull as it is; 1: the full depth profile of the drawings"));
        b.add(
            opt_.profile_exponent,
            ParamSpec::Float("profile_exponent", 2.0, 1.0, 16.0, "",
                             "exponent n of the profile (1 - (1 - d/R)^n)^(1/n): 2 round, 1 a ridge, larger flatter"));
        b.add(opt_.ray_keep, ParamSpec::Int("ray_keep", 1, 1, 64, "cells",
                                            "occupied cells every line of sight keeps (1: one is enough for the "
                                            "silhouette; more keeps a minimum thickness)"));
        b.add(opt_.thin_cells,
              ParamSpec::Int("thin_cells", 3, 0, 64, "cells",
                             "voxels in a run of at most this many cells along a view's line of sight, "
                             "well inside a thin part of that view's drawing, are kept (fins, blades, "
                             "ears seen face-on)"));
        b.add(opt_.view_blend, ParamSpec::Float("view_blend", 2.0, 0.0, 10.0, "cells",
                                                "the views' fields joined by a smooth maximum over this many cells "
                                                "(where one view objects mildly and the others do not, they win); 0: "
                                                "the plain maximum, any view removes"));
        b.add(opt_.smooth_cells,
              ParamSpec::Float("smooth", 2.5, 0.0, 8.0, "cells at 256",
                               "standard deviation of the Gaussian smoothing of the field (a smoother "
                               "new surface), in cells of a grid of 256 along the object's longest "
                               "side, 0 for none"));
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        std::shared_ptr<const Views> views = in.has("views") ? in.get<Views>("views") : vol->views;
        PlausibleStats st;
        auto out = make_plausible(
            *vol, views, opt_, [&](double f) { ctx.progress(f, "plausible volume"); }, &st);
        ctx.metric("hull_voxels", double(st.hull_voxels));
        ctx.metric("candidates", double(st.candidates));
        ctx.metric("removed_voxels", double(st.removed));
        ctx.metric("removed_pct", st.hull_voxels ? 100.0 * double(st.removed) / double(st.hull_voxels) : 0.0);
        ctx.metric("kept_for_rays", double(st.kept_for_rays));
        ctx.metric("thin_kept", double(st.thin_kept));
        ctx.metric("new_crossings", double(st.new_crossings));
        ctx.metric("thickened", double(st.thickened));
        ctx.metric("short_rays", double(st.short_rays));
        ctx.metric("thin_dropped", double(st.thin_dropped));
        ctx.metric("loose_dropped", double(st.loose_dropped));
        ctx.metric("cavities_filled", double(st.cavities_filled));
        ctx.metric("pieces_joined", double(st.pieces_joined));
        ctx.metric("ball_rays", double(st.ball_rays));
        ctx.metric("cell_px", st.cell_px);
        if (!vol->crossings)
            ctx.warn("the volume is not refined: the new surface gets crossings, the hull's own edges midpoints");
        return std::shared_ptr<const Volume>(out);
    }
};

} // namespace

Stage* make_hull_plausible() { return new HullPlausible; }

} // namespace cm
