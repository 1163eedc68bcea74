// mesh.reduce: the paper's polygon reduction (method step 5). A vertex is a
// candidate while the normals of its faces stay within max_angle_deg of each
// other; the least important go first, I(V) = arccos(<N_a, N_b>) * sum_j |V_j - V|.
#include <memory>

#include "core/mesh.h"
#include "core/stage.h"
#include "decimate_stage.h"
#include "mesh_decimate.h"

namespace cm {
namespace {

class MeshReduce : public Stage {
    ReduceOptions opt_;
    FaceTarget target_;

public:
    StageSignature signature() const override {
        return {"mesh.reduce",
                "The paper's importance-based polygon reduction: flat regions lose triangles, sharp borders stay",
                {{"mesh", DataKind::Mesh,
                  "the mesh to reduce (closed 2-manifold parts are reduced; "
                  "vertices on boundaries or non-manifold edges stay)"}},
                DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        b.add(opt_.max_angle_deg, ParamSpec::Float("max_angle_deg", 15.0, 0.1, 89.0, "deg",
                                                   "largest angle between the face normals around a removable vertex "
                                                   "(the paper: 5 to 40; larger reduces more)"));
        target_.declare(b, 0.0);
        b.add(opt_.max_aspect_ratio, ParamSpec::Float("max_aspect_ratio", 0.0, 0.0, 1e6, "",
                                                      "refuse collapses that make a face thinner than this (1 = "
                                                      "equilateral); 0: off, as in the paper"));
        b.add(opt_.no_crossings, crossing_guard_param());
    }
    void check() override { target_.check(); }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        auto out = std::make_shared<Mesh>();
        ReduceOptions opt = opt_;
        opt.target_faces = target_.count(src->face_count());
        opt.progress = [&ctx](double f) { ctx.progress(f, "reducing"); };
        const DecimateStats st = reduce_mesh(*src, *out, opt);
        report_decimation(ctx, st, *out);
        return std::shared_ptr<const Mesh>(std::move(out));
    }
};

} // namespace

Stage* make_mesh_reduce() { return new MeshReduce; }

} // namespace cm
