// Reconciliation of drawn views that disagree (docs/views.md, "Drawings that disagree"):
// after the alignment has given every view one scale and one placement, each free axis
// view may scale its two image axes on their own and turn in its plane, then bend within a
// tolerance, so that what the views share agrees; opposite views are merged.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

struct ReconcileOptions {
    std::size_t primary = 0;         ///< the view that stays as drawn
    std::string opposite = "union";  ///< union | intersect | primary: views seeing along one line of sight
    double tolerance = 0.02;         ///< a view moved by more than this ratio is reported in a warning
    double max_turn_deg = 4.0;       ///< the largest turn searched
    double bend = 0.05;              ///< the largest bend, as a ratio of the silhouette's longest side
    std::string stretch = "uniform"; ///< uniform (one scale per view) | axes (each image axis its own)
};

/// What reconciliation did to one view, in the drawing's pixels.
struct ViewReconciliation {
    std::string name;
    double scale_x = 1, scale_y = 1; ///< stretch of the image axes
    double turn_deg = 0;             ///< turn in the image plane (counter-clockwise on the drawing)
    double warp_px = 0;              ///< the bend's largest displacement (its warp field's)
    double missing_pct = 0;          ///< share of the drawing the views' hull does not cover, after
    bool reconciled = false;         ///< false: an oblique view, left as drawn
};

/// @brief Reconciles aligned, drawn orthographic views (no fixed camera): fits per-axis
/// scales and a turn for every axis view but the primary, resamples the silhouettes (and
/// drawings) into the reconciled frame, merges views with one line of sight as
/// `opt.opposite` says, bends each view by a smooth warp within `opt.bend` where another
/// draws beyond it (so that the model keeps what every drawing shows), and sets the box to what the views span
/// and the cameras' placement. Views that already agree are left untouched, bit for bit.
/// Appends one warning per view moved more than `opt.tolerance`, and one per view whose
/// disagreement would need a bend beyond the tolerance (refused).
std::vector<ViewReconciliation> reconcile_views(Views& views, const ReconcileOptions& opt,
                                                std::vector<std::string>& warnings);

} // namespace cm
