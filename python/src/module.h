// The Python module's shared pieces: the registry it runs stages from, the numpy faces of the
// data that flows between stages, and running work on a thread while Python waits.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/data.h"
#include "core/progress.h"
#include "plugins/registry.h"

namespace cm::py {

namespace pyb = pybind11;

/// The module's registry: the plugins beside the module (build tree) or installed, those of
/// CONCEPTMESH_PLUGIN_PATH, and the memory.* stages that hand a host's data into a pipeline.
const Registry& registry();

/// Data held for memory.* nodes, by key: put() gives a fresh key, drop() forgets it.
std::string memory_put(Data d);
void memory_drop(const std::string& key);
/// Registers memory.mesh, memory.views and memory.volume in `r`.
void add_memory_stages(Registry& r);

/// Data -> its Python object (Mesh, Views, Volume, the written paths, the report as a dict).
pyb::object to_python(const Data& d);
/// A Python Mesh, Views or Volume -> Data; an error names `what` when it is none of them.
Data from_python(const pyb::handle& obj, const std::string& what);

void bind_data(pyb::module_& m);
void bind_stages(pyb::module_& m);
void bind_pipeline(pyb::module_& m);
void bind_errors(pyb::module_& m);

/// One progress event, as the waiting thread hands it to Python (conceptmesh.ProgressEvent).
struct Event {
    std::string kind, node, stage, text;
    double percent = -1, seconds = 0;
};

/// A ProgressSink that queues events for the waiting thread (run_waiting).
class EventQueue : public ProgressSink {
public:
    void started(const std::string& node, const std::string& stage) override {
        push({"started", node, stage, {}, 0, 0});
    }
    void progress(const std::string& node, double percent, const std::string& what) override {
        push({"progress", node, {}, what, percent, 0});
    }
    void finished(const std::string& node, double seconds) override { push({"finished", node, {}, {}, 100, seconds}); }
    void message(const std::string& node, const std::string& level, const std::string& text) override {
        push({level, node, {}, text, -1, 0});
    }
    void done() {
        std::lock_guard<std::mutex> lock(mutex_);
        done_ = true;
        cv_.notify_all();
    }
    /// Waits up to `slice` for events or the end; returns what came and whether it ended.
    bool take(std::deque<Event>& out, std::chrono::milliseconds slice) {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait_for(lock, slice, [this] { return done_ || !events_.empty(); });
        out.swap(events_);
        return done_;
    }

private:
    void push(Event e) {
        std::lock_guard<std::mutex> lock(mutex_);
        events_.push_back(std::move(e));
        cv_.notify_all();
    }
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Event> events_;
    bool done_ = false;
};

/// Runs `work` on a thread of its own with the GIL released, while the calling thread
/// hands the progress events of `sink` to `callback` (may be None) and looks for Ctrl-C
/// every 50 ms. Ctrl-C or an exception in the callback sets `stop` (the run's interrupter
/// stops), waits for `work` to end and raises it. A C++ exception of `work` becomes the
/// module's exception (translate_error).
void run_waiting(const std::function<void()>& work, EventQueue& events, const pyb::object& callback,
                 std::atomic<bool>& stop);

/// Raises the module's exception for a conceptmesh message: conceptmesh.Error, or its
/// FileError (an OSError) or ParameterError (a ValueError), with .node and .stage taken from
/// the message's "node "id" (stage)" part; Cancelled as KeyboardInterrupt.
[[noreturn]] void raise_error(const std::exception& e, const std::string& stage = {});
/// The same inside a pybind11 call: any std::exception from `f` becomes the module's.
template <typename F>
auto translated(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const pyb::error_already_set&) {
        throw;
    } catch (const pyb::builtin_exception&) {
        throw;
    } catch (const std::exception& e) {
        raise_error(e);
    }
}

} // namespace cm::py
