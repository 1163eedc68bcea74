// Tool commands that work on meshes and views outside a pipeline
// (render-views, compare, preview). Added as they land.
#include "cli/commands.h"

namespace cm::cli {

void add_tool_commands(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    (void)app; (void)g; (void)action;
}

} // namespace cm::cli
