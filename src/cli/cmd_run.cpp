// conceptmesh run: runs a pipeline, printing progress, optionally writing a run report.
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/progress_json.h"
#include "cli/progress_printer.h"
#include "cli/tool_common.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace cm::cli {

namespace {

struct RunCommandOptions {
    std::string pipeline, report, progress = "text";
    std::vector<std::string> sets, labels;
};

void check_labels(const RunCommandOptions& o, RunOptions& opt) {
    for (const auto& l : o.labels) {
        const auto eq = l.find('=');
        if (eq == 0 || eq == std::string::npos) throw Error("--label \"" + l + "\": expected KEY=VALUE");
        opt.labels[l.substr(0, eq)] = l.substr(eq + 1);
    }
    if (!o.labels.empty() && o.report.empty())
        throw Error("--label needs --report: labels are written into the run report");
}

int run_run(const RunCommandOptions& o, const GlobalOptions& g, std::unique_ptr<JsonProgress>& json) {
    print_plugin_diagnostics(g);
    // Validated by run_pipeline, which starts the views while it validates the rest.
    Pipeline p = Pipeline::load(o.pipeline);
    for (const auto& s : o.sets) p.apply_override(s);
    if (json) {
        std::vector<std::pair<std::string, std::string>> nodes;
        for (const auto& n : p.nodes) nodes.emplace_back(n.id, n.stage);
        json = std::make_unique<JsonProgress>(o.pipeline, std::move(nodes));
        json->begin();
    }
    if (!o.report.empty()) {
        const fs::path dir = fs::absolute(o.report).parent_path();
        if (!fs::is_directory(dir))
            throw Error("--report \"" + o.report + "\": the folder \"" + dir.string() + "\" does not exist");
        if (fs::is_directory(o.report))
            throw Error("--report \"" + o.report + "\" is a folder; name the JSON file to write");
    }
    // The bars and lines on stderr, or the JSON stream on stdout: not both.
    ProgressPrinter printer(g.quiet || json, g.verbose);
    RunOptions opt;
    opt.sink = json ? static_cast<ProgressSink*>(json.get()) : &printer;
    opt.side_output_dir = o.report.empty() ? fs::path(".") : fs::absolute(o.report).parent_path();
    opt.report = o.report;
    check_labels(o, opt);
    const RunResult r = with_plugin_warnings(g, [&] { return run_pipeline(p, Registry::global(), opt); });
    if (json) {
        json->done(r.outputs, r.seconds, r.peak_rss_bytes);
    } else if (!g.quiet) {
        for (const auto& out : r.outputs) std::cerr << "conceptmesh: wrote " << out.string() << "\n";
        std::cerr << "conceptmesh: finished in " << std::fixed << std::setprecision(2) << r.seconds
                  << " s, peak memory " << (r.peak_rss_bytes >> 20) << " MiB\n";
    }
    return 0;
}

} // namespace

void add_run_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd = app.add_subcommand("run", "Run a pipeline");
    auto o = std::make_shared<RunCommandOptions>();
    cmd->add_option("pipeline", o->pipeline, "Pipeline YAML file")->required();
    cmd->add_option("--set", o->sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
    cmd->add_option("--report", o->report, "Write a JSON run report (per node: params, time, memory, counts)");
    cmd->add_option("--label", o->labels, "Add KEY=VALUE to the run report's \"labels\" (repeatable)");
    cmd->add_flag("-q,--quiet", g.quiet, "Only errors and warnings");
    cmd->add_flag("-v,--verbose", g.verbose, "More detail while running");
    cmd->add_option("--progress", o->progress,
                    "text: bars on a terminal, lines otherwise (stderr); json: one JSON object per line on stdout "
                    "(docs/pipelines.md)")
        ->check(CLI::IsMember({"text", "json"}))
        ->capture_default_str();
    set_action(cmd, action, [&g, o] {
        if (o->progress != "json") {
            std::unique_ptr<JsonProgress> none;
            return run_run(*o, g, none);
        }
        // The stream ends with an "end" line whatever happens, a failure before the pipeline
        // is read included; the error also goes to stderr as usual, and the exit status is
        // the same as without the stream.
        auto json = std::make_unique<JsonProgress>(o->pipeline, std::vector<std::pair<std::string, std::string>>{});
        try {
            return run_run(*o, g, json);
        } catch (const std::exception& e) {
            json->failed(e);
            throw;
        }
    });
}

} // namespace cm::cli
