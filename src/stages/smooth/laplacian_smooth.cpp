// mesh.laplacian_smooth: the paper's umbrella operator (method step 4),
// V' = V + factor * (1/N) sum_j (V_j - V), iterated with Jacobi updates.
#include "smooth_stage.h"

namespace cm {
namespace {

class LaplacianSmooth : public Stage {
public:
    StageInfo info() const override {
        auto params = smooth_common_params(10);
        params.push_back(ParamSpec::Float("factor", 1.0, 0.0, 1.0, "",
                                          "fraction of the umbrella step taken per iteration (1: the paper's operator)"));
        return {"mesh.laplacian_smooth",
                "Umbrella-operator Laplacian smoothing (the paper's step 4), optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh, params};
    }
    void check() override {
        if (params_.get_float("factor") <= 0.0) throw Error("factor must be in (0, 1], got 0");
    }
    Data run(const Inputs& in, Context& ctx) override {
        SmoothOptions opt;
        opt.method = SmoothOptions::Method::Laplacian;
        opt.factor = params_.get_float("factor");
        return run_smooth_stage(in, ctx, params_, opt);
    }
};

} // namespace

Stage* make_mesh_laplacian_smooth() { return new LaplacianSmooth; }

} // namespace cm
