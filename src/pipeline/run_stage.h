// One stage run outside a pipeline file: the command-line tools run views.load and the
// eval stages this way, and the tests run any stage by name. The parameters take the
// same path as a node's (checked against the declaration, defaults filled in, the
// stage's own check), and the files it writes are committed only when it succeeds.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/stage.h"
#include "pipeline/pipeline.h"
#include "plugins/registry.h"

namespace cm {

struct StageRunOptions {
    ProgressSink* sink = nullptr;
    std::filesystem::path side_output_dir = ".";
    std::string node = "tool";   ///< the node id messages and progress name
};

struct StageRun {
    Data output;
    std::map<std::string, std::string> metrics_json;   ///< name -> JSON text
    std::vector<std::string> warnings;
    std::vector<std::filesystem::path> outputs;        ///< files committed
};

/// Parameters for run_stage() from text, as --set gives them: name -> value.
std::map<std::string, RawParam> text_params(const std::map<std::string, std::string>& values);
/// Parameters for run_stage() from a YAML mapping ("{resolution: 64, keep: all}"), typed as
/// in a pipeline file. Throws cm::Error for malformed YAML or a value that is no mapping.
std::map<std::string, RawParam> yaml_params(const std::string& yaml_mapping);

/// Creates `stage` from the registry, resolves `params`, runs it on `inputs` and commits
/// its files. Throws cm::Error (cm::Cancelled when interrupted) with the stage's own
/// sentence; nothing it wrote is left behind on failure.
StageRun run_stage(const Registry& registry, const std::string& stage, const std::map<std::string, RawParam>& params,
                   const Inputs& inputs, const StageRunOptions& opt = {});

} // namespace cm
