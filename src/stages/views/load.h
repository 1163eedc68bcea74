// Loading a views manifest into Views: one implementation shared by the views.load stage
// and the command-line tools (compare, preview).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/algorithm.h"
#include "core/views.h"
#include "reconcile.h"

namespace cm {

/// The parameters of views.load beside its manifest.
struct LoadViewsOptions {
    std::string keep;       ///< default for views whose manifest entry says keep: auto
    double align_tolerance; ///< relative disagreement on a shared axis that raises a warning
    std::string reconcile;  ///< on | off: reconcile drawn views that disagree (reconcile.h)
    std::string opposite;   ///< union | intersect | primary: views seeing along one line of sight
    double bend;            ///< the largest bend, a ratio of the silhouette's longest side
    std::string stretch;    ///< uniform | axes: how a reconciled view may scale
    int svg_size;           ///< the longer side, in pixels, at which SVG drawings are drawn

    LoadViewsOptions() { set_declared_defaults(*this); }
    /// `keep`, `align_tolerance`, `reconcile`, `opposite`, `bend`, `svg_size` and `stretch`.
    void declare(ParamBinder& b);
};

struct LoadViewsStats {
    std::vector<std::string> warnings;          ///< views disagreeing on an axis
    std::vector<std::string> notes;             ///< dropped marks, filled regions (the stage's info lines)
    std::vector<std::string> names;             ///< the views, in the manifest's order
    std::vector<double> silhouette_area_px;     ///< per view: its coverage summed, in pixels
    std::optional<Vec3d> bounds_size;           ///< the size of the views' box, when they have one
    std::vector<ViewReconciliation> reconciled; ///< per view, when reconciliation ran
    std::vector<std::size_t> pockets_filled;    ///< per view: pockets of partial coverage filled (pockets.h)
    /// The warnings, then `views` (their number), `pockets_filled` (all views'),
    /// `silhouette_area_px.<view>` and, with a
    /// box, `bounds_size`; after reconciliation `reconcile.<view>.{scale_x, scale_y,
    /// turn_deg, warp_px, missing_pct}`; not the notes.
    void report(Metrics& m) const;
};

/// @brief Reads the manifest and its images, extracts the silhouettes, sets up the cameras
/// and aligns hand-drawn views into the output frame (docs/conventions.md). `progress`
/// reports reading the views up to 0.8, then 0.8 before aligning them.
/// @throw cm::Error naming the manifest line or the view (unreadable image, empty silhouette, ...).
Result<Views, LoadViewsStats> load_views(const std::filesystem::path& manifest, const LoadViewsOptions& opt,
                                         Progress progress = {});

/// The silhouette as a grey image (white = object), for side outputs and previews.
Image silhouette_image(const View& v);

} // namespace cm
