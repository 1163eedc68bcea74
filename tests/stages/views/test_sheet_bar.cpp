// The bar for turnaround sheets: a reconstruction from one sheet of front, right and top
// matches the one from the same three drawings as separate files (docs/results/sheet.md has
// the figures at full size).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

// xor_pct of compare --fit bbox of `mesh` against `views`.
double xor_pct(const fs::path& mesh, const fs::path& views, const fs::path& cwd) {
    const auto r = test::run_cli("compare " + mesh.string() + " " + views.string() + " --fit bbox --json", cwd);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out).at("xor_pct").get<double>();
}

// The paper pipeline on `manifest` at a small resolution, writing `mesh`.
void reconstruct(const fs::path& manifest, const fs::path& mesh, const fs::path& cwd) {
    const auto r = test::run_cli("run " + (test::source_dir() / "pipelines/paper.yaml").string() +
                                     " -q --set views.manifest=" + manifest.string() + " --set hull.resolution=96" +
                                     " --set write.path=" + mesh.string() +
                                     " --set preview.path=" + (cwd / (mesh.stem().string() + ".preview.png")).string(),
                                 cwd);
    ASSERT_EQ(r.exit_code, 0) << r.err;
}

} // namespace

TEST(SheetBar, ReconstructionFromOneSheetMatchesSeparateDrawings) {
    const fs::path spot = test::shared_dir() / "data/models/spot.obj";
    CM_SKIP_WITHOUT(spot);
    test::TempDir dir("sheet_bar");
    const auto r = test::run_cli(
        "render-views " + spot.string() + " -o views --size 256 --style art --views front,right,top --front -Z -q",
        dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::vector<Image> drawings;
    for (const char* v : {"front", "right", "top"})
        drawings.push_back(read_image(dir / "views" / (std::string(v) + ".png")));
    write_image(test::compose_sheet(drawings, 16, 16), dir / "sheet.png");
    test::write_text(dir / "sheet.yaml", "sheet: {image: sheet.png, views: [front, right, top]}\n");
    // The separate drawings aligned from their silhouettes, as the sheet's panels are.
    test::write_text(dir / "free.yaml",
                     "views:\n  front: views/front.png\n  right: views/right.png\n  top: views/top.png\n");
    reconstruct(dir / "sheet.yaml", dir / "sheet.obj", dir.path());
    reconstruct(dir / "free.yaml", dir / "free.obj", dir.path());
    reconstruct(dir / "views/views.yaml", dir / "fixed.obj", dir.path());
    const fs::path views = dir / "views/views.yaml";
    const double sheet = xor_pct(dir / "sheet.obj", views, dir.path());
    const double free = xor_pct(dir / "free.obj", views, dir.path());
    const double fixed = xor_pct(dir / "fixed.obj", views, dir.path());
    RecordProperty("xor_pct_sheet", std::to_string(sheet));
    RecordProperty("xor_pct_separate_aligned", std::to_string(free));
    RecordProperty("xor_pct_separate_fixed_cameras", std::to_string(fixed));
    EXPECT_NEAR(sheet, free, 0.1);
    EXPECT_GT(sheet, 0.0); // a mesh, not the views themselves
    EXPECT_LT(sheet, 10.0);
    std::printf("xor_pct: sheet %.3f, separate (aligned) %.3f, separate (fixed cameras) %.3f\n", sheet, free, fixed);
}
