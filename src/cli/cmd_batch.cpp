// conceptmesh batch: the options of a batch (src/batch/run.h runs it).
#include <memory>

#include "batch/run.h"
#include "cli/commands.h"
#include "cli/tool_common.h"

namespace cm::cli {

void add_batch_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd =
        app.add_subcommand("batch", "Run many assets (ASSETS.yaml) here or on a Slurm cluster, with a review page");
    auto o = std::make_shared<batch::Options>();
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
        o->quiet = g.quiet;
        batch::Hooks hooks;
        hooks.plugins_loaded = [&g] { print_plugin_diagnostics(g); };
        hooks.check_pipeline = [&g](const std::string& file, const std::vector<std::string>& sets) {
            load_checked(file, sets, g);
        };
        hooks.error = [](const std::string& text) { print_error(text); };
        return batch::run(*o, hooks);
    });
}

} // namespace cm::cli
