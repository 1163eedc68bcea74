// conceptmesh schema DIR: the JSON Schemas of pipeline files and of every stage's parameters.
#include <iostream>

#include "cli/commands.h"
#include "cli/tool_common.h"
#include "io/file_commit.h"

namespace fs = std::filesystem;

namespace cm::cli {

const char* views_manifest_schema_json(); // generated from schemas/views-manifest.schema.json
const char* batch_schema_json();          // generated from schemas/batch.schema.json

void add_schema_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd =
        app.add_subcommand("schema", "Write the JSON Schemas (pipeline, views manifest, one per stage) into DIR");
    auto dir = std::make_shared<std::string>();
    cmd->add_option("dir", *dir, "Output folder (creates DIR/pipeline.schema.json and DIR/stages/)")->required();
    cmd->add_flag("-q,--quiet", g.quiet, "Print nothing but errors");
    set_action(cmd, action, [&g, dir] {
        print_plugin_diagnostics(g);
        const Registry& reg = Registry::global();
        fs::create_directories(fs::path(*dir) / "stages");
        write_file_atomic(fs::path(*dir) / "pipeline.schema.json", pipeline_schema_json(reg));
        write_file_atomic(fs::path(*dir) / "views-manifest.schema.json", views_manifest_schema_json());
        write_file_atomic(fs::path(*dir) / "batch.schema.json", batch_schema_json());
        for (const auto& n : reg.names())
            write_file_atomic(fs::path(*dir) / "stages" / (n + ".schema.json"),
                              stage_schema_json(reg.create(n)->info()));
        print_plugin_diagnostics(g); // the plugins load on first use
        if (!g.quiet) std::cerr << "conceptmesh: wrote " << reg.names().size() + 3 << " schemas into " << *dir << "\n";
        return 0;
    });
}

} // namespace cm::cli
