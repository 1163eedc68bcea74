// write_manifest(): the views manifest as read_manifest() reads it (docs/views.md).
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/file_commit.h"
#include "io/manifest.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

// The shortest text that reads back as the same double ("-0" written as 0).
std::string number_text(double v, const std::string& what) {
    if (!std::isfinite(v)) throw Error("cannot write views manifest: " + what + " is not a finite number");
    if (v == 0) v = 0;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

template <std::size_t N>
std::string list_text(const std::array<double, N>& a, const std::string& what, std::size_t first = 0,
                      std::size_t count = N) {
    std::string s = "[";
    for (std::size_t i = first; i < first + count; ++i) s += (i > first ? ", " : "") + number_text(a[i], what);
    return s + "]";
}

// A YAML scalar: plain when it can only read back as the same text, else double-quoted.
std::string scalar_text(const std::string& s) {
    auto safe = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '+' || c == '-';
    };
    bool plain = !s.empty() && s[0] != '-' && s != "null" && s != "Null" && s != "NULL";
    for (char c : s) plain = plain && safe(c);
    if (plain) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            q += '\\';
            q += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(static_cast<unsigned char>(c)));
            q += hex;
        } else {
            q += c;
        }
    }
    return q + "\"";
}

// Relative to the manifest's folder when the image lies inside it, else absolute.
std::string image_text(const fs::path& image, const fs::path& folder) {
    const fs::path abs = fs::absolute(image).lexically_normal();
    const fs::path rel = abs.lexically_relative(folder);
    const bool inside = !rel.empty() && *rel.begin() != "..";
    return scalar_text((inside ? rel : abs).generic_string());
}

// The keys for drawings as they are handed over (close_gaps, mask, shadow).
void real_drawing_fields(const ManifestView& v, const fs::path& folder, std::vector<std::string>& f) {
    if (v.close_gaps) f.push_back("close_gaps: " + number_text(*v.close_gaps, "view \"" + v.key + "\": close_gaps"));
    if (!v.mask.empty()) f.push_back("mask: " + image_text(v.mask, folder));
    if (v.shadow != "auto") f.push_back("shadow: " + scalar_text(v.shadow));
}

std::vector<std::string> view_fields(const ManifestView& v, const fs::path& folder) {
    const std::string what = "view \"" + v.key + "\": ";
    std::vector<std::string> f;
    if (v.view && *v.view != v.key) f.push_back("view: " + scalar_text(*v.view));
    if (v.azimuth) f.push_back("azimuth: " + number_text(*v.azimuth, what + "azimuth"));
    if (v.elevation) f.push_back("elevation: " + number_text(*v.elevation, what + "elevation"));
    if (v.matrix)
        f.push_back("matrix: [" + list_text(*v.matrix, what + "matrix", 0, 4) + ", " +
                    list_text(*v.matrix, what + "matrix", 4, 4) + ", " + list_text(*v.matrix, what + "matrix", 8, 4) +
                    "]");
    if (v.scale) f.push_back("scale: " + number_text(*v.scale, what + "scale"));
    if (v.origin) f.push_back("origin: " + list_text(*v.origin, what + "origin"));
    if (v.background != "auto") f.push_back("background: " + scalar_text(v.background));
    if (v.threshold) f.push_back("threshold: " + number_text(*v.threshold, what + "threshold"));
    if (v.keep != "auto") f.push_back("keep: " + scalar_text(v.keep));
    if (v.holes != "auto") f.push_back("holes: " + scalar_text(v.holes));
    real_drawing_fields(v, folder, f);
    return f;
}

std::string view_line(const ManifestView& v, const fs::path& folder) {
    const std::string image = image_text(v.image, folder);
    const std::vector<std::string> fields = view_fields(v, folder);
    if (fields.empty()) return "  " + scalar_text(v.key) + ": " + image + "\n";
    std::string line = "  " + scalar_text(v.key) + ": {image: " + image;
    for (const auto& f : fields) line += ", " + f;
    return line + "}\n";
}

std::string manifest_text(const Manifest& m, const fs::path& folder) {
    std::ostringstream os;
    if (!m.comment.empty()) {
        std::istringstream lines(m.comment);
        for (std::string line; std::getline(lines, line);) os << (line.empty() ? "#" : "# " + line) << "\n";
    }
    if (m.height) os << "height: " << number_text(*m.height, "height") << "\n";
    if (m.width) os << "width: " << number_text(*m.width, "width") << "\n";
    if (m.depth) os << "depth: " << number_text(*m.depth, "depth") << "\n";
    if (m.bounds) os << "bounds: " << list_text(*m.bounds, "bounds") << "\n";
    os << "views:\n";
    for (const auto& v : m.views) os << view_line(v, folder);
    return os.str();
}

} // namespace

void write_manifest(const fs::path& file, const Manifest& m) {
    if (m.views.empty()) throw Error("cannot write views manifest \"" + file.string() + "\": it has no views");
    write_file_atomic(file, manifest_text(m, fs::absolute(file).parent_path().lexically_normal()));
}

} // namespace cm
