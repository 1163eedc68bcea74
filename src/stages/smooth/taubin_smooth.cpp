// mesh.taubin_smooth: lambda|mu smoothing (Taubin 1995). Each iteration takes a
// shrinking umbrella step (lambda > 0) and an inflating one (mu < -lambda), so
// the low frequencies of the shape, and its volume, are kept.
#include <cmath>
#include <sstream>

#include "smooth_stage.h"

namespace cm {
namespace {

class TaubinSmooth : public Stage {
public:
    StageInfo info() const override {
        auto params = smooth_common_params(10);
        params.push_back(ParamSpec::Float("lambda", 0.63, 0.0, 1.0, "", "shrinking step, in (0, 1)"));
        params.push_back(ParamSpec::Float("mu", -0.67, -1.0, 0.0, "", "inflating step, in (-1, 0) with |mu| > lambda"));
        return {"mesh.taubin_smooth",
                "Taubin lambda|mu smoothing: removes noise without shrinking, optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh, params};
    }
    void check() override {
        const double l = params_.get_float("lambda"), m = params_.get_float("mu");
        if (l <= 0.0 || m >= 0.0 || -m <= l) {
            std::ostringstream s;
            s << "lambda must be > 0 and mu < -lambda, got lambda " << l << " and mu " << m;
            throw Error(s.str());
        }
    }
    Data run(const Inputs& in, Context& ctx) override {
        SmoothOptions opt;
        opt.method = SmoothOptions::Method::Taubin;
        opt.lambda = params_.get_float("lambda");
        opt.mu = params_.get_float("mu");
        return run_smooth_stage(in, ctx, params_, opt);
    }
};

} // namespace

Stage* make_mesh_taubin_smooth() { return new TaubinSmooth; }

} // namespace cm
