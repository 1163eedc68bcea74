// Runs a validated pipeline: nodes in dependency order on a TBB task group,
// independent branches at once; records time and memory per node; stages
// output files under temporary names and renames them only when all succeeded.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <tbb/task_group.h>
#include <unistd.h>

#include "io/file_commit.h"
#include "pipeline/pipeline.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm {

namespace {

std::size_t current_rss() {
    std::ifstream in("/proc/self/statm");
    std::size_t pages = 0, resident = 0;
    in >> pages >> resident;
    return resident * std::size_t(::sysconf(_SC_PAGESIZE));
}

std::size_t peak_rss() {
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
        { std::lock_guard<std::mutex> lock(mutex_); stop_ = true; }
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

} // namespace

RunResult run_pipeline(Pipeline& p, const Registry& registry, const RunOptions& opt) {
    const std::size_t n = p.nodes.size();
    if (p.order.size() != n) p.validate(registry);

    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < n; ++i) index[p.nodes[i].id] = i;

    // Instantiate and configure every stage before anything runs, so a bad
    // combination of parameters fails fast.
    std::vector<std::unique_ptr<Stage>> stages(n);
    for (std::size_t i : p.order) {
        auto& node = p.nodes[i];
        try {
            stages[i] = registry.create(node.stage);
            stages[i]->configure(node.params);
        } catch (const std::exception& e) {
            throw Error(p.where(node) + e.what());
        }
    }

    std::vector<std::vector<std::size_t>> dependents(n);
    std::vector<std::atomic<int>> pending(n);
    std::vector<std::atomic<int>> consumers(n);
    for (std::size_t i = 0; i < n; ++i) {
        pending[i] = int(p.nodes[i].inputs.size());
        consumers[i] = 0;
    }
    for (std::size_t i = 0; i < n; ++i)
        for (const auto& [port, src] : p.nodes[i].inputs) {
            dependents[index[src]].push_back(i);
            ++consumers[index[src]];
        }

    std::vector<Data> outputs(n);
    std::vector<NodeRecord> records(n);
    std::mutex error_mutex;
    FileCommit files;
    std::atomic<bool> failed{false};
    std::string first_error;
    bool cancelled = false;
    MemoryMonitor memory(n);
    tbb::task_group group;
    const auto run_start = std::chrono::steady_clock::now();

    std::function<void(std::size_t)> launch;
    auto execute = [&](std::size_t i) {
        if (failed) return;
        auto& node = p.nodes[i];
        Context::Hooks hooks;
        hooks.sink = opt.sink;
        hooks.side_output_dir = opt.side_output_dir;
        hooks.stage_file = [&files](const fs::path& tmp, const fs::path& fin) { files.add(tmp, fin); };
        Context ctx(node.id, node.stage, hooks);
        Inputs in;
        for (const auto& [port, src] : node.inputs) in.set(port, outputs[index[src]]);
        if (opt.sink) opt.sink->started(node.id, node.stage);
        const std::size_t rss0 = memory.begin(i);
        const auto t0 = std::chrono::steady_clock::now();
        try {
            Data d = stages[i]->run(in, ctx);
            if (kind_of(d) != node.info.output)
                throw Error(std::string("the stage returned ") + to_string(kind_of(d)) + " instead of " +
                            to_string(node.info.output));
            outputs[i] = std::move(d);
        } catch (const std::exception& e) {
            memory.end(i);
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!failed.exchange(true)) {
                cancelled = dynamic_cast<const Cancelled*>(&e) != nullptr;
                first_error = p.where(node) + e.what();
            }
            return;
        }
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const std::size_t peak = memory.end(i);
        auto& rec = records[i];
        rec.id = node.id;
        rec.stage = node.stage;
        for (const auto& [k, v] : node.params.values()) rec.params_json[k] = param_to_json(v).dump();
        rec.seconds = secs;
        rec.peak_rss_bytes = peak;
        rec.rss_growth_bytes = peak > rss0 ? peak - rss0 : 0;
        rec.metrics_json = ctx.metrics_json();
        rec.warnings = ctx.warnings();
        if (opt.sink) opt.sink->finished(node.id, secs);
        // Free inputs nobody else needs (grids can be large).
        in = Inputs();
        for (const auto& [port, src] : node.inputs)
            if (--consumers[index[src]] == 0) outputs[index[src]] = Data{};
        for (std::size_t d : dependents[i])
            if (--pending[d] == 0) launch(d);
    };
    launch = [&](std::size_t i) { group.run([&, i] { execute(i); }); };
    // Roots are decided before any task runs: a finished root decrements its
    // dependents' counters, which must not make them look like roots here too.
    std::vector<std::size_t> roots;
    for (std::size_t i = 0; i < n; ++i)
        if (p.nodes[i].inputs.empty()) roots.push_back(i);
    for (std::size_t i : roots) launch(i);
    group.wait();

    if (failed) {
        files.discard();
        if (cancelled) throw Cancelled();
        throw Error(first_error);
    }
    RunResult result;
    result.outputs = files.commit();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
    result.peak_rss_bytes = peak_rss();
    for (std::size_t i : p.order) result.nodes.push_back(records[i]);
    return result;
}

std::string RunResult::to_json(const Pipeline& p) const {
    json j;
    j["pipeline"] = p.name;
    j["file"] = p.file.string();
    j["conceptmesh_version"] = CONCEPTMESH_VERSION_STRING;
    j["seconds"] = seconds;
    j["peak_rss_bytes"] = peak_rss_bytes;
    j["outputs"] = json::array();
    for (const auto& o : outputs) j["outputs"].push_back(o.string());
    j["nodes"] = json::array();
    for (const auto& r : nodes) {
        json jn;
        jn["id"] = r.id;
        jn["stage"] = r.stage;
        jn["params"] = json::object();
        for (const auto& [k, v] : r.params_json) jn["params"][k] = json::parse(v);
        jn["seconds"] = r.seconds;
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
