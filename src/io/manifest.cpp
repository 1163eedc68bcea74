// read_manifest(): the document and its top-level keys; a view's entry, sheets and the
// checks across the views are read in the files manifest_read.h names.
#include "io/manifest.h"

#include <algorithm>
#include <cmath>

#include <yaml-cpp/yaml.h>

#include "core/error.h"
#include "io/limits.h"
#include "io/manifest_read.h"
#include "io/yaml_checks.h"

namespace fs = std::filesystem;

namespace cm {

namespace manifest_read {

std::string at(const fs::path& f, const YAML::Node& n) {
    return f.string() + (n.Mark().line >= 0 ? ":" + std::to_string(n.Mark().line + 1) : "");
}

double number(const fs::path& f, const YAML::Node& n, const std::string& what) {
    double x = 0;
    try {
        x = n.as<double>();
    } catch (const YAML::Exception&) {
        throw Error(at(f, n) + ": " + what + " must be a number, got \"" + (n.IsScalar() ? n.Scalar() : "?") + "\"");
    }
    // .nan and .inf read as numbers but mean nothing here.
    if (!std::isfinite(x)) throw Error(at(f, n) + ": " + what + " must be a finite number, got " + n.Scalar());
    return x;
}

std::string scalar(const fs::path& f, const YAML::Node& n, const std::string& view, const std::string& key) {
    if (!n.IsScalar()) throw Error(at(f, n) + ": view \"" + view + "\": " + key + " must be a single value");
    return n.Scalar();
}

} // namespace manifest_read

namespace {

using namespace manifest_read;

// The manifest's YAML document, with a "views" mapping that is not empty.
YAML::Node load_document(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("cannot read views manifest \"" + file.string() + "\": no such file");
    if (fs::is_directory(file, ec))
        throw Error("cannot read views manifest \"" + file.string() + "\": it is a folder; name the YAML file");
    YAML::Node doc;
    try {
        doc = YAML::LoadFile(file.string());
    } catch (const YAML::ParserException& e) {
        throw Error(file.string() + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
    } catch (const YAML::Exception& e) {
        throw Error("cannot read views manifest \"" + file.string() + "\": " + e.msg);
    }
    check_yaml_document(doc, file);
    const bool views_ok = doc.IsMap() && doc["views"] && doc["views"].IsMap() && doc["views"].size() != 0;
    if (!doc.IsMap() || (!doc["sheet"] && !views_ok) || (doc["views"] && !views_ok))
        throw Error(file.string() +
                    ": a views manifest needs a \"views\" mapping, e.g. views: {front: front.png, right: right.png}, "
                    "or a turnaround sheet, e.g. sheet: {image: sheet.png, views: [front, right, top]}");
    return doc;
}

std::array<double, 6> read_bounds(const fs::path& file, const YAML::Node& n) {
    if (!n.IsSequence() || n.size() != 6)
        throw Error(at(file, n) + ": bounds must be a list of 6 numbers: [xmin, ymin, zmin, xmax, ymax, zmax]");
    std::array<double, 6> b{};
    for (int i = 0; i < 6; ++i) b[std::size_t(i)] = number(file, n[i], "bounds");
    for (std::size_t k = 0; k < 3; ++k)
        if (!std::isfinite(b[k]) || !std::isfinite(b[k + 3]) || b[k] > b[k + 3])
            throw Error(at(file, n) + ": bounds: " + "xyz"[k] + "min must not exceed " + "xyz"[k] +
                        "max ([xmin, ymin, zmin, xmax, ymax, zmax])");
    for (double x : b)
        if (std::abs(x) > kMaxCoordinate)
            throw Error(at(file, n) +
                        ": bounds: coordinates beyond 1e12 in size are refused (a mesh, in single precision, "
                        "cannot hold them); give the box in units nearer the object's size");
    return b;
}

// The keys beside "views": the real size of the object (height, width, depth) and its box.
void read_top_level(const fs::path& file, YAML::Node doc, Manifest& m) {
    for (auto it = doc.begin(); it != doc.end(); ++it) {
        const std::string k = it->first.Scalar();
        if (k == "views" || k == "sheet") continue;
        if (k == "height") m.height = number(file, it->second, "height");
        else if (k == "width") m.width = number(file, it->second, "width");
        else if (k == "depth") m.depth = number(file, it->second, "depth");
        else if (k == "bounds") m.bounds = read_bounds(file, it->second);
        else
            throw Error(at(file, it->first) + ": unknown manifest key \"" + k +
                        "\" (known: views, sheet, height, width, depth, bounds)");
    }
    for (const char* k : {"height", "width", "depth"}) {
        auto& v = std::string(k) == "height" ? m.height : std::string(k) == "width" ? m.width : m.depth;
        if (v && !(*v > 0)) throw Error(at(file, doc[k]) + ": " + k + " must be positive");
        if (v && (*v < 1e-12 || *v > 1e9))
            throw Error(at(file, doc[k]) + ": " + k + " " + doc[k].Scalar() +
                        " is outside [1e-12, 1e9] (metres): a mesh (single precision) cannot hold that size");
    }
}

} // namespace

const ManifestSheet* sheet_of(const Manifest& m, std::size_t index, std::size_t* panel) {
    for (const auto& sh : m.sheets)
        for (std::size_t k = 0; k < sh.views.size(); ++k)
            if (sh.views[k] == index) {
                if (panel) *panel = k;
                return &sh;
            }
    return nullptr;
}

bool Manifest::fixed_cameras() const {
    return std::any_of(views.begin(), views.end(), [](const ManifestView& v) { return v.scale.has_value(); });
}

Manifest read_manifest(const fs::path& file) {
    YAML::Node doc = load_document(file);
    Manifest m;
    m.file = file;
    const fs::path base = file.parent_path();
    read_top_level(file, doc, m);
    for (auto top = doc.begin(); top != doc.end(); ++top) { // views and sheets in the file's order
        if (top->first.Scalar() == "sheet") read_sheets(file, base, top->second, m);
        if (top->first.Scalar() != "views") continue;
        for (auto it = doc["views"].begin(); it != doc["views"].end(); ++it) {
            const YAML::Node key = it->first, n = it->second; // copies: it-> gives a temporary
            m.views.push_back(read_view(file, base, key, n));
        }
    }
    const std::size_t max_views = resource_limits().max_views;
    if (max_views != 0 && m.views.size() > max_views)
        throw Error("views manifest \"" + file.string() + "\" holds " + std::to_string(m.views.size()) +
                    " views, over the limit of " + std::to_string(max_views) + " (--max-views)");
    check_unique_keys(file, m);
    check_frame(file, doc, m);
    return m;
}

} // namespace cm
