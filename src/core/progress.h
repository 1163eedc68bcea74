// Progress and cancellation. Each running node gets an Interrupter, an
// openvdb::util::NullInterrupter so it can be handed to OpenVDB tools as is.
#pragma once
#include <atomic>
#include <mutex>
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

/// Test hook: with CONCEPTMESH_TEST_HOLD_NODE=<node id>[@<percent>] in the environment,
/// that node's first look at its interrupter (at or past that progress) prints
/// "conceptmesh: test hold: node <id> at <n>%" to stderr and waits there until a stop is
/// asked for, then goes on as if it had not seen it: the stop must be taken at the node's
/// next look. Other threads of the node that look while it is held wait there too, and take
/// the stop at that look. A test then knows the stage is running when it signals, and from the
/// progress in the message ("stopped at 53%") how soon the stage looked again.
class Interrupter : public openvdb::util::NullInterrupter {
public:
    /// `stop` (may be null): a stop of this run alone (a run given up before its later
    /// stages start), looked at beside the process-wide one.
    Interrupter(std::string node, ProgressSink* sink, const std::atomic<bool>* stop = nullptr);
    void start(const char* name = nullptr) override;
    void end() override;
    /// True once a cancel was requested; reports `percent` (0-100, -1 for none).
    bool wasInterrupted(int percent = -1) override;
    /// Fractional progress in [0, 1] of the whole stage; throws cm::Cancelled when cancelled.
    void step(double fraction, const std::string& what = {});
    /// Throws cm::Cancelled ("stopped at 12%") when a cancel was requested.
    void check();

private:
    bool held(); ///< the test hold; true when it just waited for the stop
    bool stop_asked() const {
        return cancel_requested().load(std::memory_order_relaxed) || (stop_ && stop_->load(std::memory_order_relaxed));
    }
    std::string node_;
    std::mutex what_mutex_; ///< step() may be called from worker threads
    std::string what_;
    ProgressSink* sink_;
    const std::atomic<bool>* stop_;
    std::atomic<int> last_percent_{-1};
    std::atomic<bool> hold_{false};
    std::atomic<bool> holding_{false}; ///< the hold has begun: every look of the node waits for the stop
    int hold_at_ = 0;
};

} // namespace cm
