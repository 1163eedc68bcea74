// Progress and cancellation. Each running node gets an Interrupter, an
// openvdb::util::NullInterrupter so it can be handed to OpenVDB tools as is.
#pragma once
#include <atomic>
#include <string>

#include <openvdb/util/NullInterrupter.h>

namespace cm {

/// Receives progress from running nodes (the CLI draws bars or prints lines).
class ProgressSink {
public:
    virtual ~ProgressSink() = default;
    virtual void started(const std::string& node, const std::string& stage) = 0;
    virtual void progress(const std::string& node, double percent, const std::string& what) = 0;
    virtual void finished(const std::string& node, double seconds) = 0;
    virtual void message(const std::string& node, const std::string& level, const std::string& text) = 0;
};

/// The process-wide cancel request (set by the Ctrl-C handler, or by a test).
std::atomic<bool>& cancel_requested();

class Interrupter : public openvdb::util::NullInterrupter {
public:
    Interrupter(std::string node, ProgressSink* sink) : node_(std::move(node)), sink_(sink) {}
    void start(const char* name = nullptr) override;
    void end() override;
    /// True once a cancel was requested; reports `percent` (0-100, -1 for none).
    bool wasInterrupted(int percent = -1) override;
    /// Fractional progress in [0, 1] of the whole stage; throws cm::Cancelled when cancelled.
    void step(double fraction, const std::string& what = {});
    /// Throws cm::Cancelled when a cancel was requested.
    void check() const;

private:
    std::string node_;
    std::string what_;
    ProgressSink* sink_;
    std::atomic<int> last_percent_{-1};
};

} // namespace cm
