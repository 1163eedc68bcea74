// The checks of the views manifest across its views (the frame the cameras set, names used
// once) and of a background option.
#include <algorithm>
#include <cctype>
#include <sstream>

#include "io/manifest_read.h"

namespace fs = std::filesystem;

namespace cm {

namespace manifest_read {

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

// Every view has a name of its own, across views and sheets.
void check_unique_keys(const fs::path& file, const Manifest& m) {
    for (std::size_t i = 0; i < m.views.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (m.views[i].key == m.views[j].key)
                throw Error(file.string() + ":" + std::to_string(m.views[i].line) + ": view \"" + m.views[i].key +
                            "\" is named twice (first on line " + std::to_string(m.views[j].line) + ")");
}

} // namespace manifest_read

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

} // namespace cm
