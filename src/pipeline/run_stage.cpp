#include "pipeline/run_stage.h"

#include "core/error.h"
#include "io/file_commit.h"

namespace fs = std::filesystem;

namespace cm {

std::map<std::string, RawParam> text_params(const std::map<std::string, std::string>& values) {
    std::map<std::string, RawParam> out;
    for (const auto& [k, v] : values) out[k].text = v;
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
        RawParam raw;
        raw.node = it->second;
        raw.line = it->second.Mark().line + 1;
        if (raw.node.IsScalar()) raw.text = raw.node.Scalar();
        out[it->first.Scalar()] = raw;
    }
    return out;
}

StageRun run_stage(const Registry& registry, const std::string& stage, const std::map<std::string, RawParam>& params,
                   const Inputs& inputs, const StageRunOptions& opt) {
    std::unique_ptr<Stage> s = registry.create(stage);
    const StageInfo info = s->info();
    s->configure(resolve_params(info, params, [](int) { return std::string(); }));

    FileCommit files;
    Context::Hooks hooks;
    hooks.sink = opt.sink;
    hooks.side_output_dir = opt.side_output_dir;
    hooks.stage_file = [&files](const fs::path& tmp, const fs::path& fin) { files.add(tmp, fin); };
    Context ctx(opt.node, stage, hooks);
    StageRun run;
    run.output = s->run(inputs, ctx);
    if (kind_of(run.output) != info.output)
        throw Error("stage \"" + stage + "\" returned " + to_string(kind_of(run.output)) + " instead of " +
                    to_string(info.output));
    run.metrics_json = ctx.metrics_json();
    run.warnings = ctx.warnings();
    run.outputs = files.commit();
    return run;
}

} // namespace cm
