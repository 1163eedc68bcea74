// Progress and cancellation. Each running node gets an Interrupter, an
// openvdb::util::NullInterrupter so it can be handed to OpenVDB tools as is; the algorithms
// of the stages take a Progress, the one progress and cancel object of the contract.
#pragma once
#include <atomic>
#include <functional>
#include <memory>
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

/// @brief The one progress and cancel object every algorithm takes (OpenVDB's interrupter is
/// the model): it reports the fraction done of the algorithm's part of a stage, and a look at
/// it throws cm::Cancelled once a stop was asked for.
///
/// A stage hands its algorithm Context::progress("what"); a test or a tool passes a function
/// of the fraction, or nothing: a default Progress reports nowhere and never stops. Copies are
/// cheap and report to the same place; part() narrows one to a sub-range, for the steps of an
/// algorithm. Thread-safe as its destination is (an Interrupter is; a test's function must be
/// when the algorithm calls it from worker threads).
class Progress {
public:
    using Report = std::function<void(double fraction)>;
    using Check = std::function<void()>;
    Progress() = default;
    /// Reports to `report` (not explicit: a lambda converts), which may throw to stop.
    Progress(Report report);
    /// Reports nowhere; each look calls `check`, which may throw to stop.
    Progress(Check check);
    /// Reports to `report`; a look for a stop alone (check()) calls `check`.
    Progress(Report report, Check check);
    /// Reports to a node's interrupter, with `what` for the progress line.
    Progress(Interrupter& interrupter, std::string what);

    /// Reports `fraction` (clamped to [0, 1]) of this part; throws cm::Cancelled when a stop
    /// was asked for.
    void operator()(double fraction) const;
    /// Looks for a stop only, where no fraction is at hand (per chunk of a parallel loop);
    /// throws cm::Cancelled.
    void check() const;
    /// The part [lo, hi] of this one: its 0 is this one's lo, its 1 this one's hi.
    Progress part(double lo, double hi) const;
    /// Whether it reports anywhere.
    explicit operator bool() const { return dest_ != nullptr; }

private:
    struct Destination {
        Report report;
        Check check;
    };
    std::shared_ptr<const Destination> dest_;
    double lo_ = 0, hi_ = 1;
};

} // namespace cm
