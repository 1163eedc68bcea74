// extract.marching_cubes: the volume's boundary as a closed, 2-manifold, outward
// triangle mesh (paper step 3), with vertices at the exact crossings when refined.
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "marching_cubes.h"
#include "mesh_report.h"

namespace cm {
namespace {

class ExtractMarchingCubes : public ExtractorStage<MarchingCubesOptions> {
public:
    StageSignature signature() const override {
        return {"extract.marching_cubes",
                "Marching Cubes over the sparse hull: a closed, manifold, outward triangle mesh at the exact crossings",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections, or not)"}},
                DataKind::Mesh};
    }

protected:
    Data extract(const Volume& vol, Context& ctx) override {
        return extracted_mesh(marching_cubes(vol, opt_, ctx.progress("marching cubes")), check_, ctx);
    }
};

} // namespace

Stage* make_extract_marching_cubes() { return new ExtractMarchingCubes; }

} // namespace cm
