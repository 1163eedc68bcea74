#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/mesh.h"
#include "core/views.h"
#include "render/colour.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "texture_views.h"

using namespace cm;
using test::Rgb;

namespace {

const Rgb kFill{0.90f, 0.25f, 0.60f}; // a pink marker

// A box's front in a flat colour hatched over in black ink (diagonal strokes 2 px wide), with
// the paper showing through between the fill's strokes (1 px, white), every `period` px.
std::shared_ptr<Views> hatched_front(int period) {
    View v = test::painted_view("front", 160, 64, test::box_outline({-1, -1, -1}, {1, 1, 1}, Camera::named("front")->d),
                                [](const Vec3d&) { return kFill; });
    for (int j = 0; j < v.height; ++j)
        for (int i = 0; i < v.width; ++i) {
            if (!v.inside(i, j)) continue;
            const int phase = (i + j) % period;
            for (int k = 0; k < 3; ++k) {
                if (phase < 2) v.image.at(i, j, k) = 0.08f;
                if (phase == 4) v.image.at(i, j, k) = 1.0f;
            }
        }
    return test::make_views({std::move(v)}, {-1, -1, -1}, {1, 1, 1});
}

// Mean and worst delta E against the fill over the texels of the faces facing the view.
std::pair<double, double> front_error(const Mesh& m) {
    double sum = 0, worst = 0;
    int n = 0;
    const double bary[4][3] = {{1 / 3.0, 1 / 3.0, 1 / 3.0}, {0.6, 0.2, 0.2}, {0.2, 0.6, 0.2}, {0.2, 0.2, 0.6}};
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
        const auto& t = m.triangles[f];
        const Vec3d a(m.positions[t[0]]), b(m.positions[t[1]]), c(m.positions[t[2]]);
        if (dot(normalize(cross(b - a, c - a)), -Camera::named("front")->d) < 0.99) continue;
        for (const auto& w : bary) {
            const auto uv = test::uv_at(m, f, w[0], w[1], w[2]);
            const double de = delta_e76(test::texel(*m.texture, uv[0], uv[1]), kFill);
            sum += de;
            worst = std::max(worst, de);
            ++n;
        }
    }
    return {n ? sum / n : 1e9, worst};
}

std::shared_ptr<const Mesh> texture(const std::string& params, int period, double* slivers = nullptr) {
    test::StageHarness h("texture.project");
    h.params(params).input("mesh", test::make_grid_box(-1, 1, 8)).input("views", hatched_front(period));
    auto out = h.run<Mesh>();
    if (slivers) *slivers = nlohmann::json::parse(h.metrics().at("paper_sliver_pixels")).at("front").get<double>();
    return out;
}

} // namespace

TEST(TextureStrokes, AHatchedFlatColourSquareTexturesToItsFill) {
    // Dense (the strokes' fringes meet) and sparse hatching.
    for (int period : {7, 12}) {
        double slivers = 0;
        const auto [mean, worst] = front_error(*texture("{texture_size: 256, padding: 2}", period, &slivers));
        EXPECT_LT(mean, 3.0) << period;
        EXPECT_LT(worst, 6.0) << period;
        EXPECT_GT(slivers, 128.0 * 128.0 / period / 2) << period; // the report counts them
    }
}

TEST(TextureStrokes, ThePaperBetweenStrokesTakenAsDrawnPalesTheTexture) {
    // The ink alone left out (sparse hatching, where that still finds the strokes): the white
    // slivers stay in the texture.
    const auto [mean, worst] =
        front_error(*texture("{texture_size: 256, padding: 2, paper_slivers: false, fill_smooth: 0}", 12));
    EXPECT_GT(worst, 20.0);
    EXPECT_GT(mean, 3.0);
}
