// Running a pipeline or a stage while Python waits: the work on a thread of its own (the GIL
// released), the calling thread handing progress to the callback and watching for Ctrl-C.
// Python runs signal handlers and may call back into Python only on its main thread, with the
// GIL held: so the waiting is done there, in short slices.
#include <exception>
#include <optional>
#include <thread>

#include "core/error.h"
#include "module.h"

namespace cm::py {

namespace {

pyb::object event_object(const Event& e) {
    // Looked up each time (a dictionary lookup): a static Python object would outlive the interpreter.
    pyb::object type = pyb::module_::import("conceptmesh").attr("ProgressEvent");
    return type(e.kind, e.node, e.stage, e.percent, e.text, e.seconds);
}

} // namespace

void run_waiting(const std::function<void()>& work, EventQueue& events, const pyb::object& callback,
                 std::atomic<bool>& stop) {
    std::exception_ptr failure;
    std::thread worker([&] {
        try {
            work();
        } catch (...) {
            failure = std::current_exception();
        }
        events.done();
    });
    // The first Python error (Ctrl-C, or the callback's own) wins; the run is stopped for it and
    // waited for, so that its files are gone before the error reaches the caller.
    std::optional<pyb::error_already_set> raised;
    std::deque<Event> batch;
    for (bool ended = false; !ended;) {
        {
            pyb::gil_scoped_release released;
            ended = events.take(batch, std::chrono::milliseconds(50));
        }
        for (const Event& e : batch) {
            if (raised || callback.is_none()) break;
            try {
                callback(event_object(e));
            } catch (pyb::error_already_set& err) {
                raised.emplace(std::move(err));
                stop = true;
            }
        }
        batch.clear();
        if (!raised && PyErr_CheckSignals() != 0) {
            raised.emplace();
            stop = true;
        }
    }
    {
        pyb::gil_scoped_release released;
        worker.join();
    }
    if (raised) {
        // Ctrl-C: KeyboardInterrupt with the run's own word on where it stopped
        // ("node "refine" (...): stopped at 31%"), when the run did stop for it.
        if (raised->matches(PyExc_KeyboardInterrupt) && failure) {
            try {
                std::rethrow_exception(failure);
            } catch (const Cancelled& c) {
                PyErr_SetString(PyExc_KeyboardInterrupt, c.what());
                throw pyb::error_already_set();
            } catch (...) {}
        }
        throw std::move(*raised);
    }
    if (failure) {
        try {
            std::rethrow_exception(failure);
        } catch (const pyb::error_already_set&) {
            throw;
        } catch (const std::exception& e) {
            raise_error(e);
        }
    }
}

} // namespace cm::py
