// mesh.reduce: the paper's polygon reduction (method step 5). A vertex is a
// candidate while the normals of its faces stay within max_angle_deg of each
// other; the least important go first, I(V) = arccos(<N_a, N_b>) * sum_j |V_j - V|.
#include <memory>

#include "decimate_stage.h"
#include "core/mesh.h"
#include "mesh_decimate.h"
#include "core/stage.h"

namespace cm {
namespace {

class MeshReduce : public Stage {
public:
    StageInfo info() const override {
        auto params = face_target_params(0.0);
        params.insert(params.begin(),
                      ParamSpec::Float("max_angle_deg", 15.0, 0.1, 89.0, "deg",
                                       "largest angle between the face normals around a removable vertex "
                                       "(the paper: 5 to 40; larger reduces more)"));
        params.push_back(ParamSpec::Float("max_aspect_ratio", 0.0, 0.0, 1e6, "",
                                          "refuse collapses that make a face thinner than this (1 = equilateral); "
                                          "0: off, as in the paper"));
        params.push_back(crossing_guard_param());
        return {"mesh.reduce",
                "The paper's importance-based polygon reduction: flat regions lose triangles, sharp borders stay",
                {{"mesh", DataKind::Mesh, "the mesh to reduce (closed 2-manifold parts are reduced; "
                                          "vertices on boundaries or non-manifold edges stay)"}},
                DataKind::Mesh, params};
    }
    void check() override {
        check_face_target(params_);
    }
    Data run(const Inputs& in, Context& ctx) override {
        auto src = in.get<Mesh>("mesh");
        auto out = std::make_shared<Mesh>();
        ReduceOptions opt;
        opt.max_angle_deg = params_.get_float("max_angle_deg");
        opt.max_aspect_ratio = params_.get_float("max_aspect_ratio");
        opt.target_faces = face_target(params_, src->face_count());
        opt.no_crossings = params_.get_bool("guard");
        opt.progress = [&ctx](double f) { ctx.progress(f, "reducing"); };
        const DecimateStats st = reduce_mesh(*src, *out, opt);
        report_decimation(ctx, st, *out);
        return std::shared_ptr<const Mesh>(std::move(out));
    }
};

} // namespace

Stage* make_mesh_reduce() { return new MeshReduce; }

} // namespace cm
