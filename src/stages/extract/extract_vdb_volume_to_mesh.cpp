// extract.vdb_volume_to_mesh: OpenVDB's mesher (tools::volumeToMesh) on a level set made
// from the hull's exact crossings, quads split into triangles, oriented outward.
#include <cmath>
#include <string>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "geometry/mesh_check.h"
#include "mesh_report.h"
#include "vdb_mesher.h"

namespace cm {
namespace {

class ExtractVdbVolumeToMesh : public Stage {
    VdbMesherOptions opt_;
    MeshCheckMode check_ = MeshCheckMode::Auto;

public:
    StageSignature signature() const override {
        return {"extract.vdb_volume_to_mesh",
                "OpenVDB's adaptive mesher (tools::volumeToMesh) on a level set of the hull, as triangles",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections, or not)"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        b.add(opt_.adaptivity,
              ParamSpec::Float("adaptivity", 0.0, 0.0, 1.0, "",
                               "volumeToMesh adaptivity: 0 one quad per crossed edge, towards 1 flat regions "
                               "merge into larger polygons"));
        b.add(opt_.isovalue, ParamSpec::Float("isovalue", 0.0, -1e9, 1e9, "world units",
                                              "surface level: 0 the hull, positive grows it, negative shrinks it "
                                              "(beyond one cell the level set has no more detail)"));
        b.add(opt_.use_crossings,
              ParamSpec::Bool("crossings", true,
                              "build the level set from the exact crossings (false: every crossing at its edge "
                              "midpoint)"));
        b.add(opt_.relax, ParamSpec::Bool("relax", true,
                                          "volumeToMesh relaxDisorientedTriangles: smooth triangles whose normals "
                                          "disagree with the level set's gradient (adaptive meshes)"));
        declare_check(b, check_);
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        if (std::abs(opt_.isovalue) >= vol->voxel_size())
            throw Error("isovalue " + std::to_string(opt_.isovalue) + " is not within one cell (" +
                        std::to_string(vol->voxel_size()) + " world units) of the hull: the level set holds no " +
                        "surface there");
        ctx.progress(0.05, "level set");
        VdbMesherStats st;
        auto mesh = std::make_shared<Mesh>(vdb_volume_to_mesh(*vol, opt_, &st));
        ctx.progress(0.9, "check");
        ctx.metric("faces", double(mesh->face_count()));
        ctx.metric("vertices", double(mesh->vertex_count()));
        ctx.metric("quads", double(st.quads));
        ctx.metric("triangles", double(st.triangles));
        ctx.metric("level_set_bytes", double(st.level_set_bytes));
        ctx.metric("refined", vol->crossings && opt_.use_crossings ? "yes" : "no");
        report_mesh_check(*mesh, check_, ctx);
        return std::shared_ptr<const Mesh>(mesh);
    }
};

} // namespace

Stage* make_extract_vdb_volume_to_mesh() { return new ExtractVdbVolumeToMesh; }

} // namespace cm
