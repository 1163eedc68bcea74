// render-views, compare and preview from the command line.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/stage.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "io/mesh_io.h"
#include "load.h"
#include "metrics/silhouette_error.h"
#include "preview_sheet.h"
#include "render/raster.h"
#include "support/shapes.h"
#include "support/stage_harness.h"
#include "support/test_support.h"

using namespace cm;
using nlohmann::json;

namespace {

// A lopsided object (box on a sphere) so that a wrong axis or a mirror would show.
Mesh lopsided() { return test::make_lopsided(); }

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

json compare_json(const std::string& args, const std::filesystem::path& cwd) {
    const auto r = test::run_cli("compare " + args + " --json", cwd);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return json::parse(r.out);
}

} // namespace

TEST(Tools, RenderViewsThenCompareRoundTrips) {
    test::TempDir dir("tools_roundtrip");
    write_mesh(lopsided(), dir / "obj.obj");
    // The model's own frame: up +Z, facing -Y (as man.off); the views are in the conventions' frame.
    Mesh turned = lopsided();
    for (auto& p : turned.positions)
        p = {p.x, -p.z, p.y}; // conventions -> model: Y up becomes Z up, +Z front becomes -Y
    write_mesh(turned, dir / "turned.obj");
    for (const char* style : {"mask", "art"}) {
        SCOPED_TRACE(style);
        auto r = test::run_cli(
            std::string("render-views obj.obj -o ") + style + " --size 200 --views front,right,top --style " + style,
            dir.path());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        for (const char* f : {"front.png", "right.png", "top.png", "views.yaml"})
            EXPECT_TRUE(std::filesystem::exists(dir / style / f)) << f;
        // The original mesh needs a fit: the views' world has its origin at the bottom centre of the box.
        json j = compare_json(std::string("obj.obj ") + style + "/views.yaml --fit bbox", dir.path());
        EXPECT_LT(j["xor_pct"].get<double>(), std::string(style) == "mask" ? 0.05 : 0.8);
        EXPECT_EQ(j["views"].size(), 3u);
    }
    // Without the fit the mesh is elsewhere: a large error.
    json j = compare_json("obj.obj mask/views.yaml", dir.path());
    EXPECT_GT(j["xor_pct"].get<double>(), 50.0);
    // The turned model with its axes named gives the same views.
    auto r = test::run_cli("render-views turned.obj -o turned --size 200 --style mask --up +Z --front -Y", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_image(dir / "turned" / "right.png").pixels, read_image(dir / "mask" / "right.png").pixels);
    j = compare_json("turned.obj mask/views.yaml --fit bbox --up +Z --front -Y", dir.path());
    EXPECT_LT(j["xor_pct"].get<double>(), 0.05);
    j = compare_json("turned.obj mask/views.yaml --fit pivot --up +Z --front -Y", dir.path());
    EXPECT_LT(j["xor_pct"].get<double>(), 0.05);
    // Art and mask silhouettes agree once extracted.
    const Views a = load_views(dir / "art" / "views.yaml", {}).value,
                m = load_views(dir / "mask" / "views.yaml", {}).value;
    for (std::size_t v = 0; v < 3; ++v) {
        std::size_t inter = 0, uni = 0;
        for (std::size_t i = 0; i < a.views[v].coverage.size(); ++i) {
            const bool s = a.views[v].coverage[i] >= 0.5f, t = m.views[v].coverage[i] >= 0.5f;
            inter += s && t;
            uni += s || t;
        }
        EXPECT_GT(double(inter) / double(uni), 0.995) << a.views[v].name;
    }
}

TEST(Tools, RenderedViewsCarryExactCamerasAndBounds) {
    // An off-centre, lopsided object: its box's bottom centre is far from its own origin.
    test::TempDir dir("tools_exact");
    Mesh m = lopsided();
    for (auto& p : m.positions) p += Vec3f{3.0f, 2.0f, -1.5f};
    write_mesh(m, dir / "obj.obj");
    Vec3f lo, hi;
    m.bounds(lo, hi);
    const Vec3d pivot{0.5 * (double(lo.x) + double(hi.x)), double(lo.y), 0.5 * (double(lo.z) + double(hi.z))};
    auto r =
        test::run_cli("render-views obj.obj -o v --size 256 --style mask --views front,right,top,az30el20", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string yaml = test::read_text(dir / "v" / "views.yaml");
    EXPECT_NE(yaml.find("# The cameras are exact"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("Delete scale, origin and bounds"), std::string::npos) << yaml;

    // The manifest: every view's camera, and the box in the output frame (mesh units, origin
    // at the bottom centre of the box).
    const Manifest man = read_manifest(dir / "v" / "views.yaml");
    ASSERT_TRUE(man.bounds.has_value());
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR((*man.bounds)[std::size_t(k)], double(lo[k]) - pivot[k], 1e-6) << k;
        EXPECT_NEAR((*man.bounds)[std::size_t(k) + 3], double(hi[k]) - pivot[k], 1e-6) << k;
    }
    EXPECT_EQ((*man.bounds)[1], 0.0);
    ASSERT_EQ(man.views.size(), 4u);
    const double e = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    for (const auto& mv : man.views) {
        SCOPED_TRACE(mv.key);
        ASSERT_TRUE(mv.scale && mv.origin);
        EXPECT_NEAR(*mv.scale, 0.9 * 256 / e, 1e-9);
        // The box's centre, (0, height / 2, 0) in the world, lands on the image centre.
        const Camera dir_cam =
            mv.view ? *Camera::named(*mv.view) : Camera::from_azimuth_elevation(*mv.azimuth, *mv.elevation);
        const Vec3d mid{0, 0.5 * (double(hi.y) - double(lo.y)), 0};
        EXPECT_NEAR((*mv.origin)[0] + *mv.scale * dot(mid, dir_cam.r), 128.0, 1e-9);
        EXPECT_NEAR((*mv.origin)[1] - *mv.scale * dot(mid, dir_cam.u), 128.0, 1e-9);
    }
    // views.load keeps them as they are.
    const auto [views, report] = load_views(dir / "v" / "views.yaml", {});
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    for (std::size_t i = 0; i < views.views.size(); ++i) {
        EXPECT_EQ(views.views[i].camera.scale, *man.views[i].scale);
        EXPECT_EQ(views.views[i].camera.cx, (*man.views[i].origin)[0]);
        EXPECT_EQ(views.views[i].camera.cy, (*man.views[i].origin)[1]);
    }

    // The mesh against its own views: no error with either fit, oblique view included.
    for (const char* fit : {" --fit bbox", " --fit pivot"}) {
        SCOPED_TRACE(fit);
        const json j = compare_json(std::string("obj.obj v/views.yaml") + fit, dir.path());
        EXPECT_LT(j["xor_pct"].get<double>(), 0.05);
        EXPECT_EQ(j["views"].size(), 4u);
    }
    // Without a fit the off-centre mesh is off by its pivot; the same mesh moved to the
    // output frame's origin matches as it is.
    EXPECT_GT(compare_json("obj.obj v/views.yaml", dir.path())["xor_pct"].get<double>(), 50.0);
    Mesh placed = m;
    for (auto& p : placed.positions) p = Vec3f(Vec3d(p) - pivot);
    write_mesh(placed, dir / "placed.obj");
    EXPECT_LT(compare_json("placed.obj v/views.yaml", dir.path())["xor_pct"].get<double>(), 0.05);

    // Deleting scale, origin and bounds leaves views aligned from their silhouettes: close
    // (--fit bbox), but not exact.
    test::write_text(dir / "v" / "free.yaml", "views:\n  front: front.png\n  right: right.png\n  top: top.png\n");
    const double free_xor = compare_json("obj.obj v/free.yaml --fit bbox", dir.path())["xor_pct"].get<double>();
    EXPECT_LT(free_xor, 2.0);
}

TEST(Tools, RenderViewsAzimuthElevationAndTable) {
    test::TempDir dir("tools_azel");
    write_mesh(lopsided(), dir / "obj.obj");
    auto r = test::run_cli("render-views obj.obj -o v --size 128 --style mask --views front,az45el30", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string yaml = test::read_text(dir / "v" / "views.yaml");
    EXPECT_NE(yaml.find("az45el30: {image: az45el30.png, azimuth: 45, elevation: 30, scale: "), std::string::npos)
        << yaml;
    r = test::run_cli("compare obj.obj v/views.yaml --fit bbox", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("az45el30"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("all"), std::string::npos) << r.out;
    // Bad view names and axes are one-line errors.
    r = test::run_cli("render-views obj.obj -o w --views front,diagonal", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("\"diagonal\""), std::string::npos) << r.err;
    r = test::run_cli("render-views obj.obj -o w --up +Y --front -Y", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("two different axes"), std::string::npos) << r.err;
    r = test::run_cli("compare missing.obj v/views.yaml", dir.path());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("missing.obj"), std::string::npos) << r.err;
}

TEST(Tools, PreviewWritesASheet) {
    test::TempDir dir("tools_preview");
    write_mesh(lopsided(), dir / "obj.obj");
    auto r = test::run_cli("render-views obj.obj -o v --size 160 --style art", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = test::run_cli("preview obj.obj --views v/views.yaml --fit bbox -o sheet.png --panel 96", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image sheet = read_image(dir / "sheet.png");
    EXPECT_EQ(sheet.width, 3 * 96 + 4 * 8);
    EXPECT_GT(sheet.height, 3 * 96);
    r = test::run_cli("preview obj.obj -o self.png --panel 64", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "self.png"));
}

TEST(Tools, PreviewOverlayShowsWhereTheMeshDiffers) {
    // Input: a box's silhouette; mesh: the box moved right. The overlay has both colours.
    const Mesh box = test::make_box({-1, -1, -1}, {1, 1, 1});
    Mesh moved = box;
    for (auto& p : moved.positions) p.x += 0.1f; // 5.4 px at 54 px per unit
    Views views;
    const View v = front_view_of(box, 120);
    views.views.push_back(v);
    PreviewOptions opt;
    opt.panel = 120;
    // Not a structured binding: the lambda below uses the sheet, and clang 14 (the asan
    // tree) lets no lambda use a structured binding.
    const auto made = make_preview_sheet(moved, views, opt);
    const Image& sheet = made.value;
    const SilhouetteError& err = made.stats.error;
    EXPECT_NEAR(err.xor_pct, 100.0 * 10 / 108, 0.01); // 5 columns each side of 108
    std::size_t input_only = 0, mesh_only = 0;
    for (std::size_t i = 0; i < sheet.samples(); i += 3) {
        auto is = [&](const float* c) {
            return std::abs(sheet.value(i) - c[0]) < 0.01f && std::abs(sheet.value(i + 1) - c[1]) < 0.01f &&
                   std::abs(sheet.value(i + 2) - c[2]) < 0.01f;
        };
        input_only += is(kInputOnly);
        mesh_only += is(kMeshOnly);
    }
    EXPECT_GT(input_only, 400u);
    EXPECT_GT(mesh_only, 400u);
}
