// conceptmesh run | validate | stages | schema
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/progress_printer.h"
#include "core/error.h"
#include "pipeline/pipeline.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::cli {

namespace {

void write_text_file(const fs::path& path, const std::string& text) {
    auto tmp = path;
    tmp += ".part";
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw Error("cannot write \"" + path.string() + "\": " + std::strerror(errno));
        out << text;
        if (!out.flush()) throw Error("cannot write \"" + path.string() + "\": " + std::strerror(errno));
    }
    fs::rename(tmp, path);
}

Pipeline load_checked(const std::string& file, const std::vector<std::string>& sets) {
    Pipeline p = Pipeline::load(file);
    for (const auto& s : sets) p.apply_override(s);
    p.validate(Registry::global());
    return p;
}

json stage_json(const StageInfo& info, const StageEntry* e) {
    json j;
    j["name"] = info.name;
    j["summary"] = info.summary;
    if (e) {
        j["plugin"] = e->plugin;
        j["plugin_version"] = e->plugin_version;
        j["library"] = e->library.string();
    }
    j["inputs"] = json::array();
    for (const auto& p : info.inputs)
        j["inputs"].push_back({{"name", p.name}, {"kind", to_string(p.kind)}, {"doc", p.doc}, {"optional", p.optional}});
    j["output"] = to_string(info.output);
    j["params"] = json::array();
    for (const auto& p : info.params) {
        json jp = {{"name", p.name}, {"type", to_string(p.type)}, {"doc", p.doc}, {"unit", p.unit}};
        jp["default"] = p.default_value ? param_to_json(*p.default_value) : json(nullptr);
        jp["required"] = !p.default_value && !p.is_optional;
        if (p.min) jp["min"] = *p.min;
        if (p.max) jp["max"] = *p.max;
        if (!p.choices.empty()) jp["choices"] = p.choices;
        j["params"].push_back(jp);
    }
    return j;
}

void describe(std::ostream& os, const StageInfo& info, const StageEntry* e) {
    os << info.name << " — " << info.summary << "\n";
    if (e) os << "  plugin: " << e->plugin << " " << e->plugin_version << " (" << e->library.string() << ")\n";
    os << "  inputs:";
    if (info.inputs.empty()) os << " none";
    os << "\n";
    for (const auto& p : info.inputs)
        os << "    " << std::left << std::setw(12) << p.name << to_string(p.kind) << (p.optional ? " (optional)" : "")
           << "  " << p.doc << "\n";
    os << "  output: " << to_string(info.output) << "\n  parameters:\n";
    if (info.params.empty()) os << "    none\n";
    for (const auto& p : info.params) {
        std::string range;
        if (p.min || p.max) {
            std::ostringstream r;
            r << " in [" << (p.min ? *p.min : -INFINITY) << ", " << (p.max ? *p.max : INFINITY) << "]";
            range = r.str();
        }
        if (!p.choices.empty()) {
            range = " one of";
            for (const auto& c : p.choices) range += " " + c;
        }
        const std::string def = p.default_value ? format_value(*p.default_value) : (p.is_optional ? "(unset)" : "(required)");
        os << "    " << std::left << std::setw(18) << p.name << std::setw(7) << to_string(p.type) << " default "
           << def << range << (p.unit.empty() ? "" : " " + p.unit) << "\n      " << p.doc << "\n";
    }
}

} // namespace

void add_pipeline_commands(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    // run
    {
        auto* cmd = app.add_subcommand("run", "Run a pipeline");
        auto file = std::make_shared<std::string>();
        auto sets = std::make_shared<std::vector<std::string>>();
        auto report = std::make_shared<std::string>();
        cmd->add_option("pipeline", *file, "Pipeline YAML file")->required();
        cmd->add_option("--set", *sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
        cmd->add_option("--report", *report, "Write a JSON run report (per node: params, time, memory, counts)");
        cmd->add_flag("-q,--quiet", g.quiet, "Only errors and warnings");
        cmd->add_flag("-v,--verbose", g.verbose, "More detail while running");
        cmd->callback([&g, &action, file, sets, report] {
            action = [&g, file, sets, report]() -> int {
                print_plugin_diagnostics(g);
                Pipeline p = load_checked(*file, *sets);
                if (!report->empty()) {
                    const fs::path dir = fs::absolute(*report).parent_path();
                    if (!fs::is_directory(dir))
                        throw Error("--report \"" + *report + "\": the folder \"" + dir.string() + "\" does not exist");
                }
                ProgressPrinter printer(g.quiet, g.verbose);
                RunOptions opt;
                opt.sink = &printer;
                opt.side_output_dir = report->empty() ? fs::path(".") : fs::absolute(*report).parent_path();
                RunResult r = run_pipeline(p, Registry::global(), opt);
                if (!report->empty()) write_text_file(*report, r.to_json(p));
                if (!g.quiet) {
                    for (const auto& o : r.outputs) std::cerr << "conceptmesh: wrote " << o.string() << "\n";
                    std::cerr << "conceptmesh: finished in " << std::fixed << std::setprecision(2) << r.seconds
                              << " s, peak memory " << (r.peak_rss_bytes >> 20) << " MiB\n";
                }
                return 0;
            };
        });
    }
    // validate
    {
        auto* cmd = app.add_subcommand("validate", "Check a pipeline (schema, parameters, graph) without running it");
        auto file = std::make_shared<std::string>();
        auto sets = std::make_shared<std::vector<std::string>>();
        cmd->add_option("pipeline", *file, "Pipeline YAML file")->required();
        cmd->add_option("--set", *sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
        cmd->callback([&g, &action, file, sets] {
            action = [&g, file, sets]() -> int {
                print_plugin_diagnostics(g);
                Pipeline p = load_checked(*file, *sets);
                std::cout << *file << ": valid (" << p.nodes.size() << " nodes:";
                for (auto i : p.order) std::cout << " " << p.nodes[i].id;
                std::cout << ")\n";
                return 0;
            };
        });
    }
    // stages
    {
        auto* cmd = app.add_subcommand("stages", "List the stages the plugins provide, with their parameters");
        auto name = std::make_shared<std::string>();
        auto as_json = std::make_shared<bool>(false);
        cmd->add_option("--describe", *name, "Show one stage in full");
        cmd->add_flag("--json", *as_json, "Machine-readable output");
        cmd->callback([&g, &action, name, as_json] {
            action = [&g, name, as_json]() -> int {
                print_plugin_diagnostics(g);
                const Registry& reg = Registry::global();
                std::vector<std::string> names = name->empty() ? reg.names() : std::vector<std::string>{*name};
                json all = json::array();
                for (const auto& n : names) {
                    auto stage = reg.create(n);
                    const StageInfo info = stage->info();
                    if (*as_json) all.push_back(stage_json(info, reg.find(n)));
                    else if (!name->empty()) describe(std::cout, info, reg.find(n));
                    else {
                        std::cout << std::left << std::setw(30) << n << info.summary << "\n";
                        for (const auto& p : info.params) {
                            std::cout << "    " << std::setw(20) << p.name << std::setw(7) << to_string(p.type)
                                      << (p.default_value ? format_value(*p.default_value) : (p.is_optional ? "(unset)" : "(required)"))
                                      << (p.unit.empty() ? "" : " " + p.unit) << "\n";
                        }
                    }
                }
                if (*as_json) std::cout << (name->empty() ? all : all[0]).dump(2) << "\n";
                return 0;
            };
        });
    }
    // schema
    {
        auto* cmd = app.add_subcommand("schema", "Write the JSON Schemas (pipeline and one per stage) into DIR");
        auto dir = std::make_shared<std::string>();
        cmd->add_option("dir", *dir, "Output folder (creates DIR/pipeline.schema.json and DIR/stages/)")->required();
        cmd->add_flag("-q,--quiet", g.quiet, "Print nothing but errors");
        cmd->callback([&g, &action, dir] {
            action = [&g, dir]() -> int {
                print_plugin_diagnostics(g);
                const Registry& reg = Registry::global();
                fs::create_directories(fs::path(*dir) / "stages");
                write_text_file(fs::path(*dir) / "pipeline.schema.json", pipeline_schema_json(reg));
                for (const auto& n : reg.names())
                    write_text_file(fs::path(*dir) / "stages" / (n + ".schema.json"), stage_schema_json(reg.create(n)->info()));
                if (!g.quiet) std::cerr << "conceptmesh: wrote " << reg.names().size() + 1 << " schemas into " << *dir << "\n";
                return 0;
            };
        });
    }
}

} // namespace cm::cli
