#include "core/progress.h"

#include <algorithm>

#include "core/error.h"

namespace cm {

std::atomic<bool>& cancel_requested() {
    static std::atomic<bool> flag{false};
    return flag;
}

void Interrupter::start(const char* name) {
    if (name) what_ = name;
}

void Interrupter::end() {}

bool Interrupter::wasInterrupted(int percent) {
    if (percent >= 0 && sink_) {
        int last = last_percent_.load();
        if (percent != last && last_percent_.compare_exchange_strong(last, percent))
            sink_->progress(node_, percent, what_);
    }
    return cancel_requested().load(std::memory_order_relaxed);
}

void Interrupter::step(double fraction, const std::string& what) {
    if (!what.empty()) what_ = what;
    wasInterrupted(int(std::clamp(fraction, 0.0, 1.0) * 100.0));
    check();
}

void Interrupter::check() const {
    if (cancel_requested().load(std::memory_order_relaxed)) throw Cancelled();
}

} // namespace cm
