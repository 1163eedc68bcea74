// extract.dual_marching_cubes: dual contouring on exact Hermite data. One vertex per disc
// of surface in a cell, on the creases and corners the crossings' normals describe.
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "dual_mc.h"
#include "mesh_report.h"

namespace cm {
namespace {

class ExtractDualMarchingCubes : public ExtractorStage<DualMcOptions> {
public:
    StageSignature signature() const override {
        return {"extract.dual_marching_cubes",
                "Dual Marching Cubes on the exact crossings and normals: vertices on the hull's creases and corners",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections)"}},
                DataKind::Mesh};
    }

protected:
    Data extract(const Volume& vol, Context& ctx) override {
        if (!vol.crossings)
            ctx.warn(
                "the volume is not refined: the vertices are placed from edge midpoints (connect "
                "hull.marching_intersections before this stage)");
        return extracted_mesh(dual_marching_cubes(vol, opt_, ctx.progress("dual marching cubes")), check_, ctx);
    }
};

} // namespace

Stage* make_extract_dual_marching_cubes() { return new ExtractDualMarchingCubes; }

} // namespace cm
