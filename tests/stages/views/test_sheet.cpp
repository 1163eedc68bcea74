// Turnaround sheets: panels found on one drawing, each a view; the manifest's sheet form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "load.h"
#include "render/raster.h"
#include "sheet.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;
namespace fs = std::filesystem;

namespace {

// A binary drawing of `mesh` from a named view, framed on a size x size canvas.
struct Drawing {
    int size = 0;
    std::vector<std::uint8_t> mask;
};

Drawing draw(const Mesh& mesh, const std::string& view, int size) {
    Vec3f lo, hi;
    mesh.bounds(lo, hi);
    const Camera cam = framed_camera(*Camera::named(view), {lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}, size, size);
    return {size, render_mask(mesh, cam, size, size)};
}

// A sheet on off-white paper: drawings in dark ink at given corners, and under each a
// text-like label (a row of small blocks) `label_gap` pixels below the drawing. `owner`
// says which drawing (index) a pixel belongs to, -1 for paper, -2 for a label.
struct Sheet {
    Image image;
    std::vector<int> owner;
};

Sheet compose(int w, int h, const std::vector<Drawing>& drawings, const std::vector<std::array<int, 2>>& at,
              int label_gap = 10) {
    Sheet s;
    s.image.width = w;
    s.image.height = h;
    s.image.channels = 3;
    s.image.pixels.resize(std::size_t(w) * h * 3);
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
        s.image.pixels[i * 3] = 0.95f;
        s.image.pixels[i * 3 + 1] = 0.93f;
        s.image.pixels[i * 3 + 2] = 0.88f;
    }
    s.owner.assign(std::size_t(w) * h, -1);
    auto ink = [&](int x, int y, int who) {
        const std::size_t i = std::size_t(y) * w + x;
        for (int k = 0; k < 3; ++k) s.image.pixels[i * 3 + k] = 0.25f + 0.05f * k;
        s.owner[i] = who;
    };
    for (std::size_t d = 0; d < drawings.size(); ++d) {
        const Drawing& dr = drawings[d];
        int bottom = 0, left = dr.size, right = 0;
        for (int y = 0; y < dr.size; ++y)
            for (int x = 0; x < dr.size; ++x)
                if (dr.mask[std::size_t(y) * dr.size + x]) {
                    ink(at[d][0] + x, at[d][1] + y, int(d));
                    bottom = std::max(bottom, y);
                    left = std::min(left, x);
                    right = std::max(right, x);
                }
        const int x0 = at[d][0] + (left + right) / 2 - 26, y0 = at[d][1] + bottom + 1 + label_gap;
        for (int b = 0; b < 5; ++b)
            for (int y = y0; y < y0 + 9; ++y)
                for (int x = x0 + b * 11; x < x0 + b * 11 + 7; ++x) ink(x, y, -2);
    }
    return s;
}

// IoU of a loaded view's silhouette against the sheet pixels of drawing `who`, over the
// view's crop; `outside` counts the drawing's pixels the crop misses.
double panel_iou(const View& v, const SheetPanel& p, const Sheet& s, int who, int& outside) {
    std::size_t both = 0, either = 0, in_crop = 0, total = 0;
    for (int o : s.owner) total += o == who;
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) {
            const bool a = v.inside(x, y);
            const bool b = s.owner[std::size_t(y + p.y0) * s.image.width + x + p.x0] == who;
            both += a && b;
            either += a || b;
            in_crop += b;
        }
    outside = int(total - in_crop);
    return either ? double(both) / double(either) : 0.0;
}

Sheet four_panel_sheet() {
    const Mesh m = test::make_lopsided();
    // Different scales: the right view is drawn at 0.7, the back at 1.25, the top at 0.55.
    return compose(660, 230, {draw(m, "front", 140), draw(m, "right", 98), draw(m, "back", 175), draw(m, "top", 77)},
                   {{std::array<int, 2>{10, 15}}, {170, 45}, {290, 8}, {500, 60}});
}

} // namespace

TEST(Sheet, FourPanelsWithLabelsAtDifferentScales) {
    test::TempDir dir("sheet_four");
    const Sheet s = four_panel_sheet();
    write_image(s.image, dir / "sheet.png");
    test::write_text(dir / "views.yaml", "sheet: {image: sheet.png, views: [front, right, back, top]}\n");
    const Manifest man = read_manifest(dir / "views.yaml");
    const SheetViews sv = split_sheets(man);
    // The silhouettes as extracted from the panels: reconciliation would resample them.
    LoadViewsOptions as_drawn;
    as_drawn.reconcile = "off";
    const auto [views, report] = load_views(dir / "views.yaml", as_drawn);
    ASSERT_EQ(views.views.size(), 4u);
    const char* names[] = {"front", "right", "back", "top"};
    for (int k = 0; k < 4; ++k) {
        SCOPED_TRACE(names[k]);
        const View& v = views.views[std::size_t(k)];
        EXPECT_EQ(v.name, names[k]);
        EXPECT_EQ(v.width, sv.panels[std::size_t(k)].width);
        int outside = 0;
        EXPECT_GE(panel_iou(v, sv.panels[std::size_t(k)], s, k, outside), 0.99);
        EXPECT_EQ(outside, 0);
        // No label pixel in the crop.
        const SheetPanel& p = sv.panels[std::size_t(k)];
        for (int y = p.y0; y < p.y0 + p.height; ++y)
            for (int x = p.x0; x < p.x0 + p.width; ++x)
                ASSERT_NE(s.owner[std::size_t(y) * s.image.width + x], -2) << x << "," << y;
    }
    // Aligned as separate drawings: the scales are those the panels were drawn at.
    EXPECT_NEAR(views.views[1].camera.scale / views.views[0].camera.scale, 0.7, 0.02);
    EXPECT_NEAR(views.views[2].camera.scale / views.views[0].camera.scale, 1.25, 0.02);
    EXPECT_NEAR(views.views[3].camera.scale / views.views[0].camera.scale, 0.55, 0.02);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_FALSE(report.notes.empty());
    EXPECT_NE(report.notes.front().find("4 panels"), std::string::npos) << report.notes.front();
}

TEST(Sheet, TwoRowsAreReadLeftToRightThenTopToBottom) {
    test::TempDir dir("sheet_rows");
    const Mesh m = test::make_lopsided();
    // Row one: front (left, lower), right; row two: top, back. Placed out of order in x so
    // a plain left-to-right sort would mix the rows.
    const Sheet s =
        compose(330, 330, {draw(m, "front", 120), draw(m, "right", 110), draw(m, "top", 100), draw(m, "back", 130)},
                {{std::array<int, 2>{40, 20}}, {190, 5}, {5, 175}, {150, 170}});
    write_image(s.image, dir / "sheet.png");
    test::write_text(dir / "views.yaml",
                     "sheet:\n  image: sheet.png\n  views: [front, right, top, {name: rear, view: back}]\n");
    const SheetViews sv = split_sheets(read_manifest(dir / "views.yaml"));
    // The silhouettes as extracted from the panels: reconciliation would resample them.
    LoadViewsOptions as_drawn;
    as_drawn.reconcile = "off";
    const Views views = load_views(dir / "views.yaml", as_drawn).value;
    ASSERT_EQ(views.views.size(), 4u);
    EXPECT_EQ(views.views[3].name, "rear");
    for (int k = 0; k < 4; ++k) {
        SCOPED_TRACE(k);
        int outside = 0;
        EXPECT_GE(panel_iou(views.views[std::size_t(k)], sv.panels[std::size_t(k)], s, k, outside), 0.99);
        EXPECT_EQ(outside, 0);
    }
}

TEST(Sheet, PanelCountThatDiffersFromTheViewsIsOneLineNamingBoth) {
    test::TempDir dir("sheet_count");
    const Mesh m = test::make_lopsided();
    const Sheet s = compose(420, 200, {draw(m, "front", 120), draw(m, "right", 120), draw(m, "top", 120)},
                            {{std::array<int, 2>{10, 10}}, {145, 10}, {280, 10}});
    write_image(s.image, dir / "sheet.png");
    test::write_text(dir / "views.yaml", "height: 2\nsheet: {image: sheet.png, views: [front, right, back, top]}\n");
    const std::string e = error_of([&] { load_views(dir / "views.yaml", {}); });
    EXPECT_NE(e.find("views.yaml:2: sheet \"sheet.png\" holds 3 panels but names 4 views (front, right, back, top)"),
              std::string::npos)
        << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    test::write_text(dir / "views.yaml", "sheet: {image: sheet.png, views: [front, right, top]}\n");
    EXPECT_EQ(load_views(dir / "views.yaml", {}).value.views.size(), 3u);
}

TEST(Sheet, MixesWithViewsDrawnOnTheirOwnAndSavesEachSilhouette) {
    test::TempDir dir("sheet_mixed");
    const Mesh m = test::make_lopsided();
    const Drawing front = draw(m, "front", 120);
    const Sheet one = compose(140, 160, {front}, {{std::array<int, 2>{10, 5}}});
    write_image(one.image, dir / "front.png");
    const Sheet s =
        compose(300, 160, {draw(m, "right", 120), draw(m, "top", 120)}, {{std::array<int, 2>{10, 5}}, {160, 5}});
    write_image(s.image, dir / "sheet.png");
    test::write_text(dir / "views.yaml",
                     "views:\n  front: front.png\nsheet: {image: sheet.png, views: [right, top]}\n");
    test::StageHarness h("views.load");
    h.param("manifest", dir / "views.yaml").params("{save_silhouettes: true}");
    h.side_output_dir(dir.path()).keep_staged();
    auto views = h.run<Views>();
    ASSERT_EQ(views->views.size(), 3u);
    EXPECT_EQ(views->views[0].name, "front");
    EXPECT_EQ(views->views[2].name, "top");
    const auto& staged = h.staged();
    ASSERT_EQ(staged.size(), 3u);
    EXPECT_EQ(staged[1].second, dir / "right.silhouette.png");
    EXPECT_EQ(staged[2].second, dir / "top.silhouette.png");
    const Image sil = read_image(staged[2].first);
    EXPECT_EQ(sil.width, views->views[2].width);
    EXPECT_LT(sil.width, 150); // the top panel's crop, not the sheet
    // Front (its own file) and the sheet's views agree on the shared axes: no warning.
    EXPECT_TRUE(h.warnings().empty()) << h.warnings().front();
}

TEST(Sheet, OptionsOfTheSheetApplyToEveryPanel) {
    test::TempDir dir("sheet_options");
    // An L on a 100 px canvas with a 4 px dot in its empty corner: inside the panel's crop,
    // far smaller than the drawing, so keep decides whether it is part of the silhouette.
    Drawing l{100, std::vector<std::uint8_t>(100 * 100, 0)};
    auto fill = [&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) l.mask[std::size_t(y) * 100 + x] = 1;
    };
    fill(10, 50, 90, 90);
    fill(10, 10, 30, 90);
    fill(80, 14, 84, 18);
    const Sheet s = compose(230, 140, {l, l}, {{std::array<int, 2>{5, 5}}, {120, 5}});
    write_image(s.image, dir / "sheet.png");
    for (const char* keep : {"auto", "all"}) {
        SCOPED_TRACE(keep);
        test::write_text(dir / "views.yaml",
                         std::string("sheet: {image: sheet.png, views: [front, right], keep: ") + keep + "}\n");
        const SheetViews sv = split_sheets(read_manifest(dir / "views.yaml"));
        const Views views = load_views(dir / "views.yaml", {}).value;
        ASSERT_EQ(views.views.size(), 2u);
        for (std::size_t k = 0; k < 2; ++k) {
            const SheetPanel& p = sv.panels[k];
            const int dx = 5 + int(k) * 115 + 82 - p.x0, dy = 5 + 16 - p.y0; // the dot's centre in the crop
            EXPECT_EQ(views.views[k].inside(dx, dy), std::string(keep) == "all") << k;
            EXPECT_TRUE(views.views[k].inside(dx - 60, dy + 50)) << k; // the L itself
        }
    }
    // An unreadable sheet names the manifest line and the sheet.
    test::write_text(dir / "views.yaml", "height: 1\nsheet: {image: missing.png, views: [front, right]}\n");
    const std::string e = error_of([&] { load_views(dir / "views.yaml", {}); });
    EXPECT_NE(e.find("views.yaml:2: sheet \"missing.png\": "), std::string::npos) << e;
}

TEST(Sheet, FrameAndVerticalTitleAreNotPanels) {
    // A blueprint sheet: a frame ruled around the whole sheet, the views inside it, and the
    // title written vertically beside them (letters turned a quarter, each as large as a
    // small drawing's detail). The splitter yields exactly the three panels.
    test::TempDir dir("sheet_frame");
    const Mesh m = test::make_lopsided();
    Sheet s = compose(560, 260, {draw(m, "front", 130), draw(m, "right", 110), draw(m, "top", 100)},
                      {{std::array<int, 2>{70, 40}}, {225, 50}, {370, 60}});
    auto ink = [&](int x, int y) {
        for (int k = 0; k < 3; ++k) s.image.pixels[(std::size_t(y) * s.image.width + x) * 3 + k] = 0.2f;
    };
    // The frame: 3 px, 8 px in from the sheet's edge.
    for (int y = 8; y < 252; ++y)
        for (int x = 8; x < 552; ++x)
            if (x < 11 || x >= 549 || y < 11 || y >= 249) ink(x, y);
    // The title: seven letters down the left, inside the frame (an "O", an "L" and a bar
    // in turn, turned on their side), 26 px apart.
    for (int c = 0; c < 7; ++c) {
        const int x0 = 22, y0 = 30 + 28 * c;
        for (int y = y0; y < y0 + 16; ++y)
            for (int x = x0; x < x0 + 22; ++x) {
                const bool o = c % 3 == 0 && (y < y0 + 4 || y >= y0 + 12 || x < x0 + 4 || x >= x0 + 18);
                const bool l = c % 3 == 1 && (y >= y0 + 12 || x < x0 + 4);
                const bool bar = c % 3 == 2 && y >= y0 + 6 && y < y0 + 10;
                if (o || l || bar) ink(x, y);
            }
    }
    write_image(s.image, dir / "sheet.png");
    test::write_text(dir / "views.yaml", "sheet: {image: sheet.png, views: [front, right, top]}\n");
    const SheetViews sv = split_sheets(read_manifest(dir / "views.yaml"));
    ASSERT_EQ(sv.panels.size(), 3u);
    const auto [views, report] = load_views(dir / "views.yaml", {});
    ASSERT_EQ(views.views.size(), 3u);
    for (int k = 0; k < 3; ++k) {
        SCOPED_TRACE(k);
        int outside = 0;
        EXPECT_GE(panel_iou(views.views[std::size_t(k)], sv.panels[std::size_t(k)], s, k, outside), 0.99);
        EXPECT_EQ(outside, 0);
    }
    ASSERT_FALSE(sv.notes.empty());
    EXPECT_NE(sv.notes.front().find("1 frame(s)"), std::string::npos) << sv.notes.front();
}
