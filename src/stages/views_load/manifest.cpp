#include "manifest.h"

#include <yaml-cpp/yaml.h>

#include "core/camera.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

std::string at(const fs::path& f, const YAML::Node& n) {
    return f.string() + (n.Mark().line >= 0 ? ":" + std::to_string(n.Mark().line + 1) : "");
}

double number(const fs::path& f, const YAML::Node& n, const std::string& what) {
    try {
        return n.as<double>();
    } catch (const YAML::Exception&) {
        throw Error(at(f, n) + ": " + what + " must be a number, got \"" + (n.IsScalar() ? n.Scalar() : "?") + "\"");
    }
}

} // namespace

Manifest read_manifest(const fs::path& file) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw Error("cannot read views manifest \"" + file.string() + "\": no such file");
    YAML::Node doc;
    try {
        doc = YAML::LoadFile(file.string());
    } catch (const YAML::ParserException& e) {
        throw Error(file.string() + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
    } catch (const YAML::Exception& e) {
        throw Error("cannot read views manifest \"" + file.string() + "\": " + e.msg);
    }
    if (!doc.IsMap() || !doc["views"] || !doc["views"].IsMap() || doc["views"].size() == 0)
        throw Error(file.string() + ": a views manifest needs a \"views\" mapping, e.g. views: {front: front.png, right: right.png}");
    Manifest m;
    m.file = file;
    const fs::path base = file.parent_path();
    for (auto it = doc.begin(); it != doc.end(); ++it) {
        const std::string k = it->first.Scalar();
        if (k == "views") continue;
        if (k == "height") m.height = number(file, it->second, "height");
        else if (k == "width") m.width = number(file, it->second, "width");
        else if (k == "depth") m.depth = number(file, it->second, "depth");
        else if (k == "bounds") {
            if (!it->second.IsSequence() || it->second.size() != 6)
                throw Error(at(file, it->second) + ": bounds must be a list of 6 numbers: [xmin, ymin, zmin, xmax, ymax, zmax]");
            std::array<double, 6> b{};
            for (int i = 0; i < 6; ++i) b[i] = number(file, it->second[i], "bounds");
            m.bounds = b;
        } else
            throw Error(at(file, it->first) + ": unknown manifest key \"" + k + "\" (known: views, height, width, depth, bounds)");
    }
    for (const char* k : {"height", "width", "depth"}) {
        auto& v = std::string(k) == "height" ? m.height : std::string(k) == "width" ? m.width : m.depth;
        if (v && !(*v > 0)) throw Error(at(file, doc[k]) + ": " + k + " must be positive");
    }
    for (auto it = doc["views"].begin(); it != doc["views"].end(); ++it) {
        ManifestView v;
        v.key = it->first.Scalar();
        v.line = it->first.Mark().line + 1;
        const YAML::Node& n = it->second;
        if (n.IsScalar()) {
            v.image = n.Scalar();
        } else if (n.IsMap()) {
            for (auto f = n.begin(); f != n.end(); ++f) {
                const std::string k = f->first.Scalar();
                const YAML::Node& val = f->second;
                if (k == "image") v.image = val.Scalar();
                else if (k == "view") v.view = val.Scalar();
                else if (k == "azimuth") v.azimuth = number(file, val, "azimuth");
                else if (k == "elevation") v.elevation = number(file, val, "elevation");
                else if (k == "background") v.background = val.Scalar();
                else if (k == "threshold") {
                    v.threshold = number(file, val, "threshold");
                    if (*v.threshold <= 0 || *v.threshold >= 1)
                        throw Error(at(file, val) + ": view \"" + v.key + "\": threshold must be in (0, 1)");
                } else if (k == "keep") v.keep = val.Scalar();
                else if (k == "matrix") {
                    std::vector<double> flat;
                    if (val.IsSequence())
                        for (const auto& row : val) {
                            if (row.IsSequence()) for (const auto& x : row) flat.push_back(number(file, x, "matrix"));
                            else flat.push_back(number(file, row, "matrix"));
                        }
                    if (flat.size() != 12)
                        throw Error(at(file, val) + ": view \"" + v.key + "\": matrix must be 3 rows of 4 numbers (a 3x4 projection)");
                    std::array<double, 12> P{};
                    std::copy(flat.begin(), flat.end(), P.begin());
                    v.matrix = P;
                } else
                    throw Error(at(file, f->first) + ": view \"" + v.key + "\": unknown key \"" + k +
                                "\" (known: image, view, azimuth, elevation, matrix, background, threshold, keep)");
            }
        } else {
            throw Error(at(file, n) + ": view \"" + v.key + "\" must be an image path or a mapping with \"image\"");
        }
        if (v.image.empty()) throw Error(at(file, n) + ": view \"" + v.key + "\" has no image");
        if (v.image.is_relative()) v.image = base / v.image;
        if (!v.view && !v.azimuth && !v.matrix) v.view = v.key;   // short form: the key names the view
        if (v.view && !Camera::named(*v.view))
            throw Error(at(file, n) + ": view \"" + v.key + "\": unknown view name \"" + *v.view +
                        "\" (use front, back, right, left, top, bottom, or azimuth/elevation, or matrix)");
        if (v.azimuth.has_value() != v.elevation.has_value() && !v.view)
            v.elevation = v.elevation.value_or(0.0), v.azimuth = v.azimuth.value_or(0.0);
        if (v.keep != "auto" && v.keep != "largest" && v.keep != "all")
            throw Error(at(file, n) + ": view \"" + v.key + "\": keep must be auto, largest or all, got \"" + v.keep + "\"");
        m.views.push_back(std::move(v));
    }
    return m;
}

} // namespace cm
