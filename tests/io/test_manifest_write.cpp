// write_manifest(): what it writes, read_manifest() reads back as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "io/manifest.h"
#include "io/mesh_io.h"
#include "load.h"
#include "support/manifest_checks.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;

namespace {

ManifestView view(const fs::path& dir, const std::string& key) {
    ManifestView v;
    v.key = key;
    v.image = dir / (key + ".png");
    return v;
}

} // namespace

TEST(ManifestWrite, DrawnViewsWithOptionsRoundTrip) {
    test::TempDir dir("mw_drawn");
    Manifest m;
    m.comment = "Two lines\nof comment.";
    m.height = 1.0 / 3.0;
    m.width = 0.1;
    m.depth = 2e-7;
    ManifestView front = view(dir.path(), "front");
    front.view = "front";
    ManifestView side = view(dir.path(), "side");
    side.view = "right";
    side.background = "#ffeedd";
    side.threshold = 0.3;
    side.keep = "largest";
    side.holes = "keep";
    ManifestView q = view(dir.path(), "three_quarter");
    q.azimuth = 45.5;
    q.elevation = -1.0 / 7.0;
    q.background = "200,10,0";
    m.views = {front, side, q};
    write_manifest(dir / "views.yaml", m);
    const std::string text = test::read_text(dir / "views.yaml");
    EXPECT_EQ(text.rfind("# Two lines\n# of comment.\n", 0), 0u) << text;
    EXPECT_NE(text.find("\n  front: front.png\n"), std::string::npos) << text;
    test::expect_same_manifest(read_manifest(dir / "views.yaml"), m);
}

TEST(ManifestWrite, FixedCamerasAndBoundsRoundTripExactly) {
    test::TempDir dir("mw_fixed");
    Manifest m;
    m.bounds = {-0.4715520143508911, 0, -1.0 / 3.0, 0.4715520143508911, 1.6904299855232239, 1e-300};
    ManifestView front = view(dir.path(), "front");
    front.view = "front";
    front.scale = 134.1165305581403;
    front.origin = {128, 241.35730240491108};
    ManifestView oblique = view(dir.path(), "az30el20");
    oblique.azimuth = 30;
    oblique.elevation = 20;
    oblique.scale = std::nextafter(2.0, 3.0);
    oblique.origin = {-0.0, 1e21};
    m.views = {front, oblique};
    write_manifest(dir / "views.yaml", m);
    const std::string text = test::read_text(dir / "views.yaml");
    EXPECT_NE(text.find("  front: {image: front.png, scale: 134.1165305581403, origin: [128, 241.35730240491108]}\n"),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("-0,"), std::string::npos) << text;
    test::expect_same_manifest(read_manifest(dir / "views.yaml"), m);
}

TEST(ManifestWrite, CalibratedViewsAndImagesOutsideTheFolderRoundTrip) {
    test::TempDir dir("mw_calibrated");
    fs::create_directories(dir / "m");
    Manifest m;
    m.bounds = {-7.5, -10, -7.5, 7.5, 10, 15};
    ManifestView a;
    a.key = "0000";
    a.image = dir / "photos with spaces" / "a \"quoted\" #1.pgm"; // outside the manifest's folder
    a.matrix = {-729.446, 1047.2, -498.62, 30722.9, 1038.24, 730.46, -392.199, 25977.8, 1.0 / 3.0, -0.1, 0.2, 1e17};
    a.background = "white";
    ManifestView b;
    b.key = "null";
    b.image = dir / "m" / "sub" / "b.png";
    b.matrix = {1, 0, 0, 40, 0, -1, 0, 40, 0, 0, 0, 1};
    b.background = "black";
    b.threshold = 0.19;
    m.views = {a, b};
    write_manifest(dir / "m" / "views.yaml", m);
    const std::string text = test::read_text(dir / "m" / "views.yaml");
    EXPECT_NE(text.find("image: sub/b.png"), std::string::npos) << text;
    const Manifest back = read_manifest(dir / "m" / "views.yaml");
    test::expect_same_manifest(back, m);
}

TEST(ManifestWrite, RenderViewsManifestIsWhatWriteManifestWrites) {
    test::TempDir dir("mw_render_views");
    write_mesh(test::make_lopsided(), dir / "obj.obj");
    const auto r =
        test::run_cli("render-views obj.obj -o v --size 64 --style mask --views front,az30el20,top", dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string original = test::read_text(dir / "v" / "views.yaml");
    Manifest m = read_manifest(dir / "v" / "views.yaml");
    // The same text again from what was read (and its comment lines).
    for (std::size_t at = 0; original.compare(at, 2, "# ") == 0;) {
        const std::size_t end = original.find('\n', at);
        m.comment += original.substr(at + 2, end + 1 - at - 2);
        at = end + 1;
    }
    write_manifest(dir / "v" / "copy.yaml", m);
    EXPECT_EQ(test::read_text(dir / "v" / "copy.yaml"), original);
    test::expect_same_manifest(read_manifest(dir / "v" / "copy.yaml"), m);
    // views.load gives the same cameras from both.
    const Views a = load_views(dir / "v" / "views.yaml", {}).value, b = load_views(dir / "v" / "copy.yaml", {}).value;
    ASSERT_EQ(a.views.size(), b.views.size());
    for (std::size_t i = 0; i < a.views.size(); ++i) {
        SCOPED_TRACE(a.views[i].name);
        EXPECT_EQ(a.views[i].camera.scale, b.views[i].camera.scale);
        EXPECT_EQ(a.views[i].camera.cx, b.views[i].camera.cx);
        EXPECT_EQ(a.views[i].camera.cy, b.views[i].camera.cy);
        EXPECT_EQ(a.views[i].camera.d.x, b.views[i].camera.d.x);
        EXPECT_EQ(a.views[i].camera.d.y, b.views[i].camera.d.y);
        EXPECT_EQ(a.views[i].camera.d.z, b.views[i].camera.d.z);
    }
    EXPECT_EQ(a.bounds_min.x, b.bounds_min.x);
    EXPECT_EQ(a.bounds_max.y, b.bounds_max.y);
}

TEST(ManifestWrite, RefusesWhatCouldNotBeReadBack) {
    test::TempDir dir("mw_errors");
    auto message_of = [&](const Manifest& m) -> std::string {
        try {
            write_manifest(dir / "views.yaml", m);
        } catch (const Error& e) {
            return e.what();
        }
        return "(no error)";
    };
    Manifest m;
    EXPECT_NE(message_of(m).find("no views"), std::string::npos);
    ManifestView v = view(dir.path(), "front");
    v.scale = std::numeric_limits<double>::infinity();
    v.origin = {0, 0};
    m.views = {v};
    const std::string e = message_of(m);
    EXPECT_NE(e.find("view \"front\": scale is not a finite number"), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(dir / "views.yaml"));
}
