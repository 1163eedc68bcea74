// A whole batch, step by step: read ASSETS.yaml, plan every asset, check each asset's
// pipeline, run what is not up to date (here or as one Slurm array job), then gather the
// results into the summary and the review page. `conceptmesh batch` reads its options and
// calls run(); a program embedding conceptmesh can do the same.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "batch/engines.h"

namespace cm::batch {

struct Options {
    std::string assets;           ///< ASSETS.yaml; with `scan`, the file to write (default FOLDER/assets.yaml)
    std::string pipeline;         ///< every asset's pipeline instead of the file's (--pipeline)
    std::string engine = "local"; ///< local | slurm
    std::string out = "batch-out";
    std::string scan;   ///< write an ASSETS.yaml for this folder's subfolders instead of running
    std::string status; ///< how the Slurm batch in this folder is doing; gathers it once finished
    int jobs = 0;       ///< assets at once (local; 0: from cores and memory) or the array's throttle (slurm)
    bool resume = false, dry_run = false, detach = false, quiet = false;
    SlurmOptions slurm;
};

/// What the caller does for the batch: tell what the plugins said once they are loaded, check
/// one asset's pipeline (as `conceptmesh validate` does: load, apply the --set list, validate;
/// throws cm::Error) and print one error line.
struct Hooks {
    std::function<void()> plugins_loaded;
    std::function<void(const std::string& pipeline, const std::vector<std::string>& sets)> check_pipeline;
    std::function<void(const std::string& text)> error;
};

/// Runs the batch `o` asks for and returns the exit status: 0 when every asset is ok or up to
/// date, 1 when one failed (or is invalid), 75 from `status` while the Slurm job still runs.
/// Prints the summary table on stdout and progress on stderr (unless quiet). Throws cm::Error
/// for a batch that cannot start (a bad ASSETS.yaml, -o naming a file), cm::UsageError when
/// nothing to run is named, cm::Cancelled when stopped.
int run(const Options& o, const Hooks& hooks);

} // namespace cm::batch
