// Parameters that were renamed: a pipeline written for an earlier version that still uses
// an old name is told which parameter to write instead, rather than only that the name is
// unknown.
#pragma once
#include <string>

namespace cm {

/// A parameter of `stage` once called `old_name`, now `new_name`; `how` says how the old
/// values read now ("strip_lines: false is strokes: keep, true is strokes: strip").
struct RenamedParam {
    const char* stage;
    const char* old_name;
    const char* new_name;
    const char* how;
};

/// The renaming of `stage`'s former parameter `name`, or null when it never had one.
const RenamedParam* find_renamed_param(const std::string& stage, const std::string& name);

/// What follows `unknown parameter "<name>"` in the message: `: it is now "<new>" (<how>)`
/// for a former name of a parameter `stage` still declares, else an empty string.
std::string renamed_param_hint(const std::string& stage, const std::string& name);

} // namespace cm
