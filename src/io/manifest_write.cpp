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

// The keys for drawings as they are handed over (close_gaps, mask, shadow, photo).
void real_drawing_fields(const ManifestView& v, const fs::path& folder, std::vector<std::string>& f) {
    if (v.close_gaps) f.push_back("close_gaps: " + number_text(*v.close_gaps, "view \"" + v.key + "\": close_gaps"));
    if (!v.mask.empty()) f.push_back("mask: " + image_text(v.mask, folder));
    if (v.shadow != "auto") f.push_back("shadow: " + scalar_text(v.shadow));
    if (v.photo != "auto") f.push_back("photo: " + scalar_text(v.photo));
    if (v.primary) f.push_back("primary: true");
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

// Turnaround sheets.

// A panel's entry in its sheet's views: its name, or {name, view | azimuth/elevation}.
std::string sheet_entry_text(const ManifestView& v) {
    const std::string what = "view \"" + v.key + "\": ";
    std::string f;
    if (v.view && *v.view != v.key) f += ", view: " + scalar_text(*v.view);
    if (v.azimuth) f += ", azimuth: " + number_text(*v.azimuth, what + "azimuth");
    if (v.elevation) f += ", elevation: " + number_text(*v.elevation, what + "elevation");
    return f.empty() ? scalar_text(v.key) : "{name: " + scalar_text(v.key) + f + "}";
}

// One sheet as a flow mapping; its panels share its image and options and take no camera.
std::string sheet_text(const Manifest& m, const ManifestSheet& sh, const fs::path& folder) {
    if (sh.views.empty()) throw Error("cannot write views manifest: a sheet has no views");
    const ManifestView& first = m.views.at(sh.views.front());
    std::string views;
    for (std::size_t i : sh.views) {
        const ManifestView& v = m.views.at(i);
        if (v.matrix || v.scale || v.origin)
            throw Error("cannot write views manifest: view \"" + v.key +
                        "\" of a sheet has a fixed camera; a sheet's views are aligned from their silhouettes");
        if (v.image != first.image || v.background != first.background || v.threshold != first.threshold ||
            v.keep != first.keep || v.holes != first.holes)
            throw Error("cannot write views manifest: view \"" + v.key + "\" differs from view \"" + first.key +
                        "\" of its sheet in its image or options (background, threshold, keep, holes)");
        views += (views.empty() ? "" : ", ") + sheet_entry_text(v);
    }
    std::string s = "{image: " + image_text(sh.image, folder) + ", views: [" + views + "]";
    const std::string what = "sheet of view \"" + first.key + "\": ";
    if (first.background != "auto") s += ", background: " + scalar_text(first.background);
    if (first.threshold) s += ", threshold: " + number_text(*first.threshold, what + "threshold");
    if (first.keep != "auto") s += ", keep: " + scalar_text(first.keep);
    if (first.holes != "auto") s += ", holes: " + scalar_text(first.holes);
    return s + "}";
}

// The "views" and "sheet" blocks, in the order that reads back as m.views: the views drawn
// on their own and the sheets' views (sheet after sheet) each in one run.
std::string views_and_sheets_text(const Manifest& m, const fs::path& folder) {
    std::vector<char> on_sheet(m.views.size(), 0);
    std::vector<std::size_t> own, sheets;
    for (const auto& sh : m.sheets)
        for (std::size_t i : sh.views) {
            if (i >= m.views.size() || on_sheet[i])
                throw Error("cannot write views manifest: a sheet names a view that is not one of its own");
            on_sheet[i] = 1;
            sheets.push_back(i);
        }
    for (std::size_t i = 0; i < m.views.size(); ++i)
        if (!on_sheet[i]) own.push_back(i);
    const bool sheets_first = !sheets.empty() && on_sheet[0];
    std::vector<std::size_t> order = sheets_first ? sheets : own;
    order.insert(order.end(), (sheets_first ? own : sheets).begin(), (sheets_first ? own : sheets).end());
    for (std::size_t i = 0; i < order.size(); ++i)
        if (order[i] != i)
            throw Error(
                "cannot write views manifest: the views of sheets and the views drawn on their own "
                "interleave (view \"" +
                m.views[i].key + "\"); a manifest lists each kind in one run");
    std::string viewsblock, sheetblock;
    if (!own.empty()) viewsblock = "views:\n";
    for (std::size_t i : own) viewsblock += view_line(m.views[i], folder);
    if (m.sheets.size() == 1) sheetblock = "sheet: " + sheet_text(m, m.sheets[0], folder) + "\n";
    else if (!m.sheets.empty()) {
        sheetblock = "sheet:\n";
        for (const auto& sh : m.sheets) sheetblock += "  - " + sheet_text(m, sh, folder) + "\n";
    }
    return sheets_first ? sheetblock + viewsblock : viewsblock + sheetblock;
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
    os << views_and_sheets_text(m, folder);
    return os.str();
}

} // namespace

void write_manifest(const fs::path& file, const Manifest& m) {
    if (m.views.empty()) throw Error("cannot write views manifest \"" + file.string() + "\": it has no views");
    write_file_atomic(file, manifest_text(m, fs::absolute(file).parent_path().lexically_normal()));
}

} // namespace cm
