#include "core/progress.h"

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

#include "core/error.h"

namespace cm {

std::atomic<bool>& cancel_requested() {
    static std::atomic<bool> flag{false};
    return flag;
}

Interrupter::Interrupter(std::string node, ProgressSink* sink, const std::atomic<bool>* stop)
    : node_(std::move(node)), sink_(sink), stop_(stop) {
    // "<node>" or "<node>@<percent>": the node's first look at or past that progress.
    const char* env = std::getenv("CONCEPTMESH_TEST_HOLD_NODE");
    if (!env) return;
    const std::string hold = env;
    const std::size_t at = hold.find('@');
    if (hold.substr(0, at) != node_) return;
    hold_at_ = at == std::string::npos ? 0 : std::atoi(hold.c_str() + at + 1);
    hold_ = true;
}

bool Interrupter::held() {
    if (holding_.load(std::memory_order_acquire)) {
        // Another thread of this node is held: this look waits for the stop as well, and takes
        // it (a stage working on several threads goes no further than each one's next look).
        while (!stop_asked()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        return false;
    }
    if (!hold_.load(std::memory_order_relaxed) || std::max(0, last_percent_.load()) < hold_at_ ||
        !hold_.exchange(false))
        return false;
    holding_.store(true, std::memory_order_release);
    const std::string line = "conceptmesh: test hold: node " + node_ + " at " + std::to_string(last_percent_) + "%\n";
    [[maybe_unused]] auto n = ::write(2, line.data(), line.size());
    while (!stop_asked()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return true;
}

void Interrupter::start(const char* name) {
    if (!name) return;
    std::lock_guard<std::mutex> lock(what_mutex_);
    what_ = name;
}

void Interrupter::end() {}

bool Interrupter::wasInterrupted(int percent) {
    if (percent >= 0) {
        int last = last_percent_.load();
        if (percent != last && last_percent_.compare_exchange_strong(last, percent) && sink_) {
            std::string what;
            {
                std::lock_guard<std::mutex> lock(what_mutex_);
                what = what_;
            }
            sink_->progress(node_, percent, what);
        }
    }
    if (held()) return false;
    return stop_asked();
}

void Interrupter::step(double fraction, const std::string& what) {
    if (!what.empty()) {
        std::lock_guard<std::mutex> lock(what_mutex_);
        what_ = what;
    }
    if (!wasInterrupted(int(std::clamp(fraction, 0.0, 1.0) * 100.0))) return;
    check();
}

void Interrupter::check() {
    if (held() || !stop_asked()) return;
    const int at = last_percent_.load();
    throw Cancelled(at >= 0 ? "stopped at " + std::to_string(at) + "%" : std::string("stopped"));
}

Progress::Progress(Report report) : Progress(std::move(report), Check{}) {}

Progress::Progress(Check check) : Progress(Report{}, std::move(check)) {}

Progress::Progress(Report report, Check check)
    : dest_(report || check ? std::make_shared<const Destination>(Destination{std::move(report), std::move(check)})
                            : nullptr) {}

Progress::Progress(Interrupter& interrupter, std::string what)
    : Progress([&interrupter, what = std::move(what)](double f) { interrupter.step(f, what); },
               [&interrupter] { interrupter.check(); }) {}

void Progress::operator()(double fraction) const {
    if (!dest_) return;
    if (dest_->report) dest_->report(lo_ + (hi_ - lo_) * std::clamp(fraction, 0.0, 1.0));
    else dest_->check();
}

void Progress::check() const {
    if (dest_ && dest_->check) dest_->check();
}

Progress Progress::part(double lo, double hi) const {
    Progress p = *this;
    p.lo_ = lo_ + (hi_ - lo_) * lo;
    p.hi_ = lo_ + (hi_ - lo_) * hi;
    return p;
}

} // namespace cm
