#include "pipeline/renamed_params.h"

namespace cm {

namespace {

// Oldest first. An entry stays as long as pipelines written before the renaming may be
// around; the stage's own declaration is the parameter's documentation.
constexpr RenamedParam kRenamed[] = {
    {"texture.project", "strip_lines", "strokes", "strip_lines: false is strokes: keep, true is strokes: strip"},
};

} // namespace

const RenamedParam* find_renamed_param(const std::string& stage, const std::string& name) {
    for (const auto& r : kRenamed)
        if (stage == r.stage && name == r.old_name) return &r;
    return nullptr;
}

std::string renamed_param_hint(const std::string& stage, const std::string& name) {
    const RenamedParam* r = find_renamed_param(stage, name);
    if (!r) return "";
    return std::string(": it is now \"") + r->new_name + "\" (" + r->how + ")";
}

} // namespace cm
