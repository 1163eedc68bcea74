// extract.dual_marching_cubes: dual contouring on exact Hermite data. One vertex per disc
// of surface in a cell, on the creases and corners the crossings' normals describe.
#include <string>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "dual_mc.h"
#include "geometry/mesh_check.h"
#include "mesh_report.h"

namespace cm {
namespace {

class ExtractDualMarchingCubes : public Stage {
    DualMcOptions opt_;
    MeshCheckMode check_ = MeshCheckMode::Auto;

public:
    StageSignature signature() const override {
        return {"extract.dual_marching_cubes",
                "Dual Marching Cubes on the exact crossings and normals: vertices on the hull's creases and corners",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections)"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        using Ambiguity = MarchingCubesOptions::Ambiguity;
        using Normals = DualMcOptions::Normals;
        b.add(opt_.normals,
              ParamSpec::Enum("normals", "auto", {"auto", "views", "mesh"},
                              "crossing normals: auto uses the volume's stored normals, else the views' outlines "
                              "(exact), else mesh; views requires the views; mesh approximates them from the "
                              "Marching Cubes surface"),
              {Normals::Auto, Normals::Views, Normals::Mesh});
        b.add(opt_.normal_px,
              ParamSpec::Float("normal_px", 3.0, 0.0, 64.0, "px",
                               "normals from the views: the outline's direction averaged over a disc of this "
                               "radius (follows the drawn shape, not a mask's pixel steps); 0: at the point"));
        b.add(opt_.max_error,
              ParamSpec::Float("max_error", 0.2, 0.0, 16.0, "cell",
                               "adaptivity: cells merge up an octree into one vertex while it stays within this "
                               "distance of every crossing's tangent plane and the topology is kept; 0: one "
                               "vertex per disc of every cell"));
        b.add(opt_.singular_ratio,
              ParamSpec::Float("singular_ratio", 0.1, 0.0, 1.0, "",
                               "QEF eigenvalues below this fraction of the largest are dropped: larger keeps "
                               "vertices of weakly curved patches near the crossings' mean, smaller sharpens"));
        b.add(opt_.mc.ambiguity,
              ParamSpec::Enum("ambiguity", "geometric", {"geometric", "separate", "join"},
                              "ambiguous cell faces, as extract.marching_cubes: geometric pairs the crossings by "
                              "the shorter cut; separate keeps diagonal inside corners apart; join connects them"),
              {Ambiguity::Geometric, Ambiguity::Separate, Ambiguity::Join});
        b.add(opt_.mc.use_thin,
              ParamSpec::Bool("thin_parts", true,
                              "keep parts thinner than a cell that the refinement found between grid points"));
        declare_check(b, check_);
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        if (!vol->crossings)
            ctx.warn(
                "the volume is not refined: the vertices are placed from edge midpoints (connect "
                "hull.marching_intersections before this stage)");
        DualMcOptions opt = opt_;
        opt.progress = [&](double f) { ctx.progress(f, "dual marching cubes"); };
        DualMcStats st;
        auto mesh = std::make_shared<Mesh>(dual_marching_cubes(*vol, opt, &st));
        if (mesh->triangles.empty())
            throw Error("the volume has no surface: its occupancy holds no inside point (is the hull empty?)");
        ctx.metric("faces", double(mesh->face_count()));
        ctx.metric("vertices", double(mesh->vertex_count()));
        ctx.metric("quads", double(st.quads));
        ctx.metric("other_polygons", double(st.other_polygons));
        ctx.metric("multi_disc_cells", double(st.multi_disc_cells));
        ctx.metric("split_loops", double(st.split_loops));
        ctx.metric("clamped", double(st.clamped));
        ctx.metric("flat_vertices", double(st.rank[1]));
        ctx.metric("crease_vertices", double(st.rank[2]));
        ctx.metric("corner_vertices", double(st.rank[3]));
        ctx.metric("normals", st.normals);
        ctx.metric("merged", double(st.merged));
        ctx.metric("levels", double(st.levels));
        ctx.metric("guard_rounds", double(st.guard_rounds));
        ctx.metric("thin_points", double(st.mc.thin_points));
        if (st.mc.missing_crossings)
            ctx.warn(std::to_string(st.mc.missing_crossings) +
                     " crossed edge(s) have no crossing in the refined volume; their crossings sit at the edge "
                     "midpoint");
        report_mesh_check(*mesh, check_, ctx);
        return std::shared_ptr<const Mesh>(mesh);
    }
};

} // namespace

Stage* make_extract_dual_marching_cubes() { return new ExtractDualMarchingCubes; }

} // namespace cm
