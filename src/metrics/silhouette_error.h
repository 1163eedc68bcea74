// The silhouette error of a mesh against input views (docs/conventions.md):
// the mesh re-rendered through every view's camera and compared with the view's silhouette,
// as xor_pct (the seed paper's error) and IoU per view.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/views.h"
#include "render/raster.h"

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
};

/// @brief Re-renders the mesh through every view's camera and compares with the view's
/// silhouette (coverage >= 0.5). With `masks`, the renders (render_mask, one per view) are
/// kept there for a caller that shows them; `check` is called per chunk of each render (it
/// may throw to stop).
SilhouetteError silhouette_error(const Mesh& mesh, const Views& views,
                                 std::vector<std::vector<std::uint8_t>>* masks = nullptr,
                                 const RenderCheck& check = {});

/// The silhouette error of a mesh with its renders (render_mask, one per view).
struct SilhouetteRenders {
    SilhouetteError error;
    std::vector<std::vector<std::uint8_t>> masks;
    std::weak_ptr<const Mesh> mesh; ///< the mesh they are of
};

/// @brief silhouette_error() of `mesh` with its renders, made once per mesh and set of views:
/// the views keep it (Views::derived) for the next stage asking about the same mesh (a run's
/// preview and error stages render the same masks), and one asking while it is made waits.
std::shared_ptr<const SilhouetteRenders> shared_silhouette_error(const std::shared_ptr<const Mesh>& mesh,
                                                                 const Views& views, const RenderCheck& check = {});

} // namespace cm
