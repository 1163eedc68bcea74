#include "core/views.h"

#include <limits>

namespace cm {

double Views::finest_pixel() const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& v : views)
        if (v.camera.orthographic() && v.camera.scale > 0) best = std::min(best, 1.0 / v.camera.scale);
    return std::isfinite(best) ? best : units_per_pixel;
}

} // namespace cm
