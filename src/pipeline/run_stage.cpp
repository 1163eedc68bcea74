#include "pipeline/run_stage.h"

#include <mutex>

#include "core/error.h"
#include "io/file_commit.h"
#include "pipeline/yaml_values.h"

namespace fs = std::filesystem;

namespace cm {

std::map<std::string, RawParam> text_params(const std::map<std::string, std::string>& values,
                                            const std::string& source) {
    std::map<std::string, RawParam> out;
    for (const auto& [k, v] : values) {
        out[k].text = v;
        out[k].source = source;
    }
    return out;
}

std::map<std::string, RawParam> yaml_params(const std::string& yaml_mapping) {
    YAML::Node doc;
    try {
        doc = YAML::Load(yaml_mapping);
    } catch (const YAML::Exception& e) {
        throw Error("malformed YAML parameters: " + e.msg);
    }
    std::map<std::string, RawParam> out;
    if (doc.IsNull()) return out;
    if (!doc.IsMap()) throw Error("parameters must be a YAML mapping (name: value)");
    for (auto it = doc.begin(); it != doc.end(); ++it) {
        out[it->first.Scalar()] = raw_param(it->second);
    }
    return out;
}

std::unique_ptr<Stage> configure_stage(const Registry& registry, const std::string& stage,
                                       const std::map<std::string, RawParam>& params) {
    std::unique_ptr<Stage> s = registry.create(stage);
    s->configure(resolve_params(s->info(), params, [](int) { return std::string(); }));
    return s;
}

StageRun run_stage(const Registry& registry, const std::string& stage, const std::map<std::string, RawParam>& params,
                   const Inputs& inputs, const StageRunOptions& opt) {
    std::unique_ptr<Stage> s = configure_stage(registry, stage, params);
    const DataKind output = s->info().output;

    StageRun run;
    FileCommit files;
    std::mutex staged_mutex;
    Context::Hooks hooks;
    hooks.sink = opt.sink;
    hooks.side_output_dir = opt.side_output_dir;
    hooks.stop = opt.stop;
    hooks.stage_file = [&](const fs::path& tmp, const fs::path& fin) {
        std::lock_guard<std::mutex> lock(staged_mutex);
        run.staged.emplace_back(tmp, fin);
        if (opt.commit) files.add(tmp, fin);
    };
    Context ctx(opt.node, stage, hooks);
    run.output = s->run(inputs, ctx);
    if (kind_of(run.output) != output)
        throw Error("stage \"" + stage + "\" returned " + to_string(kind_of(run.output)) + " instead of " +
                    to_string(output));
    run.metrics_json = ctx.metrics_json();
    run.warnings = ctx.warnings();
    // A stop asked for while the stage ran its last part, which does not look, still means no output.
    if (opt.stop && opt.stop->load()) throw Cancelled("stage \"" + stage + "\": stopped when the stage had finished");
    if (opt.commit) run.outputs = files.commit();
    return run;
}

} // namespace cm
