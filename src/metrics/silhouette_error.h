// The silhouette error of a mesh against input views (docs/conventions.md):
// the mesh re-rendered through every view's camera and compared with the view's silhouette,
// as xor_pct (the seed paper's error) and IoU per view.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/views.h"

namespace cm {

struct ViewError {
    std::string view;
    double input_px = 0;  ///< |S|: input silhouette pixels (coverage >= 0.5)
    double render_px = 0; ///< |R|: re-rendered pixels
    double xor_px = 0;    ///< |S xor R|
    double iou = 0;       ///< |S and R| / |S or R| (1 when both are empty)
    double xor_pct = 0;   ///< 100 |S xor R| / |S|
};
struct SilhouetteError {
    std::vector<ViewError> views;
    double xor_pct = 0;  ///< 100 * sum_v |S xor R| / sum_v |S| (the seed paper's error)
    double mean_iou = 0; ///< mean of the per-view IoU
    /// xor_pct.<view> and iou.<view> of every view, xor_pct, mean_iou, and `views`
    /// (views_json()): the figures of eval.silhouette_error.
    void report(Metrics& m) const;
    /// The views' figures as a JSON array: {"view", "xor_pct", "iou", "input_px", "render_px",
    /// "xor_px"} per view.
    std::string views_json() const;
    /// {"xor_pct", "mean_iou", "views"} as JSON text.
    std::string json() const;
};

/// A render of a mesh through a view's camera (render_mask): width * height bytes, 1 where
/// the mesh covers the pixel centre.
using SilhouetteMask = std::vector<std::uint8_t>;

/// @brief Re-renders the mesh through every view's camera and compares with the view's
/// silhouette (coverage >= 0.5). `progress` is looked at per chunk of each render
/// (progress.check()). @throw cm::Error for a view without a silhouette.
SilhouetteError silhouette_error(const Mesh& mesh, const Views& views, Progress progress = {});

// The steps of silhouette_error(), for a caller that shows the renders (one at a time).

/// @brief The render of the mesh through `view`'s camera that its error is measured on.
/// @throw cm::Error for a view without a silhouette.
SilhouetteMask silhouette_mask(const Mesh& mesh, const View& view, Progress progress = {});
/// The figures of `view` against `mask`, its silhouette_mask().
ViewError view_error(const View& view, const SilhouetteMask& mask);
/// The error of all views from each one's (`views` in the order of the views).
SilhouetteError combine_view_errors(std::vector<ViewError> views);

} // namespace cm
