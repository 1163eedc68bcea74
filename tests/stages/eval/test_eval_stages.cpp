// The eval stages (eval.silhouette_error, eval.preview) through the host.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/stage.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "metrics/silhouette_error.h"
#include "preview_sheet.h"
#include "render/raster.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using nlohmann::json;

namespace {

// The silhouette of `mesh` (inside the box -1..1) drawn from the front, size x size px.
View front_view_of(const Mesh& mesh, int size) {
    View v;
    v.name = "front";
    v.width = v.height = size;
    v.camera = framed_camera(*Camera::named("front"), {-1, -1, -1}, {1, 1, 1}, size, size);
    const auto m = render_mask(mesh, v.camera, size, size);
    v.coverage = Coverage(std::vector<float>(m.begin(), m.end()), v.width, v.height);
    return v;
}

} // namespace

TEST(EvalStages, SilhouetteErrorReportsPerViewAndOverall) {
    const Mesh box = test::make_box({-1, -1, -1}, {1, 1, 1});
    auto views = std::make_shared<Views>();
    for (const char* name : {"front", "right"}) {
        View v;
        v.name = name;
        v.width = v.height = 100;
        v.camera = framed_camera(*Camera::named(name), {-1, -1, -1}, {1, 1, 1}, 100, 100);
        const auto m = render_mask(box, v.camera, 100, 100);
        v.coverage = Coverage(std::vector<float>(m.begin(), m.end()), v.width, v.height);
        views->views.push_back(v);
    }
    test::StageHarness h("eval.silhouette_error");
    h.params("{max_xor_pct: -1}");
    h.input("mesh", box);
    h.input("views", views);
    auto rep = h.run<Report>();
    const json j = json::parse(rep->json);
    EXPECT_EQ(j["xor_pct"].get<double>(), 0.0);
    EXPECT_EQ(j["views"].size(), 2u);
    const auto& m = h.metrics();
    for (const char* k : {"xor_pct", "mean_iou", "xor_pct.front", "iou.right", "views"}) EXPECT_TRUE(m.count(k)) << k;
    EXPECT_EQ(json::parse(m.at("xor_pct")).get<double>(), 0.0);

    // A limit turns a bad result into a failed run.
    Mesh moved = box;
    for (auto& q : moved.positions) q.y += 0.5f;
    h.params("{max_xor_pct: 1}");
    h.input("mesh", moved);
    EXPECT_THROW(h.run<Report>(), Error);
}

TEST(EvalStages, PreviewWritesThroughTheHost) {
    test::TempDir dir("eval_preview");
    const Mesh box = test::make_box({-1, -1, -1}, {1, 1, 1});
    auto views = std::make_shared<Views>();
    views->views.push_back(front_view_of(box, 64));
    test::StageHarness h("eval.preview");
    h.param("path", dir / "sheet.png").params("{panel: 64}");
    h.input("mesh", box);
    h.input("views", views);
    h.keep_staged(); // as the host has it before the run commits
    auto files = h.run<FileOutput>();
    ASSERT_EQ(h.staged().size(), 1u);
    const auto& [staged, final_path] = h.staged()[0];
    ASSERT_EQ(files->paths.size(), 1u);
    EXPECT_EQ(final_path, dir / "sheet.png");
    // The stage wrote a temporary file for the host to rename; it is a readable PNG.
    const Image sheet = read_image(staged);
    EXPECT_EQ(sheet.width, 3 * 64 + 4 * 8);
    h.param("path", dir / "sheet.jpg");
    EXPECT_THROW(h.configure(), Error);
}

TEST(EvalStages, PreviewShowsAWhiteMeshOnTheWhitePage) {
    // A white-painted box (line art textures white): its column on the sheet must show it.
    Mesh box = test::make_box({-1, -1, -1}, {1, 1, 1});
    box.colors.assign(box.positions.size(), {1.0f, 1.0f, 1.0f});
    Views views;
    views.views.push_back(front_view_of(box, 64));
    PreviewOptions opt;
    opt.panel = 64;
    const Image sheet = make_preview_sheet(box, views, opt).value;
    std::size_t covered = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) covered += views.views[0].inside(x, y) ? 1 : 0;
    ASSERT_GT(covered, 1000u);
    // The panel of the mesh: the second of the row, below the header's two lines and the
    // view's own (64 px panels: gaps of 8 px, lines of 7 + 2 * 8 px).
    const int gap = 8, line = 7 + 2 * gap, px = 2 * gap + 64, py = 3 * line;
    std::size_t shown = 0, page = 0;
    for (int y = py; y < py + 64; ++y)
        for (int x = px; x < px + 64; ++x) {
            const float lo = std::min({sheet.at(x, y, 0), sheet.at(x, y, 1), sheet.at(x, y, 2)});
            (lo < 0.97f ? shown : page) += 1;
        }
    EXPECT_GE(double(shown), 0.9 * double(covered)) << "page pixels " << page;
    EXPECT_GT(page, 0u); // the page around the mesh stays white
}
