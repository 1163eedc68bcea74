#include "cli/progress_printer.h"

#include <unistd.h>
#include <algorithm>
#include <cstdio>

#include "cli/commands.h"

namespace cm::cli {

ProgressPrinter::ProgressPrinter(bool quiet, bool verbose) : tty_(::isatty(2) != 0), quiet_(quiet), verbose_(verbose) {}

ProgressPrinter::~ProgressPrinter() {
    std::lock_guard<std::mutex> lock(mutex_);
    clear_locked();
}

void ProgressPrinter::clear_locked() {
    if (line_drawn_) std::fputs("\r\033[K", stderr);
    line_drawn_ = false;
}

void ProgressPrinter::redraw_locked() {
    if (!tty_ || quiet_) return;
    std::string line;
    for (const auto& id : order_) {
        const Bar& b = bars_[id];
        const int width = 20, fill = int(b.percent / 100.0 * width + 0.5);
        char pct[16];
        std::snprintf(pct, sizeof pct, "%3d%%", int(b.percent));
        line += (line.empty() ? "" : "  ") + id + " [" + std::string(std::size_t(fill), '#') +
                std::string(std::size_t(width - fill), ' ') + "] " + pct;
    }
    std::fputs(("\r\033[K" + line).c_str(), stderr);
    std::fflush(stderr);
    line_drawn_ = !line.empty();
    last_draw_ = std::chrono::steady_clock::now();
}

void ProgressPrinter::started(const std::string& node, const std::string& stage) {
    if (quiet_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    bars_[node] = Bar{stage, 0, {}, -1};
    order_.push_back(node);
    if (tty_) redraw_locked();
    else std::fprintf(stderr, "conceptmesh: [%s] %s started\n", node.c_str(), stage.c_str());
}

void ProgressPrinter::progress(const std::string& node, double percent, const std::string& what) {
    if (quiet_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = bars_.find(node);
    if (it == bars_.end()) return;
    it->second.percent = std::clamp(percent, 0.0, 100.0);
    it->second.what = what;
    if (tty_) {
        if (std::chrono::steady_clock::now() - last_draw_ > std::chrono::milliseconds(50)) redraw_locked();
    } else if (verbose_) {
        // Plain output: a line per quarter, so logs stay short.
        const int q = int(percent) / 25;
        if (q > it->second.last_printed && q < 4) {
            it->second.last_printed = q;
            std::fprintf(stderr, "conceptmesh: [%s] %d%%%s\n", node.c_str(), q * 25,
                         what.empty() ? "" : (" " + what).c_str());
        }
    }
}

void ProgressPrinter::finished(const std::string& node, double seconds) {
    if (quiet_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = bars_.find(node);
    const std::string stage = it != bars_.end() ? it->second.stage : "";
    bars_.erase(node);
    order_.erase(std::remove(order_.begin(), order_.end(), node), order_.end());
    clear_locked();
    std::fprintf(stderr, "conceptmesh: [%s] %s done in %.2f s\n", node.c_str(), stage.c_str(), seconds);
    redraw_locked();
}

void ProgressPrinter::message(const std::string& node, const std::string& level, const std::string& text) {
    if (quiet_ && level != "warning") return;
    if (level == "info" && !verbose_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    clear_locked();
    std::fprintf(stderr, "conceptmesh: %s: [%s] %s\n", level.c_str(), node.c_str(), shorten_long_words(text).c_str());
    redraw_locked();
}

} // namespace cm::cli
