#include "core/views.h"

#include <limits>

namespace cm {

std::shared_ptr<const void> DerivedData::get(const std::string& key,
                                             const std::function<std::shared_ptr<const void>()>& make) const {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = items_.find(key); it != items_.end()) return it->second;
    }
    std::shared_ptr<const void> made = make();
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.emplace(key, std::move(made)).first->second;
}

double Views::finest_pixel() const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& v : views)
        if (v.camera.orthographic() && v.camera.scale > 0) best = std::min(best, 1.0 / v.camera.scale);
    return std::isfinite(best) ? best : units_per_pixel;
}

} // namespace cm
