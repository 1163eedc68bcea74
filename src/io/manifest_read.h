// The parts of read_manifest() (io/manifest.h), each in a file of its own: the document and
// its top-level keys (manifest.cpp), a view in the short and long forms (manifest_views.cpp),
// turnaround sheets (manifest_sheets.cpp) and the checks across the views
// (manifest_checks.cpp), with the readers of YAML values they share. Used inside io only.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/error.h"
#include "io/manifest.h"

namespace cm::manifest_read {

/// The world a mesh in single precision can still carry: pixels per unit and coordinates.
constexpr double kMinScale = 1e-9, kMaxScale = 1e9, kMaxCoordinate = 1e12;

/// "file:line" of node `n` (the file alone when the node has no line).
std::string at(const std::filesystem::path& f, const YAML::Node& n);
/// The finite number `n` holds; throws cm::Error naming `what` and the line.
double number(const std::filesystem::path& f, const YAML::Node& n, const std::string& what);
/// The single value `n` holds, for `key` of view `view`; throws cm::Error for a list or a mapping.
std::string scalar(const std::filesystem::path& f, const YAML::Node& n, const std::string& view,
                   const std::string& key);

/// N numbers, flat or as rows; throws cm::Error "`what`, got <count> numbers" for another count.
template <std::size_t N>
std::array<double, N> numbers(const std::filesystem::path& f, const YAML::Node& val, const std::string& what,
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

/// One entry of "views": its key (node `key`) and either an image path or a mapping (n);
/// paths are resolved against `base`, the manifest's folder.
ManifestView read_view(const std::filesystem::path& file, const std::filesystem::path& base, const YAML::Node& key,
                       const YAML::Node& n);
/// What every view needs, in either form and on a sheet (node n): an image (resolved against
/// `base`), a camera (in the short form the key names the view), and a valid keep and holes.
void complete_view(const std::filesystem::path& file, const std::filesystem::path& base, const YAML::Node& n,
                   ManifestView& v);
/// "sheet" (node n): one sheet (a mapping) or several (a list of mappings); their views go to
/// `m.views`, in reading order, and the sheets to `m.sheets`.
void read_sheets(const std::filesystem::path& file, const std::filesystem::path& base, const YAML::Node& n,
                 Manifest& m);
/// Fixed cameras set the world frame and its units: no real size on top, and the box is
/// theirs; a box needs calibrated views or fixed cameras.
void check_frame(const std::filesystem::path& file, YAML::Node doc, const Manifest& m);
/// Every view has a name of its own, across views and sheets.
void check_unique_keys(const std::filesystem::path& file, const Manifest& m);

} // namespace cm::manifest_read
