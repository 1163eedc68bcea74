// mesh.taubin_smooth: lambda|mu smoothing (Taubin 1995). Each iteration takes a
// shrinking umbrella step (lambda > 0) and an inflating one (mu < -lambda), so
// the low frequencies of the shape, and its volume, are kept.
#include <cmath>
#include <sstream>

#include "smooth_stage.h"

namespace cm {
namespace {

class TaubinSmooth : public Stage {
    SmoothCommon common_;
    double lambda_ = 0.63, mu_ = -0.67;

public:
    StageSignature signature() const override {
        return {"mesh.taubin_smooth",
                "Taubin lambda|mu smoothing: removes noise without shrinking, optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        common_.declare(b, 10);
        b.add(lambda_, ParamSpec::Float("lambda", 0.63, 0.0, 1.0, "", "shrinking step, in (0, 1)"));
        b.add(mu_, ParamSpec::Float("mu", -0.67, -1.0, 0.0, "", "inflating step, in (-1, 0) with |mu| > lambda"));
    }
    void check() override {
        if (lambda_ <= 0.0 || mu_ >= 0.0 || -mu_ <= lambda_) {
            std::ostringstream s;
            s << "lambda must be > 0 and mu < -lambda, got lambda " << lambda_ << " and mu " << mu_;
            throw Error(s.str());
        }
    }
    Data run(const Inputs& in, Context& ctx) override {
        SmoothOptions opt;
        opt.method = SmoothOptions::Method::Taubin;
        opt.lambda = lambda_;
        opt.mu = mu_;
        return common_.run(in, ctx, opt);
    }
};

} // namespace

Stage* make_mesh_taubin_smooth() { return new TaubinSmooth; }

} // namespace cm
