#include "core/views.h"

#include <limits>

#include <tbb/collaborative_call_once.h>

namespace cm {

struct DerivedData::Slot {
    tbb::collaborative_once_flag once;
    std::shared_ptr<const void> item;
};

std::shared_ptr<const void> DerivedData::get(const std::string& key,
                                             const std::function<std::shared_ptr<const void>()>& make) const {
    std::shared_ptr<Slot> slot;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto& s = items_[key];
        if (!s) s = std::make_shared<Slot>();
        slot = s;
    }
    tbb::collaborative_call_once(slot->once, [&] { slot->item = make(); });
    return slot->item;
}

double Views::finest_pixel() const {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& v : views)
        if (v.camera.orthographic() && v.camera.scale > 0) best = std::min(best, 1.0 / v.camera.scale);
    return std::isfinite(best) ? best : units_per_pixel;
}

} // namespace cm
