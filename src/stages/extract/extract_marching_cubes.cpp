// extract.marching_cubes: the volume's boundary as a closed, 2-manifold, outward
// triangle mesh (paper step 3), with vertices at the exact crossings when refined.
#include "core/mesh.h"
#include "core/stage.h"
#include "core/volume.h"
#include "marching_cubes.h"
#include "mesh_report.h"

namespace cm {
namespace {

class ExtractMarchingCubes : public Stage {
    MarchingCubesOptions opt_;
    MeshCheckOptions check_;

public:
    StageSignature signature() const override {
        return {"extract.marching_cubes",
                "Marching Cubes over the sparse hull: a closed, manifold, outward triangle mesh at the exact crossings",
                {{"volume", DataKind::Volume, "the hull (refined by hull.marching_intersections, or not)"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        opt_.declare(b);
        check_.declare(b);
    }

    Data run(const Inputs& in, Context& ctx) override {
        auto vol = in.get<Volume>("volume");
        if (!vol->occupancy) throw Error("the volume has no occupancy grid");
        return extracted_mesh(marching_cubes(*vol, opt_, ctx.progress("marching cubes")), check_, ctx);
    }
};

} // namespace

Stage* make_extract_marching_cubes() { return new ExtractMarchingCubes; }

} // namespace cm
