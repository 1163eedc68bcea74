// The engines that run the assets' task scripts: processes on this machine, or one Slurm
// array job.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "batch/batch.h"

namespace cm::batch {

/// Runs each plan's task script in its own process, `jobs` at a time; prints one overall
/// progress bar on a terminal and a line per finished asset (unless quiet). Returns the peak
/// memory (MiB) of each process by asset name. A stop (Ctrl-C, SIGTERM) stops the running
/// tasks and throws cm::Cancelled once they have ended.
std::map<std::string, double> run_local(const std::vector<const AssetPlan*>& plans, int jobs, bool quiet);

struct SlurmOptions {
    int jobs = 0; ///< the array's % throttle; 0: none
    std::string partition, time_limit, extra;
    double mem_mib = 0; ///< per task; 0: the largest estimate of the plans
};

/// Submits one array job (one task per plan) and returns its job id. Writes the array script
/// and the task list under out_dir/.batch. Throws cm::Error with sbatch's own message.
std::string submit_slurm(const std::vector<const AssetPlan*>& plans, const SlurmOptions& o,
                         const std::filesystem::path& out_dir, const std::string& batch_name);

/// Tasks of `job_id` still queued or running, from squeue; -1 when squeue cannot say.
int slurm_tasks_left(const std::string& job_id);

/// Waits until `job_id` has no task left, printing a progress line (unless quiet).
void wait_slurm(const std::string& job_id, const std::vector<const AssetPlan*>& plans, bool quiet);

/// Runs argv (no shell) and returns its exit status, stdout in `out` and stderr in `err`.
int run_capture(const std::vector<std::string>& argv, std::string& out, std::string& err);

} // namespace cm::batch
