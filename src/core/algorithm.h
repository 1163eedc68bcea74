// The algorithm contract (OpenVDB's tool functions are the model). An algorithm is a function
// of its inputs and one options struct, taking one Progress (core/progress.h), returning its
// result with its stats:
//
//     struct SmoothOptions {
//         int iterations;
//         double factor;
//         SmoothOptions() { set_declared_defaults(*this); }
//         void declare(ParamBinder& b); // each parameter once: name, default, range, unit, doc
//     };
//     struct SmoothStats {
//         std::size_t clamped_steps = 0;
//         void report(Metrics& m) const; // by name, into the run's metrics
//     };
//     Result<Mesh, SmoothStats> smooth_mesh(const Mesh& in, const SmoothOptions& opt, Progress progress = {});
//
// The stage binds the options struct as its parameters (declare() calls opt_.declare(b)), so
// each default is declared once, in the declaration that also drives YAML, --set, the
// schema and `conceptmesh stages --describe`; the options' constructor takes the same
// defaults, so an algorithm called from a test or a tool behaves as the stage does. The
// stage runs the algorithm, hands the stats to the run (stats.report(ctx)), and returns the
// result through its port: stages exchange data only through their ports.
#pragma once
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/params.h"
#include "core/progress.h"

namespace cm {

/// Where an algorithm's stats report themselves, by name: the run's metrics of one node
/// (cm::Context), or anything else that collects figures. Thread-safe in Context.
class Metrics {
public:
    virtual ~Metrics() = default;
    /// A figure (counts, sizes, errors).
    virtual void metric(const std::string& key, double value) = 0;
    virtual void metric(const std::string& key, const std::string& value) = 0;
    /// A JSON value (an object of per-view figures, ...) as its text.
    virtual void metric_json(const std::string& key, const std::string& json_text) = 0;
    /// A sentence the user should read (a warning of the run).
    virtual void warn(const std::string& text) = 0;

    /// A count, as a figure.
    void count(const std::string& key, std::size_t n) { metric(key, double(n)); }
    /// A yes/no figure ("yes" or "no").
    void flag(const std::string& key, bool yes) { metric(key, std::string(yes ? "yes" : "no")); }
    /// A count that is news only when it is not zero: then it is reported, and said as the
    /// warning "<n> <what>".
    void warned_count(const std::string& key, std::size_t n, const std::string& what) {
        if (!n) return;
        count(key, n);
        warn(std::to_string(n) + " " + what);
    }
    /// One figure per view, as a JSON object {"front": 1.5, ...} (names escaped as JSON needs).
    void per_view(const std::string& key, const std::vector<std::string>& views, const std::vector<double>& values);
    /// One count per view, as a JSON object of whole numbers {"front": 12, ...}.
    void per_view(const std::string& key, const std::vector<std::string>& views,
                  const std::vector<std::size_t>& counts);
};

/// What an algorithm returns: its result and its stats (`auto [mesh, stats] = ...`).
template <typename T, typename Stats>
struct Result {
    T value;
    Stats stats;
};

/// Runs an algorithm of `value` in its place: `run(const T& input)` gives the Result whose
/// value replaces `value`; its stats are returned. For the `*_in_place` forms of algorithms
/// that read their input while they write a new one.
template <typename T, typename Run>
auto replace_in_place(T& value, Run&& run) {
    const T input = std::move(value);
    auto r = std::forward<Run>(run)(input);
    value = std::move(r.value);
    return r.stats;
}

} // namespace cm
