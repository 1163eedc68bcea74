// A view's entry of the views manifest, in the short form (key: image) and the long one (a
// mapping: image, camera, segmentation options).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/camera.h"
#include "io/manifest_read.h"

namespace fs = std::filesystem;

namespace cm::manifest_read {

namespace {

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

// The ways a view's mapping gives its camera, as they are read: K, R and t (together they
// make the matrix), and how many of matrix, matrix_file and K/R/t were given.
struct CameraKeys {
    std::optional<std::array<double, 9>> K, R;
    std::optional<std::array<double, 3>> tvec;
    int matrix_sources = 0;
};

// The keys for drawings as they are handed over (close_gaps, mask, shadow, photo, primary); false when
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
    } else if (k == "primary") {
        const std::string text = scalar(file, val, v.key, k);
        if (text != "true" && text != "false")
            throw Error(where + "primary must be true or false, got \"" + text + "\"");
        v.primary = text == "true";
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
                    "background, threshold, keep, holes, close_gaps, mask, shadow, photo, primary)");
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

} // namespace

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

} // namespace cm::manifest_read
