// The contact sheet of a mesh against its views: per view the input drawing, the mesh
// shaded from that view, and an overlay of the two silhouettes.
#pragma once
#include <functional>
#include <string>

#include "core/mesh.h"
#include "core/views.h"
#include "metrics/silhouette_error.h"
#include "render/raster.h"

namespace cm {

struct PreviewOptions {
    int panel = 320;   ///< each panel fits in panel x panel pixels
    std::string title; ///< printed at the top (e.g. the mesh file)
    /// Called between the steps with the fraction done; may throw (cm::Cancelled) to stop.
    std::function<void(double)> progress;
    /// Called per chunk of the renders and pastes, from worker threads; may throw to stop.
    RenderCheck check;
};

/// Overlay colours: pixels only in the input silhouette (the mesh misses them) and pixels
/// only in the re-rendered mesh (the mesh adds them).
inline constexpr float kInputOnly[3] = {0.93f, 0.33f, 0.10f};
inline constexpr float kMeshOnly[3] = {0.10f, 0.47f, 0.93f};

/// @brief Builds the sheet (RGB) and fills `error` with the silhouette error it shows.
Image make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt, SilhouetteError& error);
/// @brief The sheet of the silhouette error and renders of `mesh` already made (see
/// shared_silhouette_error).
Image make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt,
                         const SilhouetteRenders& renders);

} // namespace cm
