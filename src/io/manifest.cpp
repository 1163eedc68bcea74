#include "io/manifest.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "core/camera.h"
#include "core/error.h"
#include "io/limits.h"
#include "io/yaml_checks.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

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

// N numbers, flat or as rows.
template <std::size_t N>
std::array<double, N> numbers(const fs::path& f, const YAML::Node& val, const std::string& what,
                              const std::string& entry = "a matrix entry") {
    std::vector<double> flat;
    if (val.IsSequence())
        for (const auto& row : val) {
            if (row.IsSequence())
                for (const auto& x : row) flat.push_back(number(f, x, entry));
            else flat.push_back(number(f, row, entry));
        }
    if (flat.size() != N) throw Error(what + ", got " + std::to_string(flat.size()) + " numbers");
    std::array<double, N> a{};
    std::copy(flat.begin(), flat.end(), a.begin());
    return a;
}

// A text file holding the 12 numbers of a 3x4 projection, row by row; words (such as
// the "CONTOUR" header of some calibration files) are skipped.
std::array<double, 12> read_matrix_file(const fs::path& mf, const std::string& where) {
    std::ifstream in(mf);
    if (!in) throw Error(where + "cannot read matrix_file \"" + mf.string() + "\"");
    std::vector<double> v;
    std::string line, tok;
    for (int ln = 1; std::getline(in, line); ++ln) {
        std::istringstream words(line);
        while (words >> tok) {
            char* end = nullptr;
            const double x = std::strtod(tok.c_str(), &end);
            if (!end || *end != '\0' || end == tok.c_str()) continue;
            if (!std::isfinite(x)) // strtod reads "nan" and "inf" as numbers
                throw Error(where + "matrix_file \"" + mf.string() + "\" line " + std::to_string(ln) + ": \"" + tok +
                            "\" is not a finite number");
            v.push_back(x);
        }
    }
    if (v.size() != 12)
        throw Error(where + "matrix_file \"" + mf.string() +
                    "\" must hold 12 numbers (a 3x4 projection, row by row), found " + std::to_string(v.size()));
    std::array<double, 12> P{};
    std::copy(v.begin(), v.end(), P.begin());
    return P;
}

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

// The world a mesh in single precision can still carry: pixels per unit and coordinates.
constexpr double kMinScale = 1e-9, kMaxScale = 1e9, kMaxCoordinate = 1e12;

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

// The ways a view's mapping gives its camera, as they are read: K, R and t (together they
// make the matrix), and how many of matrix, matrix_file and K/R/t were given.
struct CameraKeys {
    std::optional<std::array<double, 9>> K, R;
    std::optional<std::array<double, 3>> tvec;
    int matrix_sources = 0;
};

// The keys for drawings as they are handed over (close_gaps, mask, shadow, photo); false when
// `k` is none of them.
bool read_real_drawing_key(const fs::path& file, const fs::path& base, const std::string& k, const YAML::Node& val,
                           ManifestView& v) {
    const std::string where = at(file, val) + ": view \"" + v.key + "\": ";
    if (k == "close_gaps") {
        const std::string text = val.IsScalar() ? val.Scalar() : "?";
        if (text == "auto") {
            v.close_gaps.reset();
            return true;
        }
        double g = -1;
        try {
            g = val.as<double>();
        } catch (const YAML::Exception&) {
            g = -1;
        }
        if (!(g >= 0) || !std::isfinite(g))
            throw Error(where + "close_gaps must be auto or a number of pixels >= 0 (0 turns gap closing off), got \"" +
                        text + "\"");
        v.close_gaps = g;
    } else if (k == "mask") {
        v.mask = scalar(file, val, v.key, k);
        if (v.mask.empty()) throw Error(where + "mask must name an image file");
        if (v.mask.is_relative()) v.mask = base / v.mask;
    } else if (k == "shadow") {
        v.shadow = scalar(file, val, v.key, k);
        if (v.shadow != "auto" && v.shadow != "keep")
            throw Error(where + "shadow must be auto or keep, got \"" + v.shadow + "\"");
    } else if (k == "photo") {
        v.photo = scalar(file, val, v.key, k);
        if (v.photo != "auto" && v.photo != "on" && v.photo != "off")
            throw Error(where + "photo must be auto, on or off, got \"" + v.photo + "\"");
    } else {
        return false;
    }
    return true;
}

// One key (its node: `key`) of a view's mapping, with its value `val`.
void read_view_key(const fs::path& file, const fs::path& base, const YAML::Node& key, const YAML::Node& val,
                   ManifestView& v, CameraKeys& cam) {
    const std::string k = key.Scalar();
    const std::string where = at(file, val) + ": view \"" + v.key + "\": ";
    if (k == "image") v.image = scalar(file, val, v.key, k);
    else if (k == "view") v.view = scalar(file, val, v.key, k);
    else if (k == "azimuth") v.azimuth = number(file, val, "azimuth");
    else if (k == "elevation") v.elevation = number(file, val, "elevation");
    else if (k == "background") {
        v.background = scalar(file, val, v.key, k);
        try {
            check_background_option(v.background);
        } catch (const Error& e) {
            throw Error(where + e.what());
        }
    } else if (k == "threshold") {
        v.threshold = number(file, val, "threshold");
        if (*v.threshold <= 0 || *v.threshold >= 1) throw Error(where + "threshold must be in (0, 1)");
    } else if (k == "keep") v.keep = scalar(file, val, v.key, k);
    else if (k == "holes") v.holes = scalar(file, val, v.key, k);
    else if (k == "matrix") {
        v.matrix = numbers<12>(file, val, where + "matrix must be 3 rows of 4 numbers (a 3x4 projection)");
        ++cam.matrix_sources;
    } else if (k == "matrix_file") {
        fs::path mf = scalar(file, val, v.key, k);
        if (mf.is_relative()) mf = base / mf;
        v.matrix = read_matrix_file(mf, where);
        ++cam.matrix_sources;
    } else if (k == "scale") {
        v.scale = number(file, val, "view \"" + v.key + "\": scale");
        if (!(*v.scale > 0) || !std::isfinite(*v.scale))
            throw Error(where + "scale must be a positive number of pixels per world unit, got " + val.Scalar());
        if (*v.scale < kMinScale || *v.scale > kMaxScale)
            throw Error(where + "scale " + val.Scalar() +
                        " is outside [1e-9, 1e9] pixels per world unit: a mesh (single precision) cannot hold "
                        "that world; choose units nearer the drawing's size");
    } else if (k == "origin") {
        v.origin =
            numbers<2>(file, val, where + "origin must be 2 numbers [cx, cy] (the image point of the world origin)",
                       "view \"" + v.key + "\": an origin coordinate");
        if (!std::isfinite((*v.origin)[0]) || !std::isfinite((*v.origin)[1]))
            throw Error(where + "origin must be finite");
    } else if (k == "K") cam.K = numbers<9>(file, val, where + "K must be 3 rows of 3 numbers");
    else if (k == "R") cam.R = numbers<9>(file, val, where + "R must be 3 rows of 3 numbers");
    else if (k == "t") cam.tvec = numbers<3>(file, val, where + "t must be 3 numbers");
    else if (read_real_drawing_key(file, base, k, val, v)) return;
    else
        throw Error(at(file, key) + ": view \"" + v.key + "\": unknown key \"" + k +
                    "\" (known: image, view, azimuth, elevation, scale, origin, matrix, matrix_file, K, R, t, "
                    "background, threshold, keep, holes, close_gaps, mask, shadow, photo)");
}

// A view given as a mapping (node n): its keys, then the camera they give, given once and
// in one way.
void read_view_mapping(const fs::path& file, const fs::path& base, const YAML::Node& n, ManifestView& v) {
    CameraKeys cam;
    for (auto f = n.begin(); f != n.end(); ++f) {
        const YAML::Node key = f->first, val = f->second; // copies: f-> gives a temporary
        read_view_key(file, base, key, val, v, cam);
    }
    if (cam.K || cam.R || cam.tvec) {
        if (!(cam.K && cam.R && cam.tvec))
            throw Error(at(file, n) + ": view \"" + v.key + "\": K, R and t go together (P = K [R | t])");
        std::array<double, 12> P{};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) {
                double x = 0;
                for (int k = 0; k < 3; ++k) x += (*cam.K)[r * 3 + k] * (c < 3 ? (*cam.R)[k * 3 + c] : (*cam.tvec)[k]);
                P[r * 4 + c] = x;
            }
        for (double x : P)
            if (!std::isfinite(x))
                throw Error(at(file, n) + ": view \"" + v.key +
                            "\": K [R | t] overflows (an entry of the product is not a finite number): give K, R "
                            "and t in units nearer the image's size");
        v.matrix = P;
        ++cam.matrix_sources;
    }
    if (cam.matrix_sources > 1)
        throw Error(at(file, n) + ": view \"" + v.key + "\": give the camera once: matrix, matrix_file, or K/R/t");
    if (v.matrix && (v.view || v.azimuth || v.elevation))
        throw Error(at(file, n) + ": view \"" + v.key +
                    "\": a calibrated view (matrix) takes no view or azimuth/elevation");
    if (v.view && (v.azimuth || v.elevation))
        throw Error(at(file, n) + ": view \"" + v.key + "\": give either view or azimuth/elevation, not both");
    if (v.matrix && (v.scale || v.origin))
        throw Error(at(file, n) + ": view \"" + v.key +
                    "\": scale and origin fix an orthographic camera; a calibrated view (matrix) takes neither");
    if (v.scale.has_value() != v.origin.has_value())
        throw Error(at(file, n) + ": view \"" + v.key +
                    "\": scale and origin go together (together they fix the "
                    "camera): give both or neither");
}

// What every view needs, in either form (node n): an image (resolved against `base`), a
// camera (in the short form the key names the view), and a valid keep and holes.
void complete_view(const fs::path& file, const fs::path& base, const YAML::Node& n, ManifestView& v) {
    if (v.image.empty()) throw Error(at(file, n) + ": view \"" + v.key + "\" has no image");
    if (v.image.is_relative()) v.image = base / v.image;
    if (!v.view && !v.azimuth && !v.elevation && !v.matrix) {
        // Short form: the key names the view.
        if (!Camera::named(v.key))
            throw Error(at(file, n) + ": view \"" + v.key +
                        "\": the key is not a view name (front, back, right, left, top, bottom); give view, "
                        "azimuth/elevation or matrix");
        v.view = v.key;
    }
    if (v.view && !Camera::named(*v.view))
        throw Error(at(file, n) + ": view \"" + v.key + "\": unknown view name \"" + *v.view +
                    "\" (use front, back, right, left, top, bottom, or azimuth/elevation, or matrix)");
    if (v.matrix) {
        // A matrix must be a camera: its left 3x3 invertible and its centre a finite point
        // (entries near 1e300 multiply to infinities).
        // (A singular one is left to the stages, which name the view: some uses need no centre.)
        Vec3d c{0, 0, 0};
        try {
            c = Camera::perspective(*v.matrix).center();
        } catch (const Error&) {}
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
            throw Error(at(file, n) + ": view \"" + v.key +
                        "\": the matrix puts the camera centre at infinity or NaN (entries too large or too "
                        "small): give it in units nearer the image's size");
    }
    if (!v.view && !v.matrix) {
        v.azimuth = v.azimuth.value_or(0.0);
        v.elevation = v.elevation.value_or(0.0);
        if (*v.elevation < -90 || *v.elevation > 90)
            throw Error(at(file, n) + ": view \"" + v.key + "\": elevation must be in [-90, 90] degrees");
        if (*v.azimuth < -360 || *v.azimuth > 360)
            throw Error(at(file, n) + ": view \"" + v.key + "\": azimuth must be in [-360, 360] degrees");
    }
    if (v.keep != "auto" && v.keep != "largest" && v.keep != "all")
        throw Error(at(file, n) + ": view \"" + v.key + "\": keep must be auto, largest or all, got \"" + v.keep +
                    "\"");
    if (v.holes != "auto" && v.holes != "fill" && v.holes != "keep")
        throw Error(at(file, n) + ": view \"" + v.key + "\": holes must be auto, fill or keep, got \"" + v.holes +
                    "\"");
}

// One entry of "views": its key (node `key`) and either an image path or a mapping (n).
ManifestView read_view(const fs::path& file, const fs::path& base, const YAML::Node& key, const YAML::Node& n) {
    ManifestView v;
    v.key = key.Scalar();
    v.line = key.Mark().line + 1;
    if (n.IsScalar()) {
        v.image = n.Scalar();
    } else if (n.IsMap()) {
        read_view_mapping(file, base, n, v);
    } else {
        throw Error(at(file, n) + ": view \"" + v.key + "\" must be an image path or a mapping with \"image\"");
    }
    complete_view(file, base, n, v);
    return v;
}

// Fixed cameras set the world frame and its units: no real size on top, and the box is
// theirs. Without them drawn views are aligned into a frame of their own, which a box
// given here could not refer to.
void check_frame(const fs::path& file, YAML::Node doc, const Manifest& m) {
    const bool calibrated =
        std::any_of(m.views.begin(), m.views.end(), [](const ManifestView& v) { return v.matrix.has_value(); });
    if (m.fixed_cameras())
        for (const char* k : {"height", "width", "depth"})
            if (doc[k])
                throw Error(at(file, doc[k]) + ": " + k +
                            " cannot go with fixed cameras (scale, origin): they set the units");
    if (m.bounds && !calibrated && !m.fixed_cameras())
        throw Error(at(file, doc["bounds"]) +
                    ": bounds needs calibrated views (matrix) or fixed cameras (scale, origin); "
                    "drawn views without them are aligned into a frame of their own (give height, width or depth for a "
                    "real size)");
}

// Turnaround sheets.

std::string sheet_name(const fs::path& base, const fs::path& image) {
    const fs::path rel = image.lexically_relative(base);
    return "sheet \"" + (rel.empty() ? image : rel).generic_string() + "\": ";
}

// One entry of a sheet's "views": a view name, or a mapping {name, view | azimuth/elevation}.
ManifestView read_sheet_entry(const fs::path& file, const fs::path& base, const YAML::Node& n,
                              const ManifestView& proto, const std::string& where) {
    ManifestView v = proto;
    v.line = n.Mark().line + 1;
    if (n.IsScalar()) {
        v.key = n.Scalar();
    } else if (n.IsMap()) {
        for (auto f = n.begin(); f != n.end(); ++f) {
            const YAML::Node key = f->first, val = f->second;
            const std::string k = key.Scalar();
            if ((k == "name" || k == "view") && !val.IsScalar())
                throw Error(at(file, val) + ": " + where + k + " must be a single value");
            if (k == "name") v.key = val.Scalar();
            else if (k == "view") v.view = val.Scalar();
            else if (k == "azimuth") v.azimuth = number(file, val, "azimuth");
            else if (k == "elevation") v.elevation = number(file, val, "elevation");
            else
                throw Error(at(file, key) + ": " + where + "unknown key \"" + k +
                            "\" in a view entry (known: name, view, azimuth, elevation)");
        }
        if (v.key.empty()) throw Error(at(file, n) + ": " + where + "a view entry given as a mapping needs a name");
        if (v.view && (v.azimuth || v.elevation))
            throw Error(at(file, n) + ": " + where + "view \"" + v.key +
                        "\": give either view or azimuth/elevation, not both");
    } else {
        throw Error(at(file, n) + ": " + where + "a view entry must be a view name or a mapping {name, view}");
    }
    complete_view(file, base, n, v);
    return v;
}

// The options of a sheet (background, threshold, keep, holes), which every panel takes.
void read_sheet_option(const fs::path& file, const YAML::Node& key, const YAML::Node& val, ManifestView& proto,
                       const std::string& where) {
    const std::string k = key.Scalar();
    if (!val.IsScalar()) throw Error(at(file, val) + ": " + where + k + " must be a single value");
    if (k == "background") {
        proto.background = val.Scalar();
        try {
            check_background_option(proto.background);
        } catch (const Error& e) {
            throw Error(at(file, val) + ": " + where + e.what());
        }
    } else if (k == "threshold") {
        proto.threshold = number(file, val, "threshold");
        if (*proto.threshold <= 0 || *proto.threshold >= 1)
            throw Error(at(file, val) + ": " + where + "threshold must be in (0, 1)");
    } else if (k == "keep") {
        proto.keep = val.Scalar();
        if (proto.keep != "auto" && proto.keep != "largest" && proto.keep != "all")
            throw Error(at(file, val) + ": " + where + "keep must be auto, largest or all, got \"" + proto.keep + "\"");
    } else if (k == "holes") {
        proto.holes = val.Scalar();
        if (proto.holes != "auto" && proto.holes != "fill" && proto.holes != "keep")
            throw Error(at(file, val) + ": " + where + "holes must be auto, fill or keep, got \"" + proto.holes + "\"");
    } else {
        throw Error(at(file, key) + ": " + where + "unknown key \"" + k +
                    "\" (known: image, views, background, threshold, keep, holes)");
    }
}

// One sheet (a mapping n): its image and options, then its views in reading order.
void read_sheet(const fs::path& file, const fs::path& base, const YAML::Node& n, Manifest& m) {
    if (!n.IsMap()) throw Error(at(file, n) + ": a sheet must be a mapping {image: sheet.png, views: [front, ...]}");
    if (!n["image"] || !n["image"].IsScalar() || n["image"].Scalar().empty())
        throw Error(at(file, n) + ": a sheet needs an image: sheet: {image: sheet.png, views: [front, right, top]}");
    ManifestSheet sh;
    sh.image = n["image"].Scalar();
    if (sh.image.is_relative()) sh.image = base / sh.image;
    sh.line = n.Mark().line + 1;
    const std::string where = sheet_name(base, sh.image);
    ManifestView proto;
    proto.image = sh.image;
    for (auto f = n.begin(); f != n.end(); ++f) {
        const YAML::Node key = f->first, val = f->second;
        if (key.Scalar() != "image" && key.Scalar() != "views") read_sheet_option(file, key, val, proto, where);
    }
    const YAML::Node list = n["views"];
    if (!list || !list.IsSequence() || list.size() == 0)
        throw Error(at(file, n) + ": " + where +
                    "needs views: the names of its panels in reading order, e.g. views: [front, right, top]");
    for (const auto& entry : list) {
        sh.views.push_back(m.views.size());
        m.views.push_back(read_sheet_entry(file, base, entry, proto, where));
    }
    m.sheets.push_back(std::move(sh));
}

// "sheet": one sheet (a mapping) or several (a list of mappings).
void read_sheets(const fs::path& file, const fs::path& base, const YAML::Node& n, Manifest& m) {
    if (n.IsSequence()) {
        if (n.size() == 0) throw Error(at(file, n) + ": sheet: the list of sheets is empty");
        for (const auto& s : n) read_sheet(file, base, s, m);
    } else {
        read_sheet(file, base, n, m);
    }
}

// Every view has a name of its own, across views and sheets.
void check_unique_keys(const fs::path& file, const Manifest& m) {
    for (std::size_t i = 0; i < m.views.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (m.views[i].key == m.views[j].key)
                throw Error(file.string() + ":" + std::to_string(m.views[i].line) + ": view \"" + m.views[i].key +
                            "\" is named twice (first on line " + std::to_string(m.views[j].line) + ")");
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

bool parse_background_colour(const std::string& s, std::array<double, 3>& c) {
    if (s == "white") {
        c = {1, 1, 1};
        return true;
    }
    if (s == "black") {
        c = {0, 0, 0};
        return true;
    }
    if (s == "grey" || s == "gray") {
        c = {0.5, 0.5, 0.5};
        return true;
    }
    auto hex = [](char ch) { return std::isxdigit(static_cast<unsigned char>(ch)) != 0; };
    if (s.size() == 7 && s[0] == '#' && std::all_of(s.begin() + 1, s.end(), hex)) {
        for (int k = 0; k < 3; ++k) c[k] = double(std::stoi(s.substr(1 + 2 * k, 2), nullptr, 16)) / 255.0;
        return true;
    }
    std::stringstream ss(s);
    char c1 = 0, c2 = 0;
    if (ss >> c[0] >> c1 >> c[1] >> c2 >> c[2] && c1 == ',' && c2 == ',' && (ss >> std::ws).eof()) {
        for (auto& x : c) {
            if (x < 0 || x > 255) return false;
            x /= 255.0;
        }
        return true;
    }
    return false;
}

void check_background_option(const std::string& background) {
    std::array<double, 3> c{};
    if (background == "auto" || background == "alpha" || parse_background_colour(background, c)) return;
    throw Error("background \"" + background +
                "\" is not auto, alpha, white, black, grey, \"#rrggbb\" or \"r,g,b\" (0-255)");
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
