// A pipeline file: parsed from YAML and checked against the structure schema (parse.cpp),
// validated against the registry: parameters, ports, kinds, order (validate.cpp), then run:
// validate, configure, run, each a step of the executor (executor.cpp), the nodes in
// dependency order with TBB. schema.cpp writes the schemas.
#pragma once
#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/params.h"
#include "core/stage.h"
#include "plugins/registry.h"

namespace cm {

/// One parameter value as the user gave it, before it meets its declaration: as written in
/// YAML (its kind: plain or quoted scalar, list, mapping, null; the scalar's text; its
/// source line), or the text of a --set override (no kind, line 0).
struct RawParam {
    /// How the YAML value was written: "scalar" (plain), "quoted", "list", "mapping" or
    /// "null value" (parse_param_yaml's kinds); empty for --set.
    std::string kind;
    std::string text; ///< --set: the value; YAML: the scalar as written, for messages
    int line = 0;     ///< 1-based line in the pipeline file; 0 for --set
    /// Where a --set-like value came from, for messages: "--set" on the command line, a
    /// keyword argument or `set=` in the Python module ("set= in Python").
    std::string source = "--set";
    bool from_set() const { return kind.empty(); }
    bool is_null() const { return kind == "null value"; }
};

/// Converts a raw value to the declared type: a YAML value by its own kind (a quoted
/// scalar is never a number, a list is never a scalar), --set text by parse_param_text().
/// Throws cm::Error "<name> must be ..., got ...".
ParamValue param_value(const ParamSpec& spec, const RawParam& raw);

/// Checks every raw value against the declaration (unknown names, types, ranges,
/// choices), fills in the defaults and reports missing required ones. Messages start
/// with `where(line)` (line 0: the node's own line) and name --set values as such.
ParamSet resolve_params(const StageInfo& info, const std::map<std::string, RawParam>& raw,
                        const std::function<std::string(int line)>& where);

struct PipelineNode {
    std::string id;
    std::string stage;
    int line = 0;                              ///< 1-based line of the node in the file
    std::map<std::string, std::string> inputs; ///< port -> node id
    std::map<std::string, int> input_lines;
    std::map<std::string, RawParam> raw_params; ///< as given, by parameter name
    ParamSet params;                            ///< filled by validate()
    StageInfo info;                             ///< filled by validate()
};

struct Pipeline {
    std::filesystem::path file;
    std::string name, description;
    std::vector<PipelineNode> nodes;
    std::vector<std::size_t> order; ///< topological order, filled by validate()
    /// Set by validate() once every check passed; apply_override() clears it.
    bool validated = false;

    /// Reads and checks the YAML structure against the pipeline schema.
    static Pipeline load(const std::filesystem::path& file);
    static Pipeline parse(const std::string& text, const std::filesystem::path& file_for_messages);

    /// Applies "NODE.PARAM=VALUE"; an unknown node is an error (unknown parameters
    /// are caught by validate()).
    /// `source` names where the assignment came from in messages ("--set" on the command line).
    void apply_override(const std::string& assignment, const std::string& source = "--set");
    /// Checks every node's stage and parameters, then the graph (unknown node,
    /// port kind mismatch, missing input, cycle). Throws cm::Error naming the
    /// file, line, node and stage.
    void validate(const Registry& registry);
    /// The first step of validate() for one node: its stage (loading its plugin), its
    /// parameters, and its connections to known nodes and ports.
    void resolve_node(std::size_t i, const Registry& registry);

    /// "file:line: node "id" (stage): " — the prefix of every message about a node.
    std::string where(const PipelineNode& n, int line = 0) const;
    /// Node id -> position in `nodes`.
    std::map<std::string, std::size_t> node_index() const;
};

struct NodeRecord {
    std::string id, stage;
    std::map<std::string, std::string> params_json; ///< name -> JSON text
    double seconds = 0;
    /// CPU seconds (user + system, all threads) of the process while the node ran; nodes
    /// running at the same time (independent branches) are counted in each other's.
    double cpu_seconds = 0;
    std::size_t peak_rss_bytes = 0;   ///< process peak RSS while the node ran
    std::size_t rss_growth_bytes = 0; ///< that peak minus RSS when it started
    std::map<std::string, std::string> metrics_json;
    std::vector<std::string> warnings;
};

struct RunOptions {
    ProgressSink* sink = nullptr;
    std::filesystem::path side_output_dir = ".";
    /// When set, the run report (RunResult::to_json) is written here, committed with the
    /// run's other outputs: all of them appear, or none.
    std::filesystem::path report;
    /// Written into the run report as "labels" (a caller's own keys: an asset name, a hash
    /// of the inputs), so the report says which job it belongs to.
    std::map<std::string, std::string> labels;
    /// A stop of this run alone (may be null): a host that runs the pipeline on a thread of
    /// its own sets it to cancel the run as Ctrl-C cancels the command (cm::Cancelled, no
    /// output file left). The process-wide cancel_requested() stops it too.
    std::atomic<bool>* stop = nullptr;
    /// Called with each node's output once the node has run (on the thread that ran it), for
    /// a host that hands the outputs back (the Python module); the run frees its own
    /// reference once the node's last consumer has run, as without it.
    std::function<void(const std::string& node, const Data& output)> on_output;
};

struct RunResult {
    std::vector<NodeRecord> nodes; ///< in topological order
    double seconds = 0;
    double cpu_seconds = 0; ///< of the whole process up to the end of the run, start-up included
    std::size_t peak_rss_bytes = 0;
    std::vector<std::filesystem::path> outputs; ///< files committed
    std::map<std::string, std::string> labels;  ///< RunOptions::labels
    std::string to_json(const Pipeline& p) const;
};

/// Creates and configures every node's stage of a validated pipeline (each stage's own
/// checks run here), so a bad combination of parameters fails before anything runs.
/// Throws cm::Error prefixed with the node.
std::vector<std::unique_ptr<Stage>> configure_stages(const Pipeline& p, const Registry& registry);

/// Runs a pipeline in three steps: validate (unless `p` is validated: it is left validated),
/// configure every stage, run the nodes. On failure throws cm::Error (prefixed with the file,
/// line, node and stage) and leaves no output file behind; on success renames every staged file.
RunResult run_pipeline(Pipeline& p, const Registry& registry, const RunOptions& opt);

/// JSON Schemas generated from the declared parameters.
std::string stage_schema_json(const StageInfo& info);
/// The pipeline file's structure (nodes, ids, inputs, params as an object), which parse()
/// checks a file against; `stage_names` become the examples of `stage`.
nlohmann::json pipeline_structure_schema(const std::vector<std::string>& stage_names);
std::string pipeline_schema_json(const Registry& registry);

} // namespace cm
