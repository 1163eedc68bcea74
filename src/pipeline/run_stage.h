// One stage run outside a pipeline file: the command-line tools run views.load and the
// eval stages this way, and the tests run any stage by name. The parameters take the
// same path as a node's (checked against the declaration, defaults filled in, the
// stage's own check), and the files it writes are committed only when it succeeds.
#pragma once
#include <atomic>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/stage.h"
#include "pipeline/pipeline.h"
#include "plugins/registry.h"

namespace cm {

struct StageRunOptions {
    ProgressSink* sink = nullptr;
    std::filesystem::path side_output_dir = ".";
    std::string node = "tool"; ///< the node id messages and progress name
    /// false: the files the stage writes stay under their temporary names (StageRun::staged)
    /// for the caller to look at and remove; nothing is committed.
    bool commit = true;
    /// A stop of this run alone (may be null): set from another thread, the stage stops at
    /// its next look (cm::Cancelled), as Ctrl-C stops it.
    const std::atomic<bool>* stop = nullptr;
};

struct StageRun {
    Data output;
    std::map<std::string, std::string> metrics_json; ///< name -> JSON text
    std::vector<std::string> warnings;
    std::vector<std::filesystem::path> outputs; ///< files committed
    /// Every file the stage wrote: temporary name -> final name, in the order written.
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged;
};

/// Parameters for run_stage() from text, as --set gives them: name -> value. `source` names
/// where they came from in messages ("--set", "a keyword argument").
std::map<std::string, RawParam> text_params(const std::map<std::string, std::string>& values,
                                            const std::string& source = "--set");
/// Parameters for run_stage() from a YAML mapping ("{resolution: 64, keep: all}"), typed as
/// in a pipeline file. Throws cm::Error for malformed YAML or a value that is no mapping.
std::map<std::string, RawParam> yaml_params(const std::string& yaml_mapping);

/// Creates `stage` from the registry and configures it with `params`, resolved against its
/// declaration as a node's are. Throws cm::Error with the sentence a pipeline file gets
/// after its "file:line: node ... : " prefix.
std::unique_ptr<Stage> configure_stage(const Registry& registry, const std::string& stage,
                                       const std::map<std::string, RawParam>& params);

/// Configures `stage` (configure_stage()), runs it on `inputs` and commits its files.
/// Throws cm::Error (cm::Cancelled when interrupted) with the stage's own sentence;
/// nothing it wrote is left behind on failure.
StageRun run_stage(const Registry& registry, const std::string& stage, const std::map<std::string, RawParam>& params,
                   const Inputs& inputs, const StageRunOptions& opt = {});

} // namespace cm
