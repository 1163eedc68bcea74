// Checking a parsed pipeline against the registry, in steps: each node's stage and
// parameters, its connections, the kinds along every edge, and the dependency order.
#include <filesystem>

#include "core/error.h"
#include "pipeline/pipeline.h"
#include "pipeline/renamed_params.h"

namespace fs = std::filesystem;

namespace cm {

ParamValue param_value(const ParamSpec& spec, const RawParam& raw) {
    if (raw.from_set()) return parse_param_text(spec, raw.text);
    return parse_param_yaml(spec, raw.text, raw.kind);
}

ParamSet resolve_params(const StageInfo& info, const std::map<std::string, RawParam>& raw_params,
                        const std::function<std::string(int)>& where) {
    ParamSet ps;
    for (const auto& [key, raw] : raw_params) {
        const ParamSpec* spec = find_param(info.params, key);
        const std::string src = raw.from_set() ? " (from " + raw.source + ")" : "";
        // A bad --set value is a command-line mistake (exit status 2); a bad file value is not.
        auto fail = [&, &r = raw](const std::string& text) { // (a structured binding is not captured by clang 14)
            if (r.from_set()) throw UsageError(where(r.line) + text);
            throw Error(where(r.line) + text);
        };
        if (!spec) {
            // A former name gets the parameter to write instead; any other the declared names.
            const std::string hint = renamed_param_hint(info.name, key);
            fail("unknown parameter \"" + key + "\"" + src +
                 (hint.empty() ? " (parameters: " + param_names(info.params) + ")" : hint));
        }
        if (spec->is_optional && !raw.from_set() && raw.is_null()) continue; // null: left unset
        ParamValue v;
        try {
            v = param_value(*spec, raw);
        } catch (const Error& e) {
            fail(e.what() + src);
        }
        if (auto why = check_param(*spec, v); !why.empty()) fail(why + src);
        ps.set(key, v);
        ps.mark_explicit(key);
    }
    if (auto missing = fill_defaults(info.params, ps); !missing.empty()) throw Error(where(0) + missing);
    return ps;
}

namespace {

using NodeIndex = std::map<std::string, std::size_t>;

/// Creates the node's stage to learn its info, and resolves its parameters against it.
void resolve_stage(const Pipeline& p, PipelineNode& n, const Registry& registry) {
    if (!registry.find(n.stage)) {
        std::string known;
        for (const auto& s : registry.names()) known += (known.empty() ? "" : ", ") + s;
        throw Error(p.where(n) + "unknown stage \"" + n.stage +
                    "\" (known stages: " + (known.empty() ? "none; no plugin was found" : known) + ")");
    }
    std::unique_ptr<Stage> stage;
    try {
        stage = registry.create(n.stage);
    } catch (const Error& e) {
        throw Error(p.where(n) + e.what());
    }
    n.info = stage->info();
    n.params = resolve_params(n.info, n.raw_params, [&](int line) { return p.where(n, line); });
}

const PortSpec* find_port(const StageInfo& info, const std::string& port) {
    for (const auto& spec : info.inputs)
        if (spec.name == port) return &spec;
    return nullptr;
}

/// Every connection names a declared port and a known node; every port that is not
/// optional is connected.
void check_connections(const Pipeline& p, const PipelineNode& n, const NodeIndex& index) {
    for (const auto& [port, src] : n.inputs) {
        const int line = n.input_lines.at(port);
        if (!find_port(n.info, port)) {
            std::string known;
            for (const auto& spec : n.info.inputs) known += (known.empty() ? "" : ", ") + spec.name;
            throw Error(p.where(n, line) + "unknown input port \"" + port +
                        "\" (ports: " + (known.empty() ? "none" : known) + ")");
        }
        if (!index.count(src))
            throw Error(p.where(n, line) + "input \"" + port + "\" names unknown node \"" + src + "\"");
    }
    for (const auto& spec : n.info.inputs)
        if (!spec.optional && !n.inputs.count(spec.name))
            throw Error(p.where(n) + "missing input \"" + spec.name + "\" (" + to_string(spec.kind) + ": " + spec.doc +
                        ")");
}

/// Every connection carries the kind its port takes (needs every node's info).
void check_kinds(const Pipeline& p, const NodeIndex& index) {
    for (const auto& n : p.nodes) {
        for (const auto& [port, src] : n.inputs) {
            const PipelineNode& from = p.nodes[index.at(src)];
            const PortSpec* spec = find_port(n.info, port);
            if (spec->kind != from.info.output)
                throw Error(p.where(n, n.input_lines.at(port)) + "input \"" + port + "\" needs " +
                            to_string(spec->kind) + " but node \"" + src + "\" (" + from.stage + ") gives " +
                            to_string(from.info.output));
        }
    }
}

/// The cycle through the nodes Kahn's algorithm left (`indeg` > 0), in data-flow order.
[[noreturn]] void throw_cycle(const Pipeline& p, const NodeIndex& index, const std::vector<int>& indeg) {
    // Walk back along inputs from a node left over to print the cycle itself.
    std::size_t start = 0;
    while (indeg[start] == 0) ++start;
    std::vector<std::size_t> path;
    std::vector<int> seen(p.nodes.size(), -1);
    std::size_t cur = start;
    while (seen[cur] < 0) {
        seen[cur] = int(path.size());
        path.push_back(cur);
        for (const auto& [port, src] : p.nodes[cur].inputs)
            if (indeg[index.at(src)] > 0) {
                cur = index.at(src);
                break;
            }
    }
    // path follows inputs backwards; print the cycle in data-flow order.
    std::string cyc;
    for (std::size_t k = path.size(); k-- > std::size_t(seen[cur]);) cyc += p.nodes[path[k]].id + " -> ";
    cyc += p.nodes[path.back()].id;
    throw Error(p.where(p.nodes[cur]) + "the graph has a cycle: " + cyc);
}

/// Topological order (Kahn); what remains is on a cycle.
std::vector<std::size_t> dependency_order(const Pipeline& p, const NodeIndex& index) {
    const std::size_t n = p.nodes.size();
    std::vector<int> indeg(n, 0);
    std::vector<std::vector<std::size_t>> out(n);
    for (std::size_t i = 0; i < n; ++i)
        for (const auto& [port, src] : p.nodes[i].inputs) {
            out[index.at(src)].push_back(i);
            ++indeg[i];
        }
    std::vector<std::size_t> order, ready;
    for (std::size_t i = 0; i < n; ++i)
        if (indeg[i] == 0) ready.push_back(i);
    while (!ready.empty()) {
        std::size_t i = ready.front();
        ready.erase(ready.begin());
        order.push_back(i);
        for (auto j : out[i])
            if (--indeg[j] == 0) ready.push_back(j);
    }
    if (order.size() != n) throw_cycle(p, index, indeg);
    return order;
}

/// Two nodes that would write one file: the second would silently replace the first.
void check_output_clashes(const Pipeline& p) {
    std::map<fs::path, const PipelineNode*> writers;
    for (const auto& n : p.nodes)
        for (const auto& spec : n.info.params) {
            if (spec.type != ParamType::Path || spec.extensions.empty() || !n.params.has(spec.name)) continue;
            const fs::path path = n.params.get_string(spec.name);
            std::error_code ec;
            fs::path key = fs::weakly_canonical(fs::absolute(path), ec);
            if (ec) key = fs::absolute(path).lexically_normal();
            const auto [it, fresh] = writers.emplace(key, &n);
            if (!fresh)
                throw Error(p.where(n, n.raw_params.count(spec.name) ? n.raw_params.at(spec.name).line : 0) +
                            spec.name + " \"" + path.string() + "\" is also written by node \"" + it->second->id +
                            "\" (line " + std::to_string(it->second->line) + "); give each output its own file");
        }
}

} // namespace

std::vector<std::unique_ptr<Stage>> configure_stages(const Pipeline& p, const Registry& registry) {
    std::vector<std::unique_ptr<Stage>> stages(p.nodes.size());
    for (std::size_t i : p.order) {
        const auto& node = p.nodes[i];
        try {
            stages[i] = registry.create(node.stage);
            stages[i]->configure(node.params);
        } catch (const std::exception& e) {
            throw Error(p.where(node) + e.what());
        }
    }
    return stages;
}

void Pipeline::resolve_node(std::size_t i, const Registry& registry) {
    resolve_stage(*this, nodes.at(i), registry);
    check_connections(*this, nodes[i], node_index());
}

void Pipeline::validate(const Registry& registry) {
    validated = false;
    const NodeIndex index = node_index();
    for (auto& n : nodes) {
        resolve_stage(*this, n, registry);
        check_connections(*this, n, index);
    }
    check_kinds(*this, index);
    order = dependency_order(*this, index);
    check_output_clashes(*this);
    configure_stages(*this, registry); // the stages' own checks (a missing manifest, ...)
    validated = true;
}

} // namespace cm
