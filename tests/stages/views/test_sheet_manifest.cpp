// The manifest's sheet form: what read_manifest() makes of it, what write_manifest() writes
// back, and one-line errors naming the file and line.
#include <gtest/gtest.h>

#include "core/error.h"
#include "io/manifest.h"
#include "support/manifest_checks.h"
#include "support/test_support.h"

using namespace cm;
using test::error_of;
namespace fs = std::filesystem;

TEST(SheetManifest, ReadsNamesEntriesAndOptionsInTheFilesOrder) {
    test::TempDir dir("sheet_read");
    test::write_text(dir / "views.yaml",
                     "height: 2\n"
                     "sheet:\n"
                     "  image: art/sheet.png\n"
                     "  views: [front, {name: side, view: right}, {name: q, azimuth: 45, "
                     "elevation: 30}]\n"
                     "  background: white\n"
                     "  threshold: 0.3\n"
                     "  keep: all\n"
                     "  holes: keep\n"
                     "views:\n"
                     "  top: top.png\n");
    const Manifest m = read_manifest(dir / "views.yaml");
    ASSERT_EQ(m.views.size(), 4u);
    ASSERT_EQ(m.sheets.size(), 1u);
    EXPECT_EQ(m.sheets[0].views, (std::vector<std::size_t>{0, 1, 2}));
    EXPECT_EQ(m.sheets[0].line, 3);
    EXPECT_EQ(m.sheets[0].image, dir / "art/sheet.png");
    EXPECT_EQ(m.views[1].key, "side");
    EXPECT_EQ(m.views[1].view, "right");
    EXPECT_EQ(m.views[2].azimuth, 45.0);
    EXPECT_EQ(m.views[2].elevation, 30.0);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(m.views[i].image, dir / "art/sheet.png");
        EXPECT_EQ(m.views[i].background, "white");
        EXPECT_EQ(m.views[i].threshold, 0.3);
        EXPECT_EQ(m.views[i].keep, "all");
        EXPECT_EQ(m.views[i].holes, "keep");
        EXPECT_EQ(m.views[i].line, 4);
    }
    EXPECT_EQ(m.views[3].key, "top");
    EXPECT_EQ(m.views[3].background, "auto");
    std::size_t panel = 9;
    EXPECT_EQ(sheet_of(m, 1, &panel), &m.sheets[0]);
    EXPECT_EQ(panel, 1u);
    EXPECT_EQ(sheet_of(m, 3), nullptr);
}

TEST(SheetManifest, WriteManifestRoundTrip) {
    test::TempDir dir("sheet_write");
    Manifest m;
    m.height = 1.5;
    auto add = [&](const std::string& key, const fs::path& image) {
        ManifestView v;
        v.key = key;
        v.image = image;
        m.views.push_back(v);
        return m.views.size() - 1;
    };
    add("front", dir / "front.png");
    m.views[0].view = "front";
    ManifestSheet a, b;
    a.image = dir / "a.png";
    b.image = dir / "sub/b.png";
    for (const char* k : {"right", "top"}) a.views.push_back(add(k, a.image));
    m.views[1].view = "right";
    m.views[2].view = "top";
    m.sheets = {a};
    write_manifest(dir / "one.yaml", m);
    const std::string text = test::read_text(dir / "one.yaml");
    EXPECT_NE(text.find("\nsheet: {image: a.png, views: [right, top]}\n"), std::string::npos) << text;
    test::expect_same_manifest(read_manifest(dir / "one.yaml"), m);

    // Two sheets (a list), with options and mapping entries.
    b.views.push_back(add("side", b.image));
    m.views[3].view = "left";
    b.views.push_back(add("q", b.image));
    m.views[4].azimuth = 45.5;
    m.views[4].elevation = -1.0 / 3.0;
    for (std::size_t i : b.views) {
        m.views[i].background = "#ffeedd";
        m.views[i].threshold = 0.25;
        m.views[i].keep = "largest";
        m.views[i].holes = "fill";
    }
    m.sheets = {a, b};
    write_manifest(dir / "two.yaml", m);
    test::expect_same_manifest(read_manifest(dir / "two.yaml"), m);

    // Sheets first: the order reads back.
    Manifest s;
    ManifestSheet c;
    c.image = dir / "c.png";
    for (const char* k : {"front", "top"}) {
        ManifestView v;
        v.key = k;
        v.view = k;
        v.image = c.image;
        c.views.push_back(s.views.size());
        s.views.push_back(v);
    }
    ManifestView r;
    r.key = r.view.emplace("right");
    r.image = dir / "r.png";
    s.views.push_back(r);
    s.sheets = {c};
    write_manifest(dir / "first.yaml", s);
    test::expect_same_manifest(read_manifest(dir / "first.yaml"), s);

    // An order no file gives is refused rather than written differently.
    std::swap(s.views[1], s.views[2]);
    s.sheets[0].views = {0, 2};
    const std::string e = error_of([&] { write_manifest(dir / "bad.yaml", s); });
    EXPECT_NE(e.find("interleave"), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(dir / "bad.yaml"));
}

TEST(SheetManifest, BadKeysAreOneLineErrorsWithFileAndLine) {
    test::TempDir dir("sheet_errors");
    auto msg = [&](const std::string& yaml) {
        test::write_text(dir / "m.yaml", yaml);
        const std::string e = error_of([&] { read_manifest(dir / "m.yaml"); });
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
        return e;
    };
    const struct {
        const char* yaml;
        const char* expect;
    } rows[] = {
        {"sheet: {image: s.png, views: [front], colour: red}\n",
         "m.yaml:1: sheet \"s.png\": unknown key \"colour\" (known: image, views, background"},
        {"sheet:\n  image: s.png\n  views: [front, {name: q, tilt: 3}]\n",
         "m.yaml:3: sheet \"s.png\": unknown key \"tilt\" in a view entry (known: name, view, azimuth, elevation)"},
        {"sheet: {views: [front]}\n", "m.yaml:1: a sheet needs an image"},
        {"sheet: {image: s.png}\n", "m.yaml:1: sheet \"s.png\": needs views"},
        {"sheet: {image: s.png, views: []}\n", "m.yaml:1: sheet \"s.png\": needs views"},
        {"sheet:\n  image: s.png\n  views: [front]\n  keep: most\n",
         "m.yaml:4: sheet \"s.png\": keep must be auto, largest or all, got \"most\""},
        {"sheet: {image: s.png, views: [front], threshold: 2}\n", "m.yaml:1: sheet \"s.png\": threshold must be in"},
        {"sheet: {image: s.png, views: [front], background: pinkish}\n", "m.yaml:1: sheet \"s.png\": background"},
        {"sheet: {image: s.png, views: [sketch]}\n", "m.yaml:1: view \"sketch\": the key is not a view name"},
        {"sheet: {image: s.png, views: [{view: right}]}\n",
         "m.yaml:1: sheet \"s.png\": a view entry given as a mapping needs a name"},
        {"views:\n  front: f.png\nsheet: {image: s.png, views: [right, front]}\n",
         "m.yaml:3: view \"front\" is named twice (first on line 2)"},
        {"sheet: [1, 2]\n", "m.yaml:1: a sheet must be a mapping"},
        {"views: {}\n", "m.yaml: a views manifest needs a \"views\" mapping"},
    };
    for (const auto& r : rows) {
        SCOPED_TRACE(r.yaml);
        const std::string e = msg(r.yaml);
        EXPECT_NE(e.find(r.expect), std::string::npos) << e;
    }
}
