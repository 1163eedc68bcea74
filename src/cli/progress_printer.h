// Shows stage progress on stderr: live bars on a terminal, plain lines otherwise.
#pragma once
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/progress.h"

namespace cm::cli {

class ProgressPrinter : public ProgressSink {
public:
    ProgressPrinter(bool quiet, bool verbose);
    ~ProgressPrinter() override;
    void started(const std::string& node, const std::string& stage) override;
    void progress(const std::string& node, double percent, const std::string& what) override;
    void finished(const std::string& node, double seconds) override;
    void message(const std::string& node, const std::string& level, const std::string& text) override;

private:
    void redraw_locked();
    void clear_locked();
    struct Bar {
        std::string stage;
        double percent = 0;
        std::string what;
        int last_printed = -1;
    };
    bool tty_, quiet_, verbose_;
    std::mutex mutex_;
    std::vector<std::string> order_;
    std::map<std::string, Bar> bars_;
    bool line_drawn_ = false;
    std::chrono::steady_clock::time_point last_draw_{};
};

} // namespace cm::cli
