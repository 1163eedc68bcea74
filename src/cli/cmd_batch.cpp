// conceptmesh batch: runs every asset of an ASSETS.yaml, each as `conceptmesh run` in its own
// process (here, or as the tasks of one Slurm array job), then writes the summary and the
// review page.
#include <algorithm>
#include <fstream>
#include <iostream>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/batch.h"
#include "cli/batch_engines.h"
#include "cli/commands.h"
#include "cli/tool_common.h"
#include "core/error.h"
#include "io/file_commit.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::cli {

namespace {

using namespace batch;

struct BatchOptions {
    std::string assets, pipeline, engine = "local", out = "batch-out", scan, status;
    int jobs = 0;
    bool resume = false, dry_run = false, detach = false;
    SlurmOptions slurm;
};

// Jobs that fit: no more than the cores, and no more than the memory holds of the largest estimate.
int default_jobs(const std::vector<const AssetPlan*>& plans) {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    double avail_mib = 0, largest = 1;
    std::ifstream mi("/proc/meminfo");
    for (std::string k; mi >> k;) {
        double v = 0;
        mi >> v;
        if (k == "MemAvailable:") avail_mib = v / 1024.0;
        mi.ignore(1 << 10, '\n');
    }
    for (const auto* p : plans) largest = std::max(largest, p->memory_mib);
    int by_memory = avail_mib > 0 ? int(0.9 * avail_mib / largest) : cores;
    return std::max(1, std::min({cores, by_memory, int(std::max<std::size_t>(1, plans.size()))}));
}

// Checks every asset as `conceptmesh validate` does; returns asset name -> one-line cause.
std::map<std::string, std::string> validate_assets(const AssetsFile& f, const std::vector<AssetPlan>& plans,
                                                   const GlobalOptions& g) {
    std::map<std::string, std::string> bad;
    for (const auto& p : plans) {
        try {
            load_checked(p.spec->pipeline.string(), p.sets, g);
        } catch (const std::exception& e) {
            bad[p.spec->name] = f.where(*p.spec) + e.what();
        }
    }
    return bad;
}

std::vector<AssetResult> gather(const std::vector<AssetPlan>& plans, const std::set<std::string>& skipped,
                                const std::map<std::string, std::string>& invalid,
                                const std::map<std::string, double>& peaks) {
    std::vector<AssetResult> results;
    for (const auto& p : plans) {
        if (auto it = invalid.find(p.spec->name); it != invalid.end()) {
            AssetResult r;
            r.name = p.spec->name;
            r.dir = p.dir;
            r.status = "failed";
            r.cause = it->second;
            results.push_back(r);
            continue;
        }
        AssetResult r = read_result(p, skipped.count(p.spec->name) > 0);
        if (auto it = peaks.find(r.name); it != peaks.end() && r.peak_mib <= 0) r.peak_mib = it->second;
        results.push_back(r);
    }
    return results;
}

int finish(const AssetsFile& f, const std::vector<AssetPlan>& plans, const std::vector<AssetResult>& results,
           const fs::path& out, const std::string& engine, const GlobalOptions& g) {
    std::cout << write_summary(f, plans, results, out, engine);
    if (!g.quiet)
        std::cerr << "conceptmesh: wrote " << (fs::absolute(out) / "batch-report.json").string() << " and "
                  << (fs::absolute(out) / "index.html").string() << "\n";
    return std::any_of(results.begin(), results.end(), [](const AssetResult& r) { return r.status == "failed"; }) ? 1
                                                                                                                  : 0;
}

int run_status(const BatchOptions& o, const GlobalOptions& g) {
    const fs::path job_file = fs::path(o.status) / ".batch" / "job.json";
    if (!fs::is_regular_file(job_file))
        throw Error("--status \"" + o.status + "\": no batch was submitted there (" + job_file.string() +
                    " is missing)");
    json j;
    try {
        std::ifstream in(job_file);
        j = json::parse(in);
    } catch (const std::exception& e) {
        throw Error(job_file.string() + ": " + e.what());
    }
    const AssetsFile f = read_assets(j.at("assets_file").get<std::string>(), j.value("pipeline", ""));
    const fs::path out = j.at("out_dir").get<std::string>();
    const std::vector<AssetPlan> plans = plan_assets(f, out);
    const std::set<std::string> skipped = j.at("skipped").get<std::set<std::string>>();
    const auto invalid = j.at("invalid").get<std::map<std::string, std::string>>();
    const std::string job = j.at("job_id").get<std::string>();
    const int left = slurm_tasks_left(job);
    if (left != 0) {
        std::size_t done = 0, total = 0;
        for (const auto& p : plans) {
            if (skipped.count(p.spec->name) || invalid.count(p.spec->name)) continue;
            ++total;
            done += fs::exists(p.dir / "exit-status");
        }
        std::cout << "slurm job " << job << ": " << done << "/" << total << " assets done, "
                  << (left < 0 ? std::string("squeue cannot say how many are left")
                               : std::to_string(left) + " queued or running")
                  << "\n";
        return 75; // EX_TEMPFAIL: ask again later
    }
    return finish(f, plans, gather(plans, skipped, invalid, {}), out, "slurm", g);
}

int run_batch(const BatchOptions& o, const GlobalOptions& g) {
    if (!o.status.empty()) return run_status(o, g);
    if (!o.scan.empty()) {
        if (o.pipeline.empty()) throw Error("--scan needs --pipeline: the pipeline every asset runs");
        if (!fs::is_regular_file(o.pipeline)) throw Error("--pipeline \"" + o.pipeline + "\" does not exist");
        const fs::path out = o.assets.empty() ? fs::path(o.scan) / "assets.yaml" : fs::path(o.assets);
        const std::size_t n = scan_folder(o.scan, out, o.pipeline);
        std::cout << "wrote " << out.string() << " (" << n << " assets)\n";
        return 0;
    }
    if (o.assets.empty()) throw UsageError("name the ASSETS.yaml to run (or --scan FOLDER, --status DIR)");
    if (o.engine != "local" && o.engine != "slurm")
        throw Error("--engine must be local or slurm, got \"" + o.engine + "\"");
    // A batch checks every asset's pipeline, which needs the plugins anyway: they are all
    // loaded first, before the batch's own work starts threads. (Loaded later, on first use,
    // the sanitized build's leak check misreads their thread-local storage at exit: clang
    // 14's LeakSanitizer with this glibc.)
    Registry::global().names();
    print_plugin_diagnostics(g);
    const AssetsFile f = read_assets(o.assets, o.pipeline);
    const fs::path out = fs::absolute(o.out).lexically_normal();
    if (fs::exists(out) && !fs::is_directory(out)) throw Error("-o \"" + o.out + "\" is a file; name a folder");
    const std::vector<AssetPlan> plans = plan_assets(f, out);
    const auto invalid = validate_assets(f, plans, g);
    if (o.dry_run) {
        for (const auto& p : plans) {
            auto it = invalid.find(p.spec->name);
            if (it == invalid.end())
                std::cout << p.spec->name << ": valid (" << p.spec->pipeline.filename().string() << ", about "
                          << long(p.memory_mib) << " MiB)\n";
            else print_error(it->second);
        }
        return invalid.empty() ? 0 : 1;
    }
    std::vector<const AssetPlan*> todo;
    std::set<std::string> skipped;
    for (const auto& p : plans) {
        if (invalid.count(p.spec->name)) continue;
        if (o.resume && up_to_date(p)) {
            skipped.insert(p.spec->name);
            continue;
        }
        write_task_script(p);
        todo.push_back(&p);
    }
    if (!g.quiet)
        std::cerr << "conceptmesh: batch " << f.name << ": " << todo.size() << " to run, " << skipped.size()
                  << " up to date, " << invalid.size() << " invalid\n";
    std::map<std::string, double> peaks;
    if (!todo.empty() && o.engine == "local") {
        peaks = run_local(todo, o.jobs > 0 ? o.jobs : default_jobs(todo), g.quiet);
    } else if (!todo.empty()) {
        const std::string job = submit_slurm(todo, o.slurm, out, f.name);
        json j;
        j["engine"] = "slurm";
        j["job_id"] = job;
        j["assets_file"] = fs::absolute(f.file).string();
        j["pipeline"] = o.pipeline.empty() ? "" : fs::absolute(o.pipeline).string();
        j["out_dir"] = out.string();
        j["skipped"] = skipped;
        j["invalid"] = invalid;
        write_file_atomic(out / ".batch" / "job.json", j.dump(2) + "\n");
        if (!g.quiet) std::cerr << "conceptmesh: submitted slurm job " << job << " (" << todo.size() << " tasks)\n";
        if (o.detach) {
            std::cout << "submitted slurm job " << job << "; follow it with: conceptmesh batch --status "
                      << out.string() << "\n";
            return 0;
        }
        wait_slurm(job, todo, g.quiet);
    }
    return finish(f, plans, gather(plans, skipped, invalid, peaks), out, o.engine, g);
}

} // namespace

void add_batch_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd =
        app.add_subcommand("batch", "Run many assets (ASSETS.yaml) here or on a Slurm cluster, with a review page");
    auto o = std::make_shared<BatchOptions>();
    cmd->add_option("assets", o->assets, "ASSETS.yaml: defaults, then the assets (name, views or sheet, set)");
    cmd->add_option("--pipeline", o->pipeline, "Pipeline for every asset (instead of the file's)");
    cmd->add_option("--engine", o->engine, "local (processes here) or slurm (one array job)")
        ->check(CLI::IsMember({"local", "slurm"}));
    cmd->add_option("--jobs", o->jobs, "Assets at once (local: default from cores and memory; slurm: the % throttle)")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--resume", o->resume, "Skip assets whose outputs exist and whose inputs are unchanged");
    cmd->add_option("-o,--output", o->out, "Output folder (one folder per asset, the summary and index.html)");
    cmd->add_flag("--dry-run", o->dry_run, "Check every asset's pipeline as validate does, run nothing");
    cmd->add_option("--scan", o->scan, "Write an ASSETS.yaml for each subfolder of FOLDER holding a views.yaml");
    cmd->add_option("--status", o->status, "How the Slurm batch in DIR is doing; gathers it once finished");
    cmd->add_flag("--detach", o->detach, "slurm: submit and return (then --status DIR)");
    cmd->add_option("--partition", o->slurm.partition, "slurm: partition");
    cmd->add_option("--time", o->slurm.time_limit, "slurm: time limit per task (sbatch --time, e.g. 30:00)");
    cmd->add_option("--mem-per-task", o->slurm.mem_mib, "slurm: MiB per task (default: the largest estimate)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--sbatch-args", o->slurm.extra, "slurm: more sbatch arguments, as one string");
    cmd->add_flag("-q,--quiet", g.quiet, "Only errors, warnings and the summary");
    set_action(cmd, action, [&g, o] {
        o->slurm.jobs = o->engine == "slurm" ? o->jobs : 0;
        return run_batch(*o, g);
    });
}

} // namespace cm::cli
