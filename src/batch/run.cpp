#include "batch/run.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "plugins/registry.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::batch {

namespace {

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
                                                   const Hooks& hooks) {
    std::map<std::string, std::string> bad;
    for (const auto& p : plans) {
        try {
            hooks.check_pipeline(p.spec->pipeline.string(), p.sets);
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
           const fs::path& out, const std::string& engine, bool quiet) {
    std::cout << write_summary(f, plans, results, out, engine);
    if (!quiet)
        std::cerr << "conceptmesh: wrote " << (fs::absolute(out) / "batch-report.json").string() << " and "
                  << (fs::absolute(out) / "index.html").string() << "\n";
    return std::any_of(results.begin(), results.end(), [](const AssetResult& r) { return r.status == "failed"; }) ? 1
                                                                                                                  : 0;
}

int run_status(const Options& o, const Hooks& hooks) {
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
    return finish(f, plans, gather(plans, skipped, invalid, {}), out, "slurm", o.quiet);
}

} // namespace

int run(const Options& o, const Hooks& hooks) {
    if (!o.status.empty()) return run_status(o, hooks);
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
    if (hooks.plugins_loaded) hooks.plugins_loaded();
    const AssetsFile f = read_assets(o.assets, o.pipeline);
    const fs::path out = fs::absolute(o.out).lexically_normal();
    if (fs::exists(out) && !fs::is_directory(out)) throw Error("-o \"" + o.out + "\" is a file; name a folder");
    const std::vector<AssetPlan> plans = plan_assets(f, out);
    const auto invalid = validate_assets(f, plans, hooks);
    if (o.dry_run) {
        for (const auto& p : plans) {
            auto it = invalid.find(p.spec->name);
            if (it == invalid.end())
                std::cout << p.spec->name << ": valid (" << p.spec->pipeline.filename().string() << ", about "
                          << long(p.memory_mib) << " MiB)\n";
            else hooks.error(it->second);
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
    if (!o.quiet)
        std::cerr << "conceptmesh: batch " << f.name << ": " << todo.size() << " to run, " << skipped.size()
                  << " up to date, " << invalid.size() << " invalid\n";
    std::map<std::string, double> peaks;
    if (!todo.empty() && o.engine == "local") {
        peaks = run_local(todo, o.jobs > 0 ? o.jobs : default_jobs(todo), o.quiet);
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
        if (!o.quiet) std::cerr << "conceptmesh: submitted slurm job " << job << " (" << todo.size() << " tasks)\n";
        if (o.detach) {
            std::cout << "submitted slurm job " << job << "; follow it with: conceptmesh batch --status "
                      << out.string() << "\n";
            return 0;
        }
        wait_slurm(job, todo, o.quiet);
    }
    return finish(f, plans, gather(plans, skipped, invalid, peaks), out, o.engine, o.quiet);
}

} // namespace cm::batch
