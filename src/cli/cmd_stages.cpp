// conceptmesh stages [--describe NAME] [--json]: the stages the plugins provide.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/tool_common.h"

using nlohmann::json;

namespace cm::cli {

namespace {

// A column at least `min` wide that leaves `gap` spaces after its longest entry.
template <class Items, class Text>
int column_width(int min, int gap, const Items& items, Text text) {
    std::size_t longest = 0;
    for (const auto& item : items) longest = std::max(longest, text(item).size());
    return std::max(min, int(longest) + gap);
}

std::string default_text(const ParamSpec& p) {
    return p.default_value ? format_value(*p.default_value) : (p.is_optional ? "(unset)" : "(required)");
}

json param_json(const ParamSpec& p) {
    json jp = {{"name", p.name}, {"type", to_string(p.type)}, {"doc", p.doc}, {"unit", p.unit}};
    jp["default"] = p.default_value ? param_to_json(*p.default_value) : json(nullptr);
    jp["required"] = !p.default_value && !p.is_optional;
    if (p.min) jp["min"] = *p.min;
    if (p.max) jp["max"] = *p.max;
    if (!p.choices.empty()) jp["choices"] = p.choices;
    return jp;
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
        j["inputs"].push_back(
            {{"name", p.name}, {"kind", to_string(p.kind)}, {"doc", p.doc}, {"optional", p.optional}});
    j["output"] = to_string(info.output);
    j["params"] = json::array();
    for (const auto& p : info.params) j["params"].push_back(param_json(p));
    return j;
}

// " in [min, max]" or " one of a b c", or nothing.
std::string range_text(const ParamSpec& p) {
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
    return range;
}

void describe(std::ostream& os, const StageInfo& info, const StageEntry* e) {
    os << info.name << " — " << info.summary << "\n";
    if (e) os << "  plugin: " << e->plugin << " " << e->plugin_version << " (" << e->library.string() << ")\n";
    os << "  inputs:";
    if (info.inputs.empty()) os << " none";
    os << "\n";
    const int input_w = column_width(12, 2, info.inputs, [](const auto& p) { return p.name; });
    for (const auto& p : info.inputs)
        os << "    " << std::left << std::setw(input_w) << p.name << to_string(p.kind)
           << (p.optional ? " (optional)" : "") << "  " << p.doc << "\n";
    os << "  output: " << to_string(info.output) << "\n  parameters:\n";
    if (info.params.empty()) os << "    none\n";
    const int name_w = column_width(18, 2, info.params, [](const auto& p) { return p.name; });
    for (const auto& p : info.params)
        os << "    " << std::left << std::setw(name_w) << p.name << std::setw(7) << to_string(p.type) << " default "
           << default_text(p) << range_text(p) << (p.unit.empty() ? "" : " " + p.unit) << "\n      " << p.doc << "\n";
}

// One line per stage and per parameter, in columns that fit every stage listed.
void list_stages(std::ostream& os, const std::vector<StageInfo>& infos) {
    std::vector<ParamSpec> params;
    for (const auto& info : infos) params.insert(params.end(), info.params.begin(), info.params.end());
    const int stage_w = column_width(30, 2, infos, [](const auto& i) { return i.name; });
    const int name_w = column_width(20, 2, params, [](const auto& p) { return p.name; });
    const int type_w = column_width(7, 1, params, [](const auto& p) { return std::string(to_string(p.type)); });
    for (const auto& info : infos) {
        os << std::left << std::setw(stage_w) << info.name << info.summary << "\n";
        for (const auto& p : info.params)
            os << "    " << std::setw(name_w) << p.name << std::setw(type_w) << to_string(p.type) << default_text(p)
               << (p.unit.empty() ? "" : " " + p.unit) << "\n";
    }
}

int run_stages(const std::string& name, bool as_json, const GlobalOptions& g) {
    print_plugin_diagnostics(g);
    const Registry& reg = Registry::global();
    const std::vector<std::string> names = name.empty() ? reg.names() : std::vector<std::string>{name};
    print_plugin_diagnostics(g); // the plugins load on first use
    std::vector<StageInfo> infos;
    if (!name.empty() && !reg.find(name)) {
        try {
            reg.create(name); // its message lists the known stages
        } catch (const Error& e) {
            throw UsageError(std::string("--describe: ") + e.what()); // a name mistyped on the command line
        }
    }
    for (const auto& n : names) infos.push_back(reg.create(n)->info());
    if (as_json) {
        json all = json::array();
        for (std::size_t i = 0; i < names.size(); ++i) all.push_back(stage_json(infos[i], reg.find(names[i])));
        std::cout << (name.empty() ? all : all[0]).dump(2) << "\n";
    } else if (!name.empty()) {
        describe(std::cout, infos[0], reg.find(name));
    } else {
        list_stages(std::cout, infos);
    }
    return 0;
}

} // namespace

void add_stages_command(CLI::App& app, GlobalOptions& g, std::function<int()>& action) {
    auto* cmd = app.add_subcommand("stages", "List the stages the plugins provide, with their parameters");
    auto name = std::make_shared<std::string>();
    auto as_json = std::make_shared<bool>(false);
    cmd->add_option("--describe", *name, "Show one stage in full");
    cmd->add_flag("--json", *as_json, "Machine-readable output");
    set_action(cmd, action, [&g, name, as_json] { return run_stages(*name, *as_json, g); });
}

} // namespace cm::cli
