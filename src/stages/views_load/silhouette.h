// From a drawing to a silhouette (coverage in [0,1], anti-aliased edges kept).
#pragma once
#include <string>
#include <vector>

#include "core/image_io.h"
#include "core/views.h"

namespace cm {

struct SilhouetteOptions {
    std::string background = "auto";   ///< auto | alpha | colour ("#rrggbb", "r,g,b" in 0-255, "white", "black")
    double threshold = -1;             ///< colour distance (0-1) to call a pixel object; <0: from the border's spread
    std::string keep = "auto";         ///< auto: drop specks and small separate marks; largest; all
};

struct SilhouetteResult {
    std::vector<float> coverage;
    std::string method;                ///< "alpha" or "background"
    double threshold = 0;
    int components_kept = 0, components_dropped = 0;
};

/// Throws cm::Error for an unusable option (bad colour).
SilhouetteResult extract_silhouette(const Image& img, const ImageInfo& info, const SilhouetteOptions& opt);

} // namespace cm
