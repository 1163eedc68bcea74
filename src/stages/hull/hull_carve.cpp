// hull.carve: the coarse visual hull (paper step 1) in a sparse OpenVDB grid.
#include "carve.h"
#include "core/stage.h"
#include "geometry/visual_hull.h"
#include "io/limits.h"

#include <cstdint>
#include <cstdio>

namespace cm {
namespace {

class HullCarve : public Stage {
    Param<int> resolution_;
    std::optional<double> voxel_ratio_;

public:
    StageSignature signature() const override {
        return {
            "hull.carve",
            "Carve the visual hull of the views' silhouettes into a sparse grid (tiles inside, leaves at the surface)",
            {{"views", DataKind::Views, "the views whose silhouettes are carved"}},
            DataKind::Volume};
    }
    void declare(ParamBinder& b) override {
        b.add(resolution_, ParamSpec::Int("resolution", 256, 8, 16384, "cells",
                                          "grid cells along the longest side of the object's bounding box"));
        b.add(voxel_ratio_, ParamSpec::Float("voxel_ratio", 4.0, 0.01, 1024.0, "px",
                                             "image pixels per grid cell in the finest view (the paper's 4x/8x coarser "
                                             "grid); when set it decides the resolution")
                                .optional());
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto views = in.get<Views>("views");
        CarveOptions opt;
        opt.resolution = resolution_;
        if (voxel_ratio_) opt.voxel_ratio = *voxel_ratio_;
        // Refuse before anything large is allocated: a one-line change of the resolution
        // can ask for more memory than the machine has (the stages after the carve hold
        // about kPipelineBytesPerSurfaceCell per surface cell).
        // The silhouettes' summed-area tables, made once for every hull of this stage (the
        // estimate's, the box estimate's and the carving's) and carried on in the volume.
        const auto tables = silhouette_tables(*views);
        int res = 0;
        const double cells = estimate_surface_cells(views, opt, &res, 64, tables);
        const double bytes = cells * kPipelineBytesPerSurfaceCell;
        ctx.metric("estimated_surface_cells", cells);
        ctx.metric("estimated_peak_bytes", bytes);
        char what[160];
        std::snprintf(what, sizeof what,
                      "the hull at resolution %d (about %.1f million surface cells) and the stages after it", res,
                      cells / 1e6);
        check_memory_estimate(std::uint64_t(bytes), what, "lower the resolution");
        CarveStats st;
        auto vol = carve(
            views, opt, [&](double f) { ctx.progress(f, "carving"); }, &st, tables);
        // voxel_ratio decides when given, so `--set hull.voxel_ratio=4` works on a pipeline
        // file that names a resolution; say so when the two differ.
        if (opt.voxel_ratio > 0 && resolution_.given && st.resolution != opt.resolution)
            ctx.warn("voxel_ratio " + std::to_string(opt.voxel_ratio) + " decides the resolution: " +
                     std::to_string(st.resolution) + " cells, not the " + std::to_string(opt.resolution) + " given");
        if (st.box_estimated) {
            ctx.info("no bounds given: carving the estimated box [" + std::to_string(st.box_min.x) + ", " +
                     std::to_string(st.box_min.y) + ", " + std::to_string(st.box_min.z) + "] - [" +
                     std::to_string(st.box_max.x) + ", " + std::to_string(st.box_max.y) + ", " +
                     std::to_string(st.box_max.z) + "]");
            if (st.box_touched)
                ctx.warn(
                    "the hull reaches the edge of the region the cameras were searched in; give bounds in the "
                    "manifest to be sure nothing is cut");
        }
        const auto& tree = vol->occupancy->tree();
        ctx.metric("resolution", double(st.resolution));
        ctx.metric("voxel_size", st.voxel_size);
        ctx.metric("active_voxels", double(tree.activeVoxelCount()));
        ctx.metric("active_tiles", double(tree.activeTileCount()));
        ctx.metric("leaf_count", double(tree.leafCount()));
        ctx.metric("grid_bytes", double(tree.memUsage()));
        return std::shared_ptr<const Volume>(vol);
    }
};

} // namespace

Stage* make_hull_carve() { return new HullCarve; }

} // namespace cm
