// mesh.laplacian_smooth: the paper's umbrella operator (method step 4),
// V' = V + factor * (1/N) sum_j (V_j - V), iterated with Jacobi updates.
#include "smooth_stage.h"

namespace cm {
namespace {

class LaplacianSmooth : public Stage {
    SmoothOptions opt_;

public:
    StageSignature signature() const override {
        return {"mesh.laplacian_smooth",
                "Umbrella-operator Laplacian smoothing (the paper's step 4), optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        opt_.declare_common(b);
        opt_.declare_laplacian(b);
    }
    void check() override {
        if (opt_.factor <= 0.0) throw Error("factor must be in (0, 1], got 0");
    }
    Data run(const Inputs& in, Context& ctx) override { return run_smooth(in, ctx, opt_); }
};

} // namespace

Stage* make_mesh_laplacian_smooth() { return new LaplacianSmooth; }

} // namespace cm
