// hull.carve: the coarse visual hull (paper step 1) in a sparse OpenVDB grid.
#include <cstdint>
#include <cstdio>

#include "carve.h"
#include "core/stage.h"
#include "geometry/visual_hull.h"
#include "io/limits.h"

namespace cm {
namespace {

class HullCarve : public Stage {
    CarveOptions opt_;

public:
    StageSignature signature() const override {
        return {
            "hull.carve",
            "Carve the visual hull of the views' silhouettes into a sparse grid (tiles inside, leaves at the surface)",
            {{"views", DataKind::Views, "the views whose silhouettes are carved"}},
            DataKind::Volume};
    }
    void declare(ParamBinder& b) override { opt_.declare(b); }

    Data run(const Inputs& in, Context& ctx) override {
        auto views = in.get<Views>("views");
        // The silhouettes' summed-area tables, made once for every hull of this stage (the
        // estimate's, the box estimate's and the carving's) and carried on in the volume.
        const auto tables = silhouette_tables(*views);
        // Refuse before anything large is allocated: a one-line change of the resolution
        // can ask for more memory than the machine has (the stages after the carve hold
        // about kPipelineBytesPerSurfaceCell per surface cell).
        const SurfaceEstimate estimate = estimate_surface(views, opt_, tables);
        estimate.report(ctx);
        char what[160];
        std::snprintf(what, sizeof what,
                      "the hull at resolution %d (about %.1f million surface cells) and the stages after it",
                      estimate.resolution, estimate.surface_cells / 1e6);
        check_memory_estimate(std::uint64_t(estimate.peak_bytes()), what, "lower the resolution");
        auto [vol, st] = carve(views, opt_, tables, ctx.progress("carving"));
        // voxel_ratio decides when given, so `--set hull.voxel_ratio=4` works on a pipeline
        // file that names a resolution; say so when the two differ.
        if (opt_.voxel_ratio > 0 && params().explicitly_set("resolution") && st.resolution != opt_.resolution)
            ctx.warn("voxel_ratio " + std::to_string(*opt_.voxel_ratio) + " decides the resolution: " +
                     std::to_string(st.resolution) + " cells, not the " + std::to_string(opt_.resolution) + " given");
        if (st.box_estimated)
            ctx.info("no bounds given: carving the estimated box [" + std::to_string(st.box_min.x) + ", " +
                     std::to_string(st.box_min.y) + ", " + std::to_string(st.box_min.z) + "] - [" +
                     std::to_string(st.box_max.x) + ", " + std::to_string(st.box_max.y) + ", " +
                     std::to_string(st.box_max.z) + "]");
        st.report(ctx);
        return std::shared_ptr<const Volume>(vol);
    }
};

} // namespace

Stage* make_hull_carve() { return new HullCarve; }

} // namespace cm
