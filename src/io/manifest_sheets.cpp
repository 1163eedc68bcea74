// Turnaround sheets in the views manifest (`sheet:`): one drawing holding several views, each
// an entry of Manifest::views whose image is the sheet.
#include "io/manifest_read.h"

namespace fs = std::filesystem;

namespace cm::manifest_read {

namespace {

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

} // namespace

// "sheet": one sheet (a mapping) or several (a list of mappings).
void read_sheets(const fs::path& file, const fs::path& base, const YAML::Node& n, Manifest& m) {
    if (n.IsSequence()) {
        if (n.size() == 0) throw Error(at(file, n) + ": sheet: the list of sheets is empty");
        for (const auto& s : n) read_sheet(file, base, s, m);
    } else {
        read_sheet(file, base, n, m);
    }
}

} // namespace cm::manifest_read
