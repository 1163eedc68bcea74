// The contact sheet of a mesh against its views: per view the input drawing, the mesh
// shaded from that view, and an overlay of the two silhouettes.
#pragma once
#include <string>

#include "core/algorithm.h"
#include "core/mesh.h"
#include "core/views.h"
#include "metrics/silhouette_error.h"

namespace cm {

/// The parameters of eval.preview that shape the sheet.
struct PreviewOptions {
    int panel;         ///< each panel fits in panel x panel pixels
    std::string title; ///< printed at the top (e.g. the mesh file)

    PreviewOptions() { set_declared_defaults(*this); }
    /// `panel` and `title`.
    void declare(ParamBinder& b);
};

struct PreviewStats {
    SilhouetteError error; ///< the silhouette error the sheet shows
    /// xor_pct and mean_iou.
    void report(Metrics& m) const;
};

/// Overlay colours: pixels only in the input silhouette (the mesh misses them) and pixels
/// only in the re-rendered mesh (the mesh adds them).
inline constexpr float kInputOnly[3] = {0.93f, 0.33f, 0.10f};
inline constexpr float kMeshOnly[3] = {0.10f, 0.47f, 0.93f};

/// @brief Builds the sheet (RGB) with the silhouette error it shows. `progress` has the
/// fraction done between the steps and is looked at per chunk of the renders and pastes.
/// @throw cm::Error without views or for a panel under 32 pixels; cm::Cancelled from `progress`.
Result<Image, PreviewStats> make_preview_sheet(const Mesh& mesh, const Views& views, const PreviewOptions& opt,
                                               Progress progress = {});

} // namespace cm
