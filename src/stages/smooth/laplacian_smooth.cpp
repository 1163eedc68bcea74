// mesh.laplacian_smooth: the paper's umbrella operator (method step 4),
// V' = V + factor * (1/N) sum_j (V_j - V), iterated with Jacobi updates.
#include "smooth_stage.h"

namespace cm {
namespace {

class LaplacianSmooth : public Stage {
    SmoothCommon common_;
    double factor_ = 1.0;

public:
    StageSignature signature() const override {
        return {"mesh.laplacian_smooth",
                "Umbrella-operator Laplacian smoothing (the paper's step 4), optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        common_.declare(b, 10);
        b.add(factor_, ParamSpec::Float("factor", 1.0, 0.0, 1.0, "",
                                        "fraction of the umbrella step taken per iteration (1: the paper's operator)"));
    }
    void check() override {
        if (factor_ <= 0.0) throw Error("factor must be in (0, 1], got 0");
    }
    Data run(const Inputs& in, Context& ctx) override {
        SmoothOptions opt;
        opt.method = SmoothOptions::Method::Laplacian;
        opt.factor = factor_;
        return common_.run(in, ctx, opt);
    }
};

} // namespace

Stage* make_mesh_laplacian_smooth() { return new LaplacianSmooth; }

} // namespace cm
