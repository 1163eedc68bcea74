// Loading a views manifest into Views: one implementation shared by the views.load stage
// and the command-line tools (compare, preview).
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/views.h"

namespace cm {

struct LoadViewsOptions {
    std::string keep = "auto";     ///< default for views whose manifest entry says keep: auto
    double align_tolerance = 0.02; ///< relative disagreement on a shared axis that raises a warning
};

struct LoadViewsReport {
    std::vector<std::string> warnings; ///< views disagreeing on an axis
    std::vector<std::string> notes;    ///< dropped marks, filled regions
};

/// @brief Reads the manifest and its images, extracts the silhouettes, sets up the cameras
/// and aligns hand-drawn views into the output frame (docs/conventions.md).
/// `progress(fraction)` is called between steps when given.
/// @throw cm::Error naming the manifest line or the view (unreadable image, empty silhouette, ...).
Views load_views(const std::filesystem::path& manifest, const LoadViewsOptions& opt, LoadViewsReport& report,
                 const std::function<void(double)>& progress = {});

/// The silhouette as a grey image (white = object), for side outputs and previews.
Image silhouette_image(const View& v);

} // namespace cm
