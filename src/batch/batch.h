// Many assets at once, each one `conceptmesh run` in its own process, on this machine or as
// one Slurm array job. assets.cpp reads ASSETS.yaml, plan.cpp plans each asset's run,
// engines.cpp runs the plan (local processes, sbatch), report.cpp and review_page.cpp gather
// the results into batch-report.json, a table and the review page; run.cpp is the whole
// batch, step by step (the `conceptmesh batch` command only reads its options).
#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cm::batch {

/// One asset of ASSETS.yaml, as written.
struct AssetSpec {
    std::string name;
    int line = 0;                     ///< line of the asset's entry
    std::filesystem::path views;      ///< views manifest (resolved); empty when `sheet` is given
    std::string sheet_yaml;           ///< a `sheet:` entry turned into a one-line manifest; empty: none
    std::filesystem::path pipeline;   ///< resolved; the defaults' when not given
    std::vector<std::string> sets;    ///< NODE.PARAM=VALUE, the defaults' first
    std::optional<double> memory_mib; ///< per-asset memory estimate given by hand
};

/// ASSETS.yaml: the defaults at the top, then the assets.
struct AssetsFile {
    std::filesystem::path file;
    std::string name;              ///< `batch:`, or the file's stem
    std::string output = "{name}"; ///< the folder of each asset under the output folder
    std::vector<AssetSpec> assets;
    /// "file:line: asset "name": " — the prefix of every message about an asset.
    std::string where(const AssetSpec& a) const;
};

/// Reads and checks ASSETS.yaml (structure, unknown keys, names unique and usable as folder
/// names, files that exist); throws cm::Error naming the file, line and asset.
/// `pipeline_override` (--pipeline) replaces the defaults' pipeline.
AssetsFile read_assets(const std::filesystem::path& file, const std::string& pipeline_override);

/// Writes an ASSETS.yaml listing every subfolder of `folder` (sorted by name) that holds a
/// views manifest (views.yaml or views.yml), with `pipeline`; returns how many it found.
/// Throws cm::Error when there is none or `out` cannot be written.
std::size_t scan_folder(const std::filesystem::path& folder, const std::filesystem::path& out,
                        const std::string& pipeline);

/// What one asset's run needs: its folder, the command, and the hash of its inputs.
struct AssetPlan {
    const AssetSpec* spec = nullptr;
    std::filesystem::path dir;      ///< absolute: the asset's folder (its run's working folder)
    std::filesystem::path manifest; ///< absolute: the views manifest the run reads
    std::vector<std::string> sets;  ///< every --set of its run, the batch's own first
    /// Under dir; empty when the pipeline has none of that node (or writes a mesh in another
    /// format than batch_mesh() takes).
    std::string mesh_file, preview_file;
    std::string inputs_hash;       ///< SHA-256 (hex) of images, manifest, pipeline, parameters, version
    double memory_mib = 0;         ///< estimated peak memory of the run
    std::vector<std::string> argv; ///< conceptmesh run ... (argv[0] is this executable)
};

/// True for the mesh formats a batch gives its assets and lists (report, review page): .glb
/// (by default, drawn on the review page) and .usdz (when the pipeline writes one).
bool batch_mesh(const std::filesystem::path& file);

/// Plans every asset under `out_dir`: folders, --set list, hash, memory estimate and command.
/// Throws cm::Error naming the asset when its pipeline cannot be read.
std::vector<AssetPlan> plan_assets(const AssetsFile& f, const std::filesystem::path& out_dir);

/// The bytes of a file; empty when it cannot be read.
std::string read_bytes(const std::filesystem::path& f);

/// SHA-256 of the asset's inputs: every image its manifest reads (bytes), the manifest, the
/// pipeline file, its --set list and the tool's version.
std::string inputs_hash(const AssetPlan& p, const std::filesystem::path& pipeline);

/// true when the asset's run report exists, carries `p.inputs_hash` and every output it lists exists.
bool up_to_date(const AssetPlan& p);

/// Writes the asset's task script (dir/task.sh): it runs the command with its log and records
/// the exit status, start and end time in dir/exit-status. Both engines run this script.
void write_task_script(const AssetPlan& p);

/// The outcome of one asset, read back from its folder.
struct AssetResult {
    std::string name, status; ///< ok | failed | skipped (up to date)
    std::string cause;        ///< failed: one line
    double seconds = 0;
    double peak_mib = 0;
    double faces = -1, xor_pct = -1;                      ///< -1: not known
    std::vector<std::pair<std::string, double>> view_xor; ///< per input view
    std::filesystem::path dir;
};

/// Reads an asset's folder after its task ended (or was skipped): exit-status, run report and log.
AssetResult read_result(const AssetPlan& p, bool skipped);

/// Writes dir/batch-report.json and dir/index.html (the review page, with three.js beside it),
/// and returns the table as text.
std::string write_summary(const AssetsFile& f, const std::vector<AssetPlan>& plans,
                          const std::vector<AssetResult>& results, const std::filesystem::path& out_dir,
                          const std::string& engine);

/// `v` with `digits` digits after the point ("0.93"), for the table and the page.
std::string fixed_digits(double v, int digits);

/// The review page only (write_summary() calls it). Throws cm::Error when three.js is missing.
void write_review_page(const std::vector<AssetPlan>& plans, const std::vector<AssetResult>& results,
                       const std::filesystem::path& out_dir, const std::string& title);

} // namespace cm::batch
