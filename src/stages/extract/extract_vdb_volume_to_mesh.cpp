// extract.vdb_volume_to_mesh: OpenVDB's mesher (tools::volumeToMesh) on a level set made
// from the hull's exact crossings, quads split into triangles, oriented outward.
#include <cmath>
#include <string>

#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "mesh_report.h"
#include "vdb_mesher.h"

namespace cm {
namespace {

class ExtractVdbVolumeToMesh : public ExtractorStage<VdbMesherOptions> {
public:
    StageSignature signature() const override {
        return {"extract.vdb_volume_to_mesh",
                "OpenVDB's adaptive mesher (tools::volumeToMesh) on a level set of the hull, as triangles",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections, or not)"}},
                DataKind::Mesh};
    }

protected:
    Data extract(const Volume& vol, Context& ctx) override {
        if (std::abs(opt_.isovalue) >= vol.voxel_size())
            throw Error("isovalue " + std::to_string(opt_.isovalue) + " is not within one cell (" +
                        std::to_string(vol.voxel_size()) + " world units) of the hull: the level set holds no " +
                        "surface there");
        auto r = vdb_volume_to_mesh(vol, opt_, ctx.progress("level set"));
        ctx.progress(0.9, "check");
        return extracted_mesh(std::move(r), check_, ctx);
    }
};

} // namespace

Stage* make_extract_vdb_volume_to_mesh() { return new ExtractVdbVolumeToMesh; }

} // namespace cm
