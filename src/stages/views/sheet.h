// Turnaround sheets: one drawing holding several views side by side (`sheet:` in the views
// manifest, docs/views.md). The panels are found on the sheet's silhouette and each becomes
// a view of its own, cropped from the sheet.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/views.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "silhouette.h"

namespace cm {

/// A panel of a sheet: the crop that holds it, in sheet pixels (row 0 at the top).
struct SheetPanel {
    int x0 = 0, y0 = 0, width = 0, height = 0;
    double area = 0; ///< object pixels (coverage >= 0.5) of its drawing
};

struct PanelSearch {
    /// Components (8-connected, coverage >= 0.5) smaller than this fraction of the largest
    /// are marks (labels, specks): they join no panel and are left out of the crops.
    double mark_fraction = 0.02;
    /// Blank paper that separates two panels: at least this fraction of the sheet's larger
    /// side (and at least 3 pixels). Narrower gaps belong to one drawing.
    double gap_fraction = 0.01;
    /// Blank paper kept around a drawing in its crop: this fraction of the drawing's larger
    /// side, between 6 and 64 pixels, less where a mark or another panel comes closer.
    double margin_fraction = 0.08;
    /// A group of pieces (those no blank band divides) whose largest is under this fraction
    /// of the sheet's largest piece is text (a title, a number), not a drawing: its pieces
    /// are marks.
    double text_fraction = 0.06;
    /// The longer side, in pixels, at which an SVG sheet is drawn (views.load's `svg_size`).
    int svg_size = kDefaultSvgSize;
};

struct PanelsFound {
    std::vector<SheetPanel> panels; ///< in reading order: left to right, then top to bottom
    int marks = 0;                  ///< components that joined no panel
};

/// @brief The panels of a sheet from its coverage (width x height, row 0 at the top): the
/// larger components grouped by the blank rows and columns between them (a recursive
/// XY-cut on their boxes), each with a margin of blank paper. Rows of panels are those
/// whose vertical extents overlap.
PanelsFound find_panels(const std::vector<float>& coverage, int width, int height, const PanelSearch& opt = {});

/// @brief The coverage of a sheet to find its panels on: its silhouette under `so`, after a
/// frame drawn around the whole sheet (ink spanning at least 80 % of it both ways, thin) is
/// painted out in the paper's colour, up to three nested frames; `frames` gets their number.
std::vector<float> sheet_coverage(const Image& img, const ImageInfo& info, const SilhouetteOptions& so, int& frames);

/// The part of `sheet` that `p` covers.
Image crop_image(const Image& sheet, const SheetPanel& p);

/// The views of a manifest's sheets, each its panel's crop, per index of Manifest::views.
struct SheetViews {
    std::vector<Image> images;      ///< the crop; empty for a view drawn on its own
    std::vector<ImageInfo> infos;   ///< the sheet file's
    std::vector<SheetPanel> panels; ///< where the crop lies on its sheet
    std::vector<std::string> notes; ///< per sheet: the panels found, the marks left out
    bool on_sheet(std::size_t view) const { return !images.at(view).empty(); }
};

/// @brief Reads every sheet of `m` once and finds its panels; panel k is the k-th view the
/// sheet names. @throw cm::Error naming the manifest line and the sheet for an unreadable
/// image or a panel count that differs from the number of views named.
SheetViews split_sheets(const Manifest& m, const PanelSearch& opt = {});

} // namespace cm
