// Stages from Python: their declarations (for docstrings and stubs), a stage run on data the
// caller holds (run_stage, the path the command-line tools take), and the registry the module
// runs them from.
#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "core/params.h"
#include "module.h"
#include "pipeline/run_stage.h"

namespace fs = std::filesystem;

namespace cm::py {

namespace {

/// The plugin folders: beside the module in the build tree (<build>/python/conceptmesh ->
/// <build>/lib/conceptmesh/plugins), else where the install put them relative to the module
/// (<prefix>/lib/python3/dist-packages/conceptmesh -> <prefix>/<libdir>/conceptmesh/plugins);
/// then CONCEPTMESH_PLUGIN_PATH, as for the command.
std::vector<fs::path> plugin_dirs() {
    std::vector<fs::path> dirs;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&plugin_dirs), &info) && info.dli_fname) {
        const fs::path here = fs::path(info.dli_fname).parent_path();
        for (const char* rel : {CONCEPTMESH_BUILD_PLUGIN_DIR, CONCEPTMESH_INSTALLED_PLUGIN_DIR})
            if (fs::is_directory(here / rel)) {
                dirs.push_back((here / rel).lexically_normal());
                break;
            }
    }
    // The command's search path after its first entry (the folder beside the executable, which
    // here is python3's): the folders of CONCEPTMESH_PLUGIN_PATH.
    const std::vector<fs::path> command_dirs = Registry::default_dirs();
    dirs.insert(dirs.end(), command_dirs.begin() + 1, command_dirs.end());
    return dirs;
}

/// One parameter as a docstring line: "max_angle_deg: float = 20 [0.1, 89] deg -- doc".
std::string describe(const ParamSpec& s) {
    std::string line = "    " + s.name + ": " + to_string(s.type);
    if (s.default_value) line += " = " + format_value(*s.default_value);
    else if (s.is_optional) line += " (optional)";
    else line += " (required)";
    if (s.min || s.max) {
        std::ostringstream r;
        r << " [" << (s.min ? format_value(*s.min) : std::string("-inf")) << ", "
          << (s.max ? format_value(*s.max) : std::string("inf")) << "]";
        line += r.str();
    }
    if (!s.unit.empty()) line += " " + s.unit;
    if (!s.choices.empty()) {
        line += " {";
        for (std::size_t i = 0; i < s.choices.size(); ++i) line += (i ? ", " : "") + s.choices[i];
        line += "}";
    }
    if (!s.extensions.empty()) {
        line += " (";
        for (std::size_t i = 0; i < s.extensions.size(); ++i) line += (i ? ", " : "") + s.extensions[i];
        line += ")";
    }
    return line + "\n        " + s.doc;
}

std::string stage_doc(const StageInfo& info) {
    std::string doc = info.name + ": " + info.summary + "\n\nInputs:\n";
    if (info.inputs.empty()) doc += "    none\n";
    for (const auto& p : info.inputs)
        doc += "    " + p.name + ": " + to_string(p.kind) + (p.optional ? " (optional)" : "") + " -- " + p.doc + "\n";
    doc += "Output: " + std::string(to_string(info.output)) + "\n\nParameters:\n";
    if (info.params.empty()) doc += "    none\n";
    for (const auto& s : info.params) doc += describe(s) + "\n";
    return doc;
}

pyb::dict param_dict(const ParamSpec& s) {
    pyb::dict d;
    d["name"] = s.name;
    d["type"] = to_string(s.type);
    d["default"] = s.default_value ? pyb::cast(format_value(*s.default_value)) : pyb::object(pyb::none());
    d["min"] = s.min ? pyb::cast(*s.min) : pyb::object(pyb::none());
    d["max"] = s.max ? pyb::cast(*s.max) : pyb::object(pyb::none());
    d["unit"] = s.unit;
    d["doc"] = s.doc;
    d["choices"] = s.choices;
    d["required"] = !s.default_value && !s.is_optional;
    d["extensions"] = s.extensions;
    return d;
}

/// Python values as the text --set takes ("true", "20", "a/b.obj").
std::map<std::string, std::string> text_of(const pyb::dict& params) {
    std::map<std::string, std::string> out;
    for (auto [k, v] : params) {
        std::string text;
        if (pyb::isinstance<pyb::bool_>(v)) text = v.cast<bool>() ? "true" : "false";
        else if (pyb::isinstance<pyb::str>(v)) text = v.cast<std::string>();
        else if (pyb::hasattr(v, "__fspath__")) text = pyb::str(v.attr("__fspath__")()).cast<std::string>();
        else text = pyb::str(v).cast<std::string>();
        out[k.cast<std::string>()] = text;
    }
    return out;
}

} // namespace

std::map<std::string, std::string> param_text(const pyb::dict& params) { return text_of(params); }

const Registry& registry() {
    static Registry* r = [] {
        auto* reg = new Registry(); // never destroyed: plugins stay loaded until exit
        reg->load_directories(plugin_dirs());
        add_memory_stages(*reg);
        return reg;
    }();
    return *r;
}

void bind_stages(pyb::module_& m) {
    m.def(
        "stage_names", [] { return translated([] { return registry().names(); }); },
        "The names of every stage of every plugin (and the memory.* stages of this module).");
    m.def(
        "stage_info",
        [](const std::string& name) {
            return translated([&] {
                const StageInfo info = registry().create(name)->info();
                pyb::dict d;
                d["name"] = info.name;
                d["summary"] = info.summary;
                pyb::list inputs;
                for (const auto& p : info.inputs) {
                    pyb::dict port;
                    port["name"] = p.name;
                    port["kind"] = to_string(p.kind);
                    port["doc"] = p.doc;
                    port["optional"] = p.optional;
                    inputs.append(port);
                }
                d["inputs"] = inputs;
                d["output"] = to_string(info.output);
                pyb::list params;
                for (const auto& s : info.params) params.append(param_dict(s));
                d["params"] = params;
                d["doc"] = stage_doc(info);
                return d;
            });
        },
        pyb::arg("name"), "A stage's declaration: summary, inputs, output and parameters, and its docstring.");
    m.def(
        "check_stage_params",
        [](const std::string& name, const pyb::dict& params) {
            const auto text = text_of(params);
            try {
                configure_stage(registry(), name, text_params(text, "a keyword argument"));
            } catch (const std::exception& e) {
                raise_error(e, name); // a stage alone: no node, the stage named
            }
        },
        pyb::arg("name"), pyb::arg("params"), "Checks parameters against the stage (ParameterError when refused).");
    m.def(
        "run_stage",
        [](const std::string& name, const pyb::dict& params, const pyb::dict& inputs, const pyb::object& progress,
           const std::string& side_output_dir) {
            const auto raw = text_params(text_of(params), "a keyword argument");
            Inputs in;
            for (auto [port, data] : inputs)
                in.set(port.cast<std::string>(), from_python(data, "input \"" + port.cast<std::string>() + "\""));
            EventQueue events;
            std::atomic<bool> stop{false};
            StageRunOptions opt;
            opt.sink = &events;
            opt.side_output_dir = side_output_dir;
            opt.node = name;
            opt.stop = &stop;
            StageRun run;
            try {
                run_waiting([&] { run = run_stage(registry(), name, raw, in, opt); }, events, progress, stop);
            } catch (const pyb::error_already_set& e) {
                // A stage run outside a pipeline names no node: the stage is the one called.
                pyb::object value = e.value();
                if (pyb::hasattr(value, "stage") && value.attr("stage").is_none()) value.attr("stage") = name;
                throw;
            }
            pyb::dict out;
            out["output"] = to_python(run.output);
            pyb::dict metrics;
            pyb::object loads = pyb::module_::import("json").attr("loads");
            for (const auto& [k, v] : run.metrics_json) metrics[pyb::str(k)] = loads(v);
            out["metrics"] = metrics;
            out["warnings"] = run.warnings;
            std::vector<std::string> files;
            for (const auto& f : run.outputs) files.push_back(f.string());
            out["files"] = files;
            return out;
        },
        pyb::arg("name"), pyb::arg("params"), pyb::arg("inputs"), pyb::arg("progress") = pyb::none(),
        pyb::arg("side_output_dir") = ".",
        "Runs one stage on data the caller holds (the GIL released; progress on the calling thread; Ctrl-C "
        "stops it). Returns {output, metrics, warnings, files}.");
    m.def(
        "memory_put", [](const pyb::handle& data) { return memory_put(from_python(data, "data")); },
        "Holds a Mesh, Views or Volume for a memory.* node; returns its key.");
    m.def("memory_drop", &memory_drop, "Forgets the data under `key`.");
    m.def(
        "registry_diagnostics", [] { return registry().diagnostics(); },
        "What loading the plugins reported (refused plugins, stale index).");
}

} // namespace cm::py
