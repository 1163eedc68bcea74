// schemas/views-manifest.schema.json against the manifest reader: what the reader accepts
// the schema accepts, what the schema names the reader knows, and the other way round.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include "core/error.h"
#include "io/manifest.h"
#include "pipeline/pipeline.h"
#include "pipeline/yaml_values.h"
#include "support/test_support.h"

using namespace cm;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const json& schema_doc() {
    static const json doc = [] {
        std::ifstream in(test::source_dir() / "schemas" / "views-manifest.schema.json");
        return json::parse(in);
    }();
    return doc;
}

// Empty when `yaml` matches the schema, else the validator's first complaint.
std::string schema_complaint(const std::string& yaml) {
    static const std::unique_ptr<valijson::Schema> schema = [] {
        auto s = std::make_unique<valijson::Schema>();
        valijson::SchemaParser parser;
        valijson::adapters::NlohmannJsonAdapter a(schema_doc());
        parser.populateSchema(a, *s);
        return s;
    }();
    const json doc = yaml_to_json(YAML::Load(yaml));
    valijson::adapters::NlohmannJsonAdapter target(doc);
    valijson::ValidationResults results;
    if (valijson::Validator().validate(*schema, target, &results)) return "";
    valijson::ValidationResults::Error e;
    results.popError(e);
    return e.description.empty() ? "invalid" : e.description;
}

// Writes `yaml` as a manifest beside a small image and reads it; the reader's message, or
// empty when it reads.
std::string reader_complaint(const test::TempDir& dir, const std::string& yaml) {
    { std::ofstream(dir / "views.yaml") << yaml; }
    try {
        read_manifest(dir / "views.yaml");
        return "";
    } catch (const Error& e) {
        return e.what();
    }
}

// The list after "(known: " in a reader's message about an unknown key.
std::set<std::string> known_keys(const std::string& message) {
    const auto a = message.find("(known: ");
    EXPECT_NE(a, std::string::npos) << message;
    const auto b = message.find(')', a);
    std::stringstream ss(message.substr(a + 8, b - a - 8));
    std::set<std::string> keys;
    for (std::string k; std::getline(ss, k, ',');) {
        k.erase(0, k.find_first_not_of(' '));
        keys.insert(k);
    }
    return keys;
}

std::set<std::string> property_names(const json& object_schema) {
    std::set<std::string> names;
    for (const auto& [k, v] : object_schema.at("properties").items()) names.insert(k);
    return names;
}

// Manifests the reader takes: the documented forms, each key at least once.
const char* const kGood[] = {
    "views:\n  front: front.png\n  right: right.png\n  top: top.png\n",
    "height: 1.8\n"
    "views:\n"
    "  front: front.png\n"
    "  side:\n"
    "    image: side.png\n"
    "    view: right\n"
    "    background: \"#f4efe3\"\n"
    "    threshold: 0.2\n"
    "    keep: all\n"
    "    holes: keep\n"
    "  three_quarter: {image: front.png, azimuth: 45, elevation: 30}\n",
    "width: 2\nviews:\n  front: {image: front.png, background: alpha, keep: largest, holes: fill}\n",
    "views:\n  front: {image: front.png, close_gaps: 6, mask: m.png, shadow: keep}\n  top: {image: t.png, close_gaps: "
    "auto, shadow: auto}\n",
    "depth: 0.5\nviews:\n  top: {image: front.png, background: \"10,20,30\"}\n",
    "bounds: [-0.6, 0, -0.45, 0.6, 1.7, 0.45]\n"
    "views:\n"
    "  front: {image: front.png, scale: 542.1, origin: [512, 972.8]}\n"
    "  right: {image: right.png, scale: 542.1, origin: [512, 972.8]}\n"
    "  top: top.png\n",
    "sheet: {image: sheet.png, views: [front, right, {name: q, azimuth: 45, elevation: 30}, {name: s, view: top}]}\n",
    "sheet:\n"
    "  - {image: a.png, views: [front, right], background: white, threshold: 0.2, keep: all, holes: fill}\n"
    "  - {image: b.png, views: [top]}\n"
    "views:\n"
    "  back: back.png\n",
    "bounds: [-1, -1, -1, 1, 1, 1]\n"
    "views:\n"
    "  a: {image: front.png, matrix: [[100, 0, 32, 0], [0, 100, 32, 0], [0, 0, 1, 5]]}\n"
    "  b: {image: front.png, matrix: [100, 0, 32, 0, 0, 100, 32, 0, 0, 0, 1, 6]}\n"
    "  c: {image: front.png, matrix_file: cam.txt}\n"
    "  d: {image: front.png, K: [[100, 0, 32], [0, 100, 32], [0, 0, 1]], R: [1, 0, 0, 0, 1, 0, 0, 0, 1], "
    "t: [0, 0, 7]}\n",
};

// Manifests both must refuse, each for one reason of shape.
const char* const kBad[] = {
    "view:\n  front: front.png\n",                                // no views
    "views: {}\n",                                                // no view
    "colour: red\nviews:\n  front: front.png\n",                  // unknown top-level key
    "views:\n  front: {image: front.png, colour: red}\n",         // unknown view key
    "views:\n  front: {image: front.png, keep: some}\n",          // bad choice
    "views:\n  front: {image: front.png, holes: maybe}\n",        // bad choice
    "views:\n  front: {image: front.png, view: sideways}\n",      // unknown view name
    "views:\n  front: {image: front.png, elevation: 120}\n",      // out of range
    "views:\n  front: {image: front.png, threshold: \"high\"}\n", // not a number
    "bounds: [0, 0, 0, 1, 1]\nviews:\n  front: front.png\n",      // 5 numbers
    "views:\n  front: {view: front}\n",                           // no image
};

} // namespace

TEST(ManifestSchema, AcceptsWhatTheReaderReads) {
    test::TempDir dir("manifest_schema_good");
    std::ofstream(dir / "cam.txt") << "100 0 32 0\n0 100 32 0\n0 0 1 5\n";
    for (const char* yaml : kGood) {
        EXPECT_EQ(reader_complaint(dir, yaml), "") << yaml;
        EXPECT_EQ(schema_complaint(yaml), "") << yaml;
    }
    // The bundled example too.
    std::ifstream in(test::source_dir() / "examples" / "spot" / "views.yaml");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(schema_complaint(text.str()), "") << text.str();
}

TEST(ManifestSchema, RefusesWhatTheReaderRefuses) {
    test::TempDir dir("manifest_schema_bad");
    for (const char* yaml : kBad) {
        EXPECT_NE(reader_complaint(dir, yaml), "") << yaml;
        EXPECT_NE(schema_complaint(yaml), "") << yaml;
    }
}

TEST(ManifestSchema, NamesExactlyTheKeysTheReaderKnows) {
    test::TempDir dir("manifest_schema_keys");
    const std::string top = reader_complaint(dir, "zz_unknown: 1\nviews:\n  front: front.png\n");
    EXPECT_EQ(known_keys(top), property_names(schema_doc())) << top;
    const std::string view = reader_complaint(dir, "views:\n  front: {image: front.png, zz_unknown: 1}\n");
    EXPECT_EQ(known_keys(view), property_names(schema_doc().at("definitions").at("view"))) << view;
    const std::string sheet = reader_complaint(dir, "sheet: {image: s.png, views: [front], zz_unknown: 1}\n");
    EXPECT_EQ(known_keys(sheet), property_names(schema_doc().at("definitions").at("sheet"))) << sheet;
    const std::string entry = reader_complaint(dir, "sheet: {image: s.png, views: [{name: q, zz_unknown: 1}]}\n");
    EXPECT_EQ(known_keys(entry), property_names(schema_doc().at("definitions").at("sheet_entry").at("oneOf").at(1)))
        << entry;
}

TEST(ManifestSchema, WhatWriteManifestWritesMatches) {
    test::TempDir dir("manifest_schema_written");
    Manifest m;
    ManifestView a;
    a.key = "front";
    a.image = dir / "front.png";
    ManifestView b = a;
    b.key = "side";
    b.view = "right";
    b.scale = 100;
    b.origin = {{32, 60}};
    b.background = "white";
    b.threshold = 0.3;
    b.keep = "all";
    b.holes = "keep";
    ManifestView c = a;
    c.key = "q";
    c.azimuth = 45;
    c.elevation = 30;
    c.scale = 100;
    c.origin = {{32, 60}};
    m.views = {a, b, c};
    m.bounds = {{-1, 0, -1, 1, 2, 1}};
    write_manifest(dir / "written.yaml", m);
    std::ifstream in(dir / "written.yaml");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(schema_complaint(text.str()), "") << text.str();
}
