// conceptmesh validate: checks a pipeline (schema, parameters, graph) without running it.
#include <iostream>

#include "cli/commands.h"
#include "cli/tool_common.h"

namespace cm::cli {

void add_validate_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd = app.add_subcommand("validate", "Check a pipeline (schema, parameters, graph) without running it");
    auto file = std::make_shared<std::string>();
    auto sets = std::make_shared<std::vector<std::string>>();
    cmd->add_option("pipeline", *file, "Pipeline YAML file")->required();
    cmd->add_option("--set", *sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
    set_action(cmd, action, [&g, file, sets] {
        print_plugin_diagnostics(g);
        Pipeline p = load_checked(*file, *sets, g);
        std::cout << *file << ": valid (" << p.nodes.size() << " nodes:";
        for (auto i : p.order) std::cout << " " << p.nodes[i].id;
        std::cout << ")\n";
        return 0;
    });
}

} // namespace cm::cli
