// The views manifest (short and long forms), see docs/views.md: read_manifest() reads it,
// write_manifest() writes it.
#pragma once
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cm {

struct ManifestView {
    std::string key;                 ///< manifest key ("front", "sketch_3q", ...)
    std::filesystem::path image;     ///< resolved against the manifest's folder
    std::optional<std::string> view; ///< named view
    std::optional<double> azimuth, elevation;
    std::optional<std::array<double, 12>> matrix; ///< from matrix, matrix_file or K/R/t
    /// A fixed orthographic camera: pixels per world unit and the image point of the world
    /// origin (pixel convention of the conventions). Given together or not at all; views
    /// without them are aligned from their silhouettes.
    std::optional<double> scale;
    std::optional<std::array<double, 2>> origin;
    std::string background = "auto"; ///< auto | alpha | colour (#rrggbb or "r,g,b")
    std::optional<double> threshold; ///< background distance threshold in [0,1]
    std::string keep = "auto";       ///< auto | largest | all ("auto" defers to the stage's keep)
    std::string holes = "auto";      ///< auto | fill | keep
    int line = 0;
    // Real drawings: gap closing, mask, shadow, photographs.
    std::optional<double> close_gaps; ///< px of ink gap closed before flooding; none: scaled to the image; 0: off
    std::filesystem::path mask;       ///< a mask image used instead of segmentation (resolved); empty: none
    std::string shadow = "auto";      ///< auto (a ground shadow is background) | keep
    std::string photo = "auto";       ///< auto (calibrated views are photographs) | on | off
    bool primary = false;             ///< the view reconciliation leaves as drawn (one at most)
};

// Turnaround sheets.
struct Manifest;
/// A turnaround sheet (`sheet:` in the manifest): one drawing holding several views side by
/// side, separated by blank paper. Each of its views is an entry of Manifest::views whose
/// image is the sheet and whose background, threshold, keep and holes are the sheet's;
/// `views` lists them in reading order (left to right, then top to bottom), which is the
/// order of the panels views.load finds in the drawing.
struct ManifestSheet {
    std::filesystem::path image;    ///< resolved against the manifest's folder
    std::vector<std::size_t> views; ///< indices into Manifest::views, in reading order
    int line = 0;                   ///< the line of the sheet's entry
};
/// The sheet whose panel view `index` of `m.views` is, and the panel's place in its reading
/// order; nullptr for a view drawn on its own.
const ManifestSheet* sheet_of(const Manifest& m, std::size_t index, std::size_t* panel = nullptr);

struct Manifest {
    std::filesystem::path file;
    /// Text written as comment lines ("# ...") at the top of the file; read_manifest() leaves it empty.
    std::string comment;
    std::vector<ManifestView> views;
    std::optional<double> height, width, depth; ///< real size of the object in output units
    /// World box (min xyz, max xyz) that holds the object: for calibrated views, or for drawn
    /// views with fixed cameras (scale, origin), whose world frame the manifest then sets.
    std::optional<std::array<double, 6>> bounds;
    bool fixed_cameras() const; ///< true when some view gives scale and origin
    /// Turnaround sheets; their views are entries of `views`.
    std::vector<ManifestSheet> sheets;
};

/// A background colour as a manifest writes it: white, black, grey, "#rrggbb" or "r,g,b"
/// (0-255); false when `s` is none of these. `rgb` is in [0, 1].
bool parse_background_colour(const std::string& s, std::array<double, 3>& rgb);
/// Checks a background option (auto, alpha or a colour); throws cm::Error naming the accepted forms.
void check_background_option(const std::string& background);

/// Reads a manifest; throws cm::Error naming the file and line.
Manifest read_manifest(const std::filesystem::path& file);

/// Writes `m` to `file` (whole or not at all, through write_file_atomic()) so that
/// read_manifest(file) gives back the same views, cameras, sizes and bounds. Images are
/// taken as read_manifest() gives them (resolved against the manifest's folder) and are
/// written relative to `file`'s folder when they lie inside it. Every view is one line;
/// one with nothing but its image, whose key names the view, takes the short form.
/// Numbers are written as the shortest text that reads back as the same double; a number
/// that is not finite throws cm::Error, as does a file that cannot be written.
void write_manifest(const std::filesystem::path& file, const Manifest& m);

} // namespace cm
