// Runs a validated pipeline: nodes in dependency order on a TBB task group,
// independent branches at once; records time and memory per node; stages
// output files under temporary names and renames them only when all succeeded.
#include <atomic>
#include <chrono>
#include <fstream>
#include <functional>

#include <openvdb/Exceptions.h>
#include <tbb/task_group.h>
#include <nlohmann/json.hpp>

#include "core/progress.h"
#include "io/file_commit.h"
#include "pipeline/pipeline.h"
#include "pipeline/process_stats.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm {

namespace {

/// What a library threw, said so that a user can act on it: OpenVDB's "ArithmeticError:
/// Tried to initialize an affine transform from a nearly singular matrix" and a bare
/// std::bad_alloc, from a stage that did not catch them itself.
std::string plain_message(const std::exception& e) {
    if (dynamic_cast<const Error*>(&e)) return e.what();
    if (auto* f = dynamic_cast<const fs::filesystem_error*>(&e)) // "filesystem error: status: ... [path]"
        return "cannot use the path \"" + f->path1().string() + "\": " + f->code().message();
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return "out of memory (the machine could not give what the stage needed): lower the resolution or the "
               "image sizes, or see --max-memory";
    if (auto* vdb = dynamic_cast<const openvdb::Exception*>(&e)) {
        std::string text = vdb->what();
        if (const auto colon = text.find(": "); colon != std::string::npos && text.find("Error") < colon)
            text.erase(0, colon + 2); // "ArithmeticError: ..." -> "..."
        if (dynamic_cast<const openvdb::ArithmeticError*>(&e))
            return "a grid computation went out of range (OpenVDB: " + text +
                   "): the voxel size or the object's box is too small or too large for its units; check the views' "
                   "cameras, bounds and the resolution";
        return "the grid library failed (OpenVDB: " + text + ")";
    }
    return e.what();
}

/// Passes progress on to the run's sink, or, while the run is not yet validated, keeps it:
/// what the first nodes report is told once the checks have passed (held()'s false), and
/// never when they fail. A user reads "started" only of a run that goes ahead.
class HeldSink : public ProgressSink {
public:
    HeldSink(ProgressSink* to, bool hold) : to_(to), holding_(hold && to) {}
    void started(const std::string& node, const std::string& stage) override {
        pass([=](ProgressSink& s) { s.started(node, stage); });
    }
    void progress(const std::string& node, double percent, const std::string& what) override {
        pass([=](ProgressSink& s) { s.progress(node, percent, what); });
    }
    void finished(const std::string& node, double seconds) override {
        pass([=](ProgressSink& s) { s.finished(node, seconds); });
    }
    void message(const std::string& node, const std::string& level, const std::string& text) override {
        pass([=](ProgressSink& s) { s.message(node, level, text); });
    }
    /// Tells what was kept, then passes everything on as it comes.
    void release() {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto& e : kept_) e(*to_);
        kept_.clear();
        holding_ = false;
    }
    ProgressSink* sink() { return to_ ? this : nullptr; }

private:
    void pass(std::function<void(ProgressSink&)> e) {
        if (!to_) return;
        std::lock_guard<std::mutex> lock(mutex_); // one event at a time, in order
        if (holding_) kept_.push_back(std::move(e));
        else e(*to_);
    }
    ProgressSink* to_;
    std::mutex mutex_;
    bool holding_;
    std::vector<std::function<void(ProgressSink&)>> kept_;
};

/// One run of a validated pipeline: each node is launched on the task group once all its
/// inputs are done, and an output is released once its last consumer has run.
class PipelineRun {
public:
    /// `gated`: the stages of the nodes with inputs come later, by open(); until then only
    /// the nodes start() is given run (see run_pipeline).
    PipelineRun(const Pipeline& p, std::vector<std::unique_ptr<Stage>> stages, const RunOptions& opt,
                bool gated = false)
        : p_(p),
          opt_(opt),
          index_(p.node_index()),
          stages_(std::move(stages)),
          n_(p.nodes.size()),
          dependents_(n_),
          pending_(n_),
          consumers_(n_),
          outputs_(n_),
          records_(n_),
          memory_(n_),
          sink_(opt.sink, gated),
          stop_(opt.stop ? opt.stop : &own_stop_),
          open_(!gated) {
        schedule();
    }
    /// Starts these nodes (inputs none, stages given) while the rest is validated.
    void start(const std::vector<std::size_t>& nodes) {
        for (std::size_t i : nodes) {
            started_[i] = 1;
            launch(i);
        }
    }
    /// The other nodes' stages: a node whose inputs are ready starts now, the others as
    /// their inputs are done.
    void open(std::vector<std::unique_ptr<Stage>> stages) {
        std::vector<std::size_t> ready;
        {
            std::lock_guard<std::mutex> lock(gate_mutex_);
            for (std::size_t i = 0; i < n_; ++i)
                if (!stages_[i]) stages_[i] = std::move(stages[i]);
            open_ = true;
            ready.swap(waiting_);
        }
        sink_.release();
        for (std::size_t i : ready) launch(i);
    }
    /// Gives the run up before it was opened: the started nodes are asked to stop, waited
    /// for, and whatever they staged is deleted.
    void abandon() {
        *stop_ = true;
        group_.wait();
        files_.discard();
    }
    /// Runs every node; commits the staged files when all succeeded, else discards them
    /// and throws the first failure (prefixed with its node).
    RunResult run();

private:
    void schedule();
    void launch(std::size_t i) {
        group_.run([this, i] { execute(i); });
    }
    /// Launches a node whose inputs are done, or keeps it for open().
    void ready(std::size_t i) {
        {
            std::lock_guard<std::mutex> lock(gate_mutex_);
            if (!open_) {
                waiting_.push_back(i);
                return;
            }
        }
        launch(i);
    }
    void execute(std::size_t i);
    /// A stop asked for by the user or the host (RunOptions::stop); not abandon()'s, after which
    /// a node already launched still starts and is stopped at its first look.
    bool stopped() const { return cancel_requested() || (opt_.stop && opt_.stop->load()); }
    Context context(const PipelineNode& node);
    /// Runs the node's stage; false when it failed (the first failure is kept).
    bool run_node(std::size_t i, const Inputs& in, Context& ctx);
    void record(std::size_t i, const Context& ctx, double seconds, double cpu, std::size_t rss0, std::size_t peak);
    /// Frees the node's inputs nobody else needs (grids can be large) and launches the
    /// dependents it was the last input of.
    void release(std::size_t i);
    RunResult commit();

    const Pipeline& p_;
    const RunOptions& opt_;
    const std::map<std::string, std::size_t> index_;
    std::vector<std::unique_ptr<Stage>> stages_;
    const std::size_t n_;
    std::vector<std::vector<std::size_t>> dependents_;
    std::vector<std::atomic<int>> pending_;   ///< inputs not done yet
    std::vector<std::atomic<int>> consumers_; ///< dependents not done yet
    std::vector<Data> outputs_;
    std::vector<NodeRecord> records_;
    std::mutex error_mutex_;
    FileCommit files_;
    std::atomic<bool> failed_{false};
    std::string first_error_;
    bool cancelled_ = false;
    process::MemoryMonitor memory_;
    HeldSink sink_;
    std::atomic<bool> own_stop_{false};
    std::atomic<bool>* stop_; ///< this run given up (abandon) or stopped by its host (RunOptions::stop)
    std::mutex gate_mutex_;
    bool open_;                        ///< every node's stage is there
    std::vector<std::size_t> waiting_; ///< nodes ready before open()
    std::vector<char> started_ = std::vector<char>(n_, 0);
    tbb::task_group group_;
    const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

void PipelineRun::schedule() {
    for (std::size_t i = 0; i < n_; ++i) {
        pending_[i] = int(p_.nodes[i].inputs.size());
        consumers_[i] = 0;
    }
    for (std::size_t i = 0; i < n_; ++i)
        for (const auto& [port, src] : p_.nodes[i].inputs) {
            dependents_[index_.at(src)].push_back(i);
            ++consumers_[index_.at(src)];
        }
}

RunResult PipelineRun::run() {
    // Roots are decided before any task runs: a finished root decrements its
    // dependents' counters, which must not make them look like roots here too.
    std::vector<std::size_t> roots;
    for (std::size_t i = 0; i < n_; ++i)
        if (p_.nodes[i].inputs.empty() && !started_[i]) roots.push_back(i);
    for (std::size_t i : roots) launch(i);
    group_.wait();
    // A stop asked for while the last stages ran (a stage that does not look, such as a
    // write in progress) still means no output.
    if (!failed_ && stopped()) {
        failed_ = true;
        cancelled_ = true;
        first_error_ = p_.file.string() + ": stopped when the last stages had finished";
    }
    if (failed_) {
        files_.discard();
        if (cancelled_) throw Cancelled(first_error_);
        throw Error(first_error_);
    }
    return commit();
}

Context PipelineRun::context(const PipelineNode& node) {
    Context::Hooks hooks;
    hooks.sink = sink_.sink();
    hooks.side_output_dir = opt_.side_output_dir;
    hooks.stage_file = [this](const fs::path& tmp, const fs::path& fin) { files_.add(tmp, fin); };
    hooks.stop = stop_;
    return Context(node.id, node.stage, hooks);
}

void PipelineRun::execute(std::size_t i) {
    if (failed_) return;
    const auto& node = p_.nodes[i];
    Context ctx = context(node);
    Inputs in;
    for (const auto& [port, src] : node.inputs) in.set(port, outputs_[index_.at(src)]);
    if (auto* sink = sink_.sink()) sink->started(node.id, node.stage);
    const std::size_t rss0 = memory_.begin(i);
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = process::cpu_seconds();
    const bool ok = run_node(i, in, ctx);
    const std::size_t peak = memory_.end(i);
    if (!ok) return;
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    record(i, ctx, secs, process::cpu_seconds() - cpu0, rss0, peak);
    if (auto* sink = sink_.sink()) sink->finished(node.id, secs);
    if (opt_.on_output) opt_.on_output(node.id, outputs_[i]);
    in = Inputs();
    release(i);
}

bool PipelineRun::run_node(std::size_t i, const Inputs& in, Context& ctx) {
    const auto& node = p_.nodes[i];
    try {
        if (stopped()) throw Cancelled(); // no new stage after a stop was asked for
        Data d = stages_[i]->run(in, ctx);
        if (kind_of(d) != node.info.output)
            throw Error(std::string("the stage returned ") + to_string(kind_of(d)) + " instead of " +
                        to_string(node.info.output));
        outputs_[i] = std::move(d);
        return true;
    } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(error_mutex_);
        if (!failed_.exchange(true)) {
            cancelled_ = dynamic_cast<const Cancelled*>(&e) != nullptr;
            first_error_ = p_.where(node) + files_.with_final_names(plain_message(e));
        }
        return false;
    }
}

void PipelineRun::record(std::size_t i, const Context& ctx, double seconds, double cpu, std::size_t rss0,
                         std::size_t peak) {
    const auto& node = p_.nodes[i];
    auto& rec = records_[i];
    rec.id = node.id;
    rec.stage = node.stage;
    for (const auto& [k, v] : node.params.values()) rec.params_json[k] = param_to_json(v).dump();
    rec.seconds = seconds;
    rec.cpu_seconds = cpu;
    rec.peak_rss_bytes = peak;
    rec.rss_growth_bytes = peak > rss0 ? peak - rss0 : 0;
    rec.metrics_json = ctx.metrics_json();
    rec.warnings = ctx.warnings();
}

void PipelineRun::release(std::size_t i) {
    for (const auto& [port, src] : p_.nodes[i].inputs)
        if (--consumers_[index_.at(src)] == 0) outputs_[index_.at(src)] = Data{};
    for (std::size_t d : dependents_[i])
        if (--pending_[d] == 0) ready(d);
}

RunResult PipelineRun::commit() {
    RunResult result;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    result.cpu_seconds = process::cpu_seconds();
    result.peak_rss_bytes = process::peak_rss();
    result.labels = opt_.labels;
    for (std::size_t i : p_.order) result.nodes.push_back(records_[i]);
    if (!opt_.report.empty()) {
        // The report lists the outputs it is committed with, and goes in with them.
        result.outputs = files_.finals();
        const fs::path tmp = files_.stage(opt_.report);
        std::ofstream out(tmp, std::ios::binary);
        out << result.to_json(p_);
        if (!out.flush()) {
            files_.discard();
            throw Error("cannot write the run report \"" + opt_.report.string() + "\"");
        }
    }
    result.outputs = files_.commit();
    if (!opt_.report.empty()) result.outputs.pop_back(); // the report itself is not an output
    return result;
}

} // namespace

namespace {

/// One run of a pipeline, in three steps: validate, configure, run. A pipeline not validated
/// yet lets its nodes without inputs (the views, as a rule) start as soon as each is checked
/// on its own: they run while the rest is validated, which loads the later stages' plugins
/// (OpenVDB's take about 60 ms to load), and the later nodes wait until all of it passed. When
/// it fails, the started nodes are stopped, their staged files deleted, and the validation's
/// error is the run's, as if nothing had run.
class Execution {
public:
    Execution(Pipeline& p, const Registry& registry, const RunOptions& opt) : p_(p), registry_(registry), opt_(opt) {}
    ~Execution() {
        if (run_ && !opened_) run_->abandon();
    }

    /// Step 1: the stages, parameters and graph checked against the registry (and the nodes
    /// without inputs started meanwhile). Throws cm::Error naming the file, line, node and stage.
    void validate() {
        if (p_.validated) return;
        start_roots();
        p_.validate(registry_);
    }

    /// Step 2: every node's stage made and given its parameters (its own checks run here),
    /// so a bad combination fails before the later nodes run.
    void configure() {
        std::vector<std::unique_ptr<Stage>> stages = configure_stages(p_, registry_);
        opened_ = true;
        if (!run_) {
            run_ = std::make_unique<PipelineRun>(p_, std::move(stages), opt_);
            return;
        }
        // The rest of the run's copy, from the validated pipeline (nodes it does not read yet).
        for (std::size_t i = 0; i < p_.nodes.size(); ++i)
            if (!copy_.nodes[i].inputs.empty()) {
                copy_.nodes[i].info = p_.nodes[i].info;
                copy_.nodes[i].params = p_.nodes[i].params;
            }
        copy_.order = p_.order;
        run_->open(std::move(stages));
    }

    /// Step 3: every node in dependency order, independent branches at once; the staged files
    /// committed when all succeeded, else discarded and the first failure thrown.
    RunResult run() { return run_->run(); }

private:
    /// The nodes without inputs (a writer waits for the checks) checked and configured each on
    /// its own, and started on a run of their own copy of the pipeline (validate() writes into
    /// `p_` meanwhile). A node that fails its own checks waits: validate() reports it in order.
    void start_roots() {
        copy_ = p_;
        std::vector<std::unique_ptr<Stage>> stages(p_.nodes.size());
        std::vector<std::size_t> early;
        for (std::size_t i = 0; i < copy_.nodes.size(); ++i) {
            if (!copy_.nodes[i].inputs.empty()) continue;
            try {
                copy_.resolve_node(i, registry_);
                if (copy_.nodes[i].info.output == DataKind::File) continue;
                auto stage = registry_.create(copy_.nodes[i].stage);
                stage->configure(copy_.nodes[i].params);
                stages[i] = std::move(stage);
                early.push_back(i);
            } catch (const std::exception&) {}
        }
        if (early.empty()) return;
        run_ = std::make_unique<PipelineRun>(copy_, std::move(stages), opt_, true);
        run_->start(early);
    }

    Pipeline& p_;
    const Registry& registry_;
    const RunOptions& opt_;
    Pipeline copy_; ///< what a run started before validation reads
    std::unique_ptr<PipelineRun> run_;
    bool opened_ = false; ///< every node's stage is given to the run
};

} // namespace

RunResult run_pipeline(Pipeline& p, const Registry& registry, const RunOptions& opt) {
    Execution execution(p, registry, opt);
    execution.validate();
    execution.configure();
    return execution.run();
}

std::string RunResult::to_json(const Pipeline& p) const {
    json j;
    j["pipeline"] = p.name;
    j["file"] = p.file.string();
    j["conceptmesh_version"] = CONCEPTMESH_VERSION_STRING;
    j["seconds"] = seconds;
    j["cpu_seconds"] = cpu_seconds;
    j["peak_rss_bytes"] = peak_rss_bytes;
    j["outputs"] = json::array();
    for (const auto& o : outputs) j["outputs"].push_back(o.string());
    if (!labels.empty()) j["labels"] = labels;
    j["nodes"] = json::array();
    for (const auto& r : nodes) {
        json jn;
        jn["id"] = r.id;
        jn["stage"] = r.stage;
        jn["params"] = json::object();
        for (const auto& [k, v] : r.params_json) jn["params"][k] = json::parse(v);
        jn["seconds"] = r.seconds;
        jn["cpu_seconds"] = r.cpu_seconds;
        jn["peak_rss_bytes"] = r.peak_rss_bytes;
        jn["rss_growth_bytes"] = r.rss_growth_bytes;
        jn["metrics"] = json::object();
        for (const auto& [k, v] : r.metrics_json) jn["metrics"][k] = json::parse(v);
        jn["warnings"] = r.warnings;
        j["nodes"].push_back(jn);
    }
    return j.dump(2) + "\n";
}

} // namespace cm
