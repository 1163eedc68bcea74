// What the executor measures of the process while nodes run: resident memory (now, and the
// peak of each running node, sampled every few milliseconds) and CPU time.
#pragma once
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace cm::process {

inline std::size_t current_rss() {
    std::ifstream in("/proc/self/statm");
    std::size_t pages = 0, resident = 0;
    in >> pages >> resident;
    return resident * std::size_t(::sysconf(_SC_PAGESIZE));
}

/// CPU seconds (user + system, all threads) the process has used so far.
inline double cpu_seconds() {
    rusage u{};
    ::getrusage(RUSAGE_SELF, &u);
    auto secs = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return secs(u.ru_utime) + secs(u.ru_stime);
}

inline std::size_t peak_rss() {
    std::ifstream in("/proc/self/status");
    std::string key;
    while (in >> key) {
        if (key == "VmHWM:") {
            std::size_t kb = 0;
            in >> kb;
            return kb * 1024;
        }
        std::getline(in, key);
    }
    return 0;
}

/// Samples the resident set every few milliseconds and keeps, for each running
/// node, the highest value seen while it ran.
class MemoryMonitor {
public:
    explicit MemoryMonitor(std::size_t n) : peak_(n, 0), active_(n, 0) {
        thread_ = std::thread([this] {
            std::unique_lock<std::mutex> lock(mutex_);
            while (!stop_) {
                const std::size_t rss = current_rss();
                for (std::size_t i = 0; i < peak_.size(); ++i)
                    if (active_[i]) peak_[i] = std::max(peak_[i], rss);
                cv_.wait_for(lock, std::chrono::milliseconds(5));
            }
        });
    }
    ~MemoryMonitor() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    std::size_t begin(std::size_t i) {
        const std::size_t rss = current_rss();
        std::lock_guard<std::mutex> lock(mutex_);
        active_[i] = 1;
        peak_[i] = rss;
        return rss;
    }
    std::size_t end(std::size_t i) {
        const std::size_t rss = current_rss();
        std::lock_guard<std::mutex> lock(mutex_);
        active_[i] = 0;
        return peak_[i] = std::max(peak_[i], rss);
    }

private:
    std::vector<std::size_t> peak_;
    std::vector<char> active_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    std::thread thread_;
};

} // namespace cm::process
