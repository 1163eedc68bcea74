// Pipelines from Python: loaded from a file or parsed from the text the Python side writes,
// overridden as --set does, validated, and run by run_pipeline, the command's own executor,
// on a thread of its own while the calling thread shows progress and watches for Ctrl-C.
#include <mutex>
#include <set>

#include "core/error.h"
#include "module.h"
#include "pipeline/pipeline.h"

namespace fs = std::filesystem;

namespace cm::py {

std::map<std::string, std::string> param_text(const pyb::dict& params); // stages.cpp

namespace {

struct PyPipeline {
    Pipeline p;
};

pyb::dict run(PyPipeline& self, const pyb::object& progress, const std::string& report, const pyb::dict& labels,
              const std::string& side_output_dir, const pyb::object& keep) {
    // The outputs handed back: every node's, or those named (a grid the caller does not want is
    // freed as the run goes, as in the command).
    std::set<std::string> kept;
    const bool keep_all = keep.is_none();
    if (!keep_all)
        for (auto id : keep) kept.insert(std::string(pyb::str(id)));
    EventQueue events;
    std::atomic<bool> stop{false};
    std::mutex outputs_mutex;
    std::map<std::string, Data> outputs;
    RunOptions opt;
    opt.sink = &events;
    opt.stop = &stop;
    opt.report = report;
    opt.side_output_dir = !side_output_dir.empty() ? fs::path(side_output_dir)
                          : report.empty()         ? fs::path(".")
                                                   : fs::absolute(report).parent_path();
    for (auto [k, v] : labels) opt.labels[std::string(pyb::str(k))] = std::string(pyb::str(v));
    opt.on_output = [&](const std::string& node, const Data& d) {
        if (!keep_all && !kept.count(node)) return;
        std::lock_guard<std::mutex> lock(outputs_mutex);
        outputs[node] = d;
    };
    RunResult r;
    run_waiting([&] { r = run_pipeline(self.p, registry(), opt); }, events, progress, stop);

    pyb::object loads = pyb::module_::import("json").attr("loads");
    pyb::dict out, node_outputs, metrics, warnings;
    for (const auto& rec : r.nodes) {
        auto it = outputs.find(rec.id);
        node_outputs[pyb::str(rec.id)] = it == outputs.end() ? pyb::object(pyb::none()) : to_python(it->second);
        pyb::dict m;
        for (const auto& [k, v] : rec.metrics_json) m[pyb::str(k)] = loads(v);
        metrics[pyb::str(rec.id)] = m;
        warnings[pyb::str(rec.id)] = rec.warnings;
    }
    out["outputs"] = node_outputs;
    out["metrics"] = metrics;
    out["warnings"] = warnings;
    std::vector<std::string> files;
    for (const auto& f : r.outputs) files.push_back(f.string());
    out["files"] = files;
    // The report as --report writes it (its "outputs" are the files committed with it).
    out["report"] = r.to_json(self.p);
    out["seconds"] = r.seconds;
    out["peak_rss_bytes"] = r.peak_rss_bytes;
    return out;
}

pyb::list nodes_of(const Pipeline& p) {
    pyb::list nodes;
    for (const auto& n : p.nodes) {
        pyb::dict d;
        d["id"] = n.id;
        d["stage"] = n.stage;
        d["inputs"] = n.inputs;
        pyb::dict params;
        for (const auto& [k, raw] : n.raw_params) params[pyb::str(k)] = raw.text;
        d["params"] = params;
        d["line"] = n.line;
        nodes.append(d);
    }
    return nodes;
}

} // namespace

void bind_pipeline(pyb::module_& m) {
    pyb::class_<PyPipeline>(m, "NativePipeline", "A parsed pipeline (conceptmesh.Pipeline wraps it).")
        .def_static(
            "load",
            [](const std::string& path) { return translated([&] { return PyPipeline{Pipeline::load(path)}; }); },
            pyb::arg("path"))
        .def_static(
            "parse",
            [](const std::string& text, const std::string& name) {
                return translated([&] { return PyPipeline{Pipeline::parse(text, name)}; });
            },
            pyb::arg("text"), pyb::arg("name"))
        .def(
            "set",
            [](PyPipeline& self, const pyb::dict& values) {
                for (const auto& [k, v] : param_text(values))
                    translated(
                        [&, &key = k, &value = v] { self.p.apply_override(key + "=" + value, "set= in Python"); });
            },
            pyb::arg("values"), "Applies NODE.PARAM -> value overrides, as --set does.")
        .def(
            "validate",
            [](PyPipeline& self) {
                translated([&] {
                    pyb::gil_scoped_release released; // loads plugins
                    self.p.validate(registry());
                });
            },
            "Checks stages, parameters and the graph, and configures every stage.")
        .def("run", &run, pyb::arg("progress") = pyb::none(), pyb::arg("report") = "", pyb::arg("labels") = pyb::dict(),
             pyb::arg("side_output_dir") = "", pyb::arg("keep") = pyb::none())
        .def_property_readonly("nodes", [](const PyPipeline& self) { return nodes_of(self.p); })
        .def_property_readonly("name", [](const PyPipeline& self) { return self.p.name; })
        .def_property_readonly("description", [](const PyPipeline& self) { return self.p.description; })
        .def_property_readonly("file", [](const PyPipeline& self) { return self.p.file.string(); })
        .def_property_readonly("validated", [](const PyPipeline& self) { return self.p.validated; });
}

} // namespace cm::py
