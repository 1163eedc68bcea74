// The Stage interface. The host drives a fixed lifecycle:
//   1. info()       what the stage is: its signature() (name, ports, output) and the
//                   parameters its declare() adds;
//   2. configure()  takes the checked parameters: fills in the declared defaults, stores
//                   them, sets every member declare() bound, then calls check();
//   3. run()        does the work on its inputs and returns its output.
// info() and configure() are the host's and not virtual; a stage writes signature(),
// declare(), check() (when some combination cannot work) and run().
// A stage never calls another stage. It throws cm::Error with a sentence; the
// host prefixes the pipeline file, node id and stage name.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/algorithm.h"
#include "core/data.h"
#include "core/error.h"
#include "core/params.h"
#include "core/progress.h"

namespace cm {

struct PortSpec {
    std::string name;
    DataKind kind;
    std::string doc;
    bool optional = false;
};

/// What a stage says about itself: name, summary, input ports and output kind.
struct StageSignature {
    std::string name;    ///< "hull.carve"
    std::string summary; ///< one line
    std::vector<PortSpec> inputs;
    DataKind output;
};

/// The signature and the declared parameters.
struct StageInfo : StageSignature {
    std::vector<ParamSpec> params;
};

/// The inputs of one node, by port name.
class Inputs {
public:
    void set(const std::string& port, Data d) { data_[port] = std::move(d); }
    bool has(const std::string& port) const { return data_.count(port) != 0; }
    template <typename T>
    std::shared_ptr<const T> get(const std::string& port) const {
        auto it = data_.find(port);
        if (it == data_.end()) throw Error("input \"" + port + "\" is not connected");
        auto* p = std::get_if<std::shared_ptr<const T>>(&it->second);
        if (!p || !*p) throw Error("input \"" + port + "\" holds the wrong kind of data");
        return *p;
    }

private:
    std::map<std::string, Data> data_;
};

/// What a running stage may use of the host. It is the Metrics its algorithms' stats report to.
class Context : public Metrics {
public:
    struct Hooks {
        ProgressSink* sink = nullptr;
        /// Side outputs (silhouette PNGs, preview sheets) go here.
        std::filesystem::path side_output_dir = ".";
        std::function<void(const std::filesystem::path& tmp, const std::filesystem::path& final)> stage_file;
        /// A stop of this run alone (may be null; see Interrupter).
        const std::atomic<bool>* stop = nullptr;
    };
    Context(std::string node, std::string stage, Hooks hooks);

    const std::string& node() const { return node_; }
    const std::string& stage() const { return stage_; }
    Interrupter& interrupter() { return interrupter_; }
    /// The progress and cancel object of this stage's algorithms, with `what` for the
    /// progress line.
    Progress progress(std::string what) { return Progress(interrupter_, std::move(what)); }
    /// Progress in [0,1] of this stage; throws cm::Cancelled when cancelled.
    void progress(double fraction, const std::string& what = {}) { interrupter_.step(fraction, what); }
    void check_cancel() { interrupter_.check(); }

    void warn(const std::string& text) override;
    void info(const std::string& text);
    /// A figure for the run report (counts, sizes, errors). Thread-safe.
    void metric(const std::string& key, double value) override;
    void metric(const std::string& key, const std::string& value) override;
    /// A JSON object merged under the node's "metrics" in the report.
    void metric_json(const std::string& key, const std::string& json_text) override;
    using Metrics::count;
    using Metrics::per_view;
    const std::map<std::string, std::string>& metrics_json() const { return metrics_; }
    const std::vector<std::string>& warnings() const { return warnings_; }

    /// A temporary path in the same folder as `final_path` (missing folders on the way are
    /// made); the host renames it to `final_path` when the whole run succeeds and deletes
    /// it otherwise.
    std::filesystem::path output_file(const std::filesystem::path& final_path);
    const std::filesystem::path& side_output_dir() const { return hooks_.side_output_dir; }

private:
    std::string node_, stage_;
    Hooks hooks_;
    Interrupter interrupter_;
    std::mutex mutex_;
    std::map<std::string, std::string> metrics_; ///< key -> JSON text
    std::vector<std::string> warnings_;
};

class Stage {
public:
    virtual ~Stage() = default;
    /// The signature() and the parameters declare() adds, in their order.
    StageInfo info() const;
    /// The host's one call before run(). Stores `params` with every declared default that
    /// is missing filled in, sets every member declare() bound (output paths checked, see
    /// ParamSpec::OutputPath), then calls check(). Throws cm::Error for an undeclared or
    /// missing required parameter, a value outside its declaration, or what check() refuses.
    void configure(const ParamSet& params);
    /// Does the work on `inputs` with the members configure() set.
    virtual Data run(const Inputs& inputs, Context& ctx) = 0;
    /// The parameters configure() stored (defaults filled in; which the user gave).
    const ParamSet& params() const { return params_; }

protected:
    virtual StageSignature signature() const = 0;
    /// Declares each parameter once and binds it to the member that holds its value:
    /// b.add(member_, ParamSpec::Float(...)). Called by info() and by configure().
    virtual void declare(ParamBinder& b) { (void)b; }
    /// Called by configure() once every bound member is set. Throw cm::Error for
    /// combinations that cannot work (a missing file, exclusive options).
    virtual void check() {}

private:
    ParamSet params_;
};

} // namespace cm
