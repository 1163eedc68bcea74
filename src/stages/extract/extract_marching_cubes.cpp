// extract.marching_cubes: the volume's boundary as a closed, 2-manifold, outward
// triangle mesh (paper step 3), with vertices at the exact crossings when refined.
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "geometry/mesh_check.h"
#include "marching_cubes.h"
#include "mesh_report.h"

namespace cm {
namespace {

class ExtractMarchingCubes : public Stage {
    MarchingCubesOptions opt_;
    MeshCheckMode check_ = MeshCheckMode::Auto;

public:
    StageSignature signature() const override {
        return {"extract.marching_cubes",
                "Marching Cubes over the sparse hull: a closed, manifold, outward triangle mesh at the exact crossings",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections, or not)"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        using Ambiguity = MarchingCubesOptions::Ambiguity;
        b.add(opt_.ambiguity,
              ParamSpec::Enum("ambiguity", "geometric", {"geometric", "separate", "join"},
                              "ambiguous faces: geometric pairs the crossings by the shorter cut; separate keeps "
                              "diagonal inside corners apart; join connects them"),
              {Ambiguity::Geometric, Ambiguity::Separate, Ambiguity::Join});
        b.add(opt_.use_crossings,
              ParamSpec::Bool("crossings", true,
                              "place vertices at the volume's exact crossings (false: edge midpoints, plain "
                              "binary Marching Cubes)"));
        b.add(opt_.use_thin,
              ParamSpec::Bool("thin_parts", true,
                              "keep parts thinner than a cell that the refinement found between grid points"));
        b.add(opt_.min_edge_fraction,
              ParamSpec::Float("min_edge_fraction", 0.01, 0.0001, 0.25, "cell",
                               "crossings nearer than this to a grid point are moved out to it, so no two "
                               "vertices coincide"));
        declare_check(b, check_);
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        MarchingCubesOptions opt = opt_;
        opt.progress = [&](double f) { ctx.progress(f, "marching cubes"); };
        MarchingCubesStats st;
        auto mesh = std::make_shared<Mesh>(marching_cubes(*vol, opt, &st));
        if (mesh->triangles.empty())
            throw Error("the volume has no surface: its occupancy holds no inside point (is the hull empty?)");

        ctx.metric("faces", double(mesh->face_count()));
        ctx.metric("vertices", double(mesh->vertex_count()));
        ctx.metric("surface_cells", double(st.surface_cells));
        ctx.metric("blocks", double(st.blocks));
        ctx.metric("ambiguous_faces", double(st.ambiguous_faces / 2));
        ctx.metric("joined_faces", double(st.joined_faces / 2));
        ctx.metric("centroid_vertices", double(st.centroid_vertices));
        ctx.metric("thin_points", double(st.thin_points));
        ctx.metric("thin_put_back", double(st.thin_put_back));
        ctx.metric("refined", vol->crossings && opt.use_crossings ? "yes" : "no");
        if (st.missing_crossings) {
            ctx.metric("missing_crossings", double(st.missing_crossings));
            ctx.warn(
                std::to_string(st.missing_crossings) +
                " crossed edge(s) have no crossing in the refined volume; their vertices sit at the edge midpoint");
        }
        report_mesh_check(*mesh, check_, ctx);
        return std::shared_ptr<const Mesh>(mesh);
    }
};

} // namespace

Stage* make_extract_marching_cubes() { return new ExtractMarchingCubes; }

} // namespace cm
