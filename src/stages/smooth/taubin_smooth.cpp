// mesh.taubin_smooth: lambda|mu smoothing (Taubin 1995). Each iteration takes a
// shrinking umbrella step (lambda > 0) and an inflating one (mu < -lambda), so
// the low frequencies of the shape, and its volume, are kept.
#include <sstream>

#include "smooth_stage.h"

namespace cm {
namespace {

class TaubinSmooth : public Stage {
    SmoothOptions opt_;

public:
    TaubinSmooth() { opt_.method = SmoothOptions::Method::Taubin; }
    StageSignature signature() const override {
        return {"mesh.taubin_smooth",
                "Taubin lambda|mu smoothing: removes noise without shrinking, optionally kept on the visual hull",
                smooth_ports(), DataKind::Mesh};
    }
    void declare(ParamBinder& b) override {
        opt_.declare_common(b);
        opt_.declare_taubin(b);
    }
    void check() override {
        if (opt_.lambda <= 0.0 || opt_.mu >= 0.0 || -opt_.mu <= opt_.lambda) {
            std::ostringstream s;
            s << "lambda must be > 0 and mu < -lambda, got lambda " << opt_.lambda << " and mu " << opt_.mu;
            throw Error(s.str());
        }
    }
    Data run(const Inputs& in, Context& ctx) override { return run_smooth(in, ctx, opt_); }
};

} // namespace

Stage* make_mesh_taubin_smooth() { return new TaubinSmooth; }

} // namespace cm
