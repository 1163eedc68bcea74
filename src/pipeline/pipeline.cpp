#include "pipeline/pipeline.h"

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>
#include <yaml-cpp/yaml.h>

#include "core/error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm {

namespace {

int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

std::string file_line(const fs::path& file, int line) {
    std::string s = file.string();
    if (line > 0) s += ":" + std::to_string(line);
    return s;
}

// The structural schema, shared by the generated file and the validator.
json pipeline_structure(const std::vector<std::string>& stage_names) {
    json node = {
        {"type", "object"},
        {"description", "One step of the pipeline: a stage, its inputs and its parameters."},
        {"required", {"id", "stage"}},
        {"additionalProperties", false},
        {"properties",
         {{"id", {{"type", "string"}, {"pattern", "^[A-Za-z_][A-Za-z0-9_-]*$"},
                  {"description", "Unique name of the node; used by inputs and by --set NODE.PARAM=VALUE."}}},
          {"stage", {{"type", "string"}, {"description", "The stage this node runs (conceptmesh stages lists them)."},
                     {"examples", stage_names}}},
          {"inputs", {{"type", "object"}, {"description", "Input port -> id of the node that feeds it."},
                      {"additionalProperties", {{"type", "string"}}}}},
          {"params", {{"type", "object"}, {"description", "The stage's parameters (conceptmesh stages --describe STAGE)."}}}}}};
    return {
        {"$schema", "http://json-schema.org/draft-07/schema#"},
        {"$id", "https://conceptmesh.dev/schemas/pipeline.schema.json"},
        {"title", "conceptmesh pipeline"},
        {"description", "A graph of conceptmesh stages. Run with: conceptmesh run FILE"},
        {"type", "object"},
        {"required", {"nodes"}},
        {"additionalProperties", false},
        {"properties",
         {{"pipeline", {{"type", "string"}, {"description", "Name of the pipeline."}}},
          {"description", {{"type", "string"}, {"description", "What the pipeline does."}}},
          {"nodes", {{"type", "array"}, {"minItems", 1}, {"items", {{"$ref", "#/definitions/node"}}}}}}},
        {"definitions", {{"node", node}}}};
}

// Follows a valijson context path ("<root>", "[nodes]", "[0]", ...) into the YAML document.
YAML::Node follow(const YAML::Node& root, const std::vector<std::string>& ctx) {
    YAML::Node cur = root;
    for (const auto& c : ctx) {
        if (c == "<root>" || c.size() < 3 || c.front() != '[') continue;
        const std::string key = c.substr(1, c.size() - 2);
        YAML::Node next(YAML::NodeType::Undefined);
        if (cur.IsSequence()) {
            try { next.reset(cur[std::stoul(key)]); } catch (...) { break; }
        } else if (cur.IsMap()) {
            for (auto it = cur.begin(); it != cur.end(); ++it)
                if (it->first.Scalar() == key) { next.reset(it->second); break; }
        }
        if (!next.IsDefined()) break;
        cur.reset(next);   // operator= would assign into the document
    }
    return cur;
}

// YAML -> JSON for the validator (valijson's yaml-cpp adapter does not compile
// with every constraint). Plain scalars become numbers or booleans when they read as one.
json to_json(const YAML::Node& n) {
    switch (n.Type()) {
    case YAML::NodeType::Map: {
        json j = json::object();
        for (auto it = n.begin(); it != n.end(); ++it) j[it->first.Scalar()] = to_json(it->second);
        return j;
    }
    case YAML::NodeType::Sequence: {
        json j = json::array();
        for (const auto& x : n) j.push_back(to_json(x));
        return j;
    }
    case YAML::NodeType::Scalar: {
        if (n.Tag() == "!") return n.Scalar();   // quoted: always a string
        const std::string& s = n.Scalar();
        if (s == "true" || s == "false") return s == "true";
        try {
            std::size_t pos = 0;
            long long i = std::stoll(s, &pos);
            if (pos == s.size()) return i;
            double d = std::stod(s, &pos);
            if (pos == s.size()) return d;
        } catch (...) {
        }
        return s;
    }
    default: return nullptr;
    }
}

void validate_structure(const YAML::Node& doc, const fs::path& file) {
    static const json schema_doc = pipeline_structure({});
    static const std::unique_ptr<valijson::Schema> schema = [] {
        auto s = std::make_unique<valijson::Schema>();
        valijson::SchemaParser parser;
        valijson::adapters::NlohmannJsonAdapter a(schema_doc);
        parser.populateSchema(a, *s);
        return s;
    }();
    valijson::Validator validator;
    valijson::ValidationResults results;
    const json as_json = to_json(doc);
    valijson::adapters::NlohmannJsonAdapter target(as_json);
    if (validator.validate(*schema, target, &results)) return;
    // Report the most specific error.
    valijson::ValidationResults::Error best;
    for (const auto& e : results)
        if (e.context.size() > best.context.size() || best.description.empty()) best = e;
    std::string path;
    for (const auto& c : best.context)
        if (c != "<root>") path += c;
    YAML::Node at = follow(doc, best.context);
    // Name the node when the error is inside one.
    std::string node_part;
    if (best.context.size() >= 3 && best.context[1] == "[nodes]") {
        YAML::Node n = follow(doc, {best.context[0], best.context[1], best.context[2]});
        if (n.IsMap() && n["id"] && n["id"].IsScalar()) {
            node_part = "node \"" + n["id"].Scalar() + "\"";
            if (n["stage"] && n["stage"].IsScalar()) node_part += " (" + n["stage"].Scalar() + ")";
            node_part += ": ";
        }
    }
    throw Error(file_line(file, line_of(at)) + ": " + node_part + "does not match the pipeline schema at " +
                (path.empty() ? "the top level" : path) + ": " + best.description);
}

} // namespace

Pipeline Pipeline::load(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw Error("cannot open pipeline \"" + file.string() + "\": " + std::strerror(errno));
    std::stringstream ss;
    ss << in.rdbuf();
    return parse(ss.str(), file);
}

Pipeline Pipeline::parse(const std::string& text, const fs::path& file) {
    YAML::Node doc;
    try {
        doc = YAML::Load(text);
    } catch (const YAML::Exception& e) {
        throw Error(file_line(file, e.mark.line + 1) + ": malformed YAML: " + e.msg);
    }
    if (!doc.IsMap()) throw Error(file.string() + ": a pipeline must be a YAML mapping with a \"nodes\" list");
    validate_structure(doc, file);

    Pipeline p;
    p.file = file;
    if (doc["pipeline"]) p.name = doc["pipeline"].Scalar();
    if (doc["description"]) p.description = doc["description"].Scalar();
    std::set<std::string> ids;
    for (const auto& n : doc["nodes"]) {
        PipelineNode node;
        node.id = n["id"].Scalar();
        node.stage = n["stage"].Scalar();
        node.line = line_of(n);
        if (!ids.insert(node.id).second)
            throw Error(file_line(file, node.line) + ": node \"" + node.id + "\" (" + node.stage +
                        "): the id is used by another node already");
        if (n["inputs"]) {
            for (auto it = n["inputs"].begin(); it != n["inputs"].end(); ++it) {
                node.inputs[it->first.Scalar()] = it->second.Scalar();
                node.input_lines[it->first.Scalar()] = line_of(it->second);
            }
        }
        if (n["params"]) {
            for (auto it = n["params"].begin(); it != n["params"].end(); ++it) {
                RawParam raw;
                raw.node = it->second;   // a copy: it->second lives in a temporary
                raw.line = line_of(raw.node);
                if (raw.node.IsScalar()) raw.text = raw.node.Scalar();
                node.raw_params[it->first.Scalar()] = raw;
            }
        }
        p.nodes.push_back(std::move(node));
    }
    return p;
}

std::string Pipeline::where(const PipelineNode& n, int line) const {
    return file_line(file, line ? line : n.line) + ": node \"" + n.id + "\" (" + n.stage + "): ";
}

void Pipeline::apply_override(const std::string& assignment) {
    const auto eq = assignment.find('=');
    const auto dot = assignment.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
        throw Error("--set \"" + assignment + "\": expected NODE.PARAM=VALUE");
    const std::string id = assignment.substr(0, dot), param = assignment.substr(dot + 1, eq - dot - 1),
                      value = assignment.substr(eq + 1);
    for (auto& n : nodes) {
        if (n.id != id) continue;
        RawParam raw;
        raw.text = value;
        n.raw_params[param] = raw;
        return;
    }
    std::string known;
    for (auto& n : nodes) known += (known.empty() ? "" : ", ") + n.id;
    throw Error("--set \"" + assignment + "\": " + file.string() + " has no node \"" + id + "\" (nodes: " + known + ")");
}

ParamValue param_value(const ParamSpec& spec, const RawParam& raw) {
    if (raw.from_set()) return parse_param_text(spec, raw.text);
    const YAML::Node& n = raw.node;
    const std::string kind = n.IsScalar() ? (n.Tag() == "!" ? "quoted" : "scalar")
                             : n.IsSequence() ? "list" : n.IsMap() ? "mapping" : "null value";
    return parse_param_yaml(spec, n.IsScalar() ? n.Scalar() : std::string(), kind);
}

ParamSet resolve_params(const StageInfo& info, const std::map<std::string, RawParam>& raw_params,
                        const std::function<std::string(int)>& where) {
    ParamSet ps;
    for (const auto& [key, raw] : raw_params) {
        const ParamSpec* spec = find_param(info.params, key);
        const std::string src = raw.from_set() ? " (from --set)" : "";
        if (!spec)
            throw Error(where(raw.line) + "unknown parameter \"" + key + "\"" + src + " (parameters: " +
                        param_names(info.params) + ")");
        if (spec->is_optional && !raw.from_set() && raw.node.IsNull()) continue;   // null: left unset
        ParamValue v;
        try {
            v = param_value(*spec, raw);
        } catch (const Error& e) {
            throw Error(where(raw.line) + e.what() + src);
        }
        if (auto why = check_param(*spec, v); !why.empty()) throw Error(where(raw.line) + why + src);
        ps.set(key, v);
        ps.mark_explicit(key);
    }
    if (auto missing = fill_defaults(info.params, ps); !missing.empty()) throw Error(where(0) + missing);
    return ps;
}

void Pipeline::validate(const Registry& registry) {
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < nodes.size(); ++i) index[nodes[i].id] = i;

    for (auto& n : nodes) {
        const StageEntry* entry = registry.find(n.stage);
        if (!entry) {
            std::string known;
            for (const auto& s : registry.names()) known += (known.empty() ? "" : ", ") + s;
            throw Error(where(n) + "unknown stage \"" + n.stage + "\" (known stages: " +
                        (known.empty() ? "none; no plugin was found" : known) + ")");
        }
        std::unique_ptr<Stage> stage;
        try {
            stage = registry.create(n.stage);
        } catch (const Error& e) {
            throw Error(where(n) + e.what());
        }
        n.info = stage->info();
        n.params = resolve_params(n.info, n.raw_params, [&](int line) { return where(n, line); });

        // Ports: every connection names a declared port, a known node and the right kind.
        for (const auto& [port, src] : n.inputs) {
            const int line = n.input_lines[port];
            const PortSpec* ps_ = nullptr;
            for (const auto& pspec : n.info.inputs)
                if (pspec.name == port) ps_ = &pspec;
            if (!ps_) {
                std::string known;
                for (const auto& pspec : n.info.inputs) known += (known.empty() ? "" : ", ") + pspec.name;
                throw Error(where(n, line) + "unknown input port \"" + port + "\" (ports: " + (known.empty() ? "none" : known) + ")");
            }
            if (!index.count(src)) throw Error(where(n, line) + "input \"" + port + "\" names unknown node \"" + src + "\"");
        }
        for (const auto& pspec : n.info.inputs)
            if (!pspec.optional && !n.inputs.count(pspec.name))
                throw Error(where(n) + "missing input \"" + pspec.name + "\" (" + to_string(pspec.kind) + ": " + pspec.doc + ")");
    }
    // Kinds need every node's info, so check them once all are known.
    for (auto& n : nodes) {
        for (const auto& [port, src] : n.inputs) {
            const PipelineNode& from = nodes[index[src]];
            for (const auto& pspec : n.info.inputs) {
                if (pspec.name == port && pspec.kind != from.info.output)
                    throw Error(where(n, n.input_lines[port]) + "input \"" + port + "\" needs " + to_string(pspec.kind) +
                                " but node \"" + src + "\" (" + from.stage + ") gives " + to_string(from.info.output));
            }
        }
    }
    // Topological order (Kahn); what remains is on a cycle.
    std::vector<int> indeg(nodes.size(), 0);
    std::vector<std::vector<std::size_t>> out(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
        for (const auto& [port, src] : nodes[i].inputs) { out[index[src]].push_back(i); ++indeg[i]; }
    order.clear();
    std::vector<std::size_t> ready;
    for (std::size_t i = 0; i < nodes.size(); ++i)
        if (indeg[i] == 0) ready.push_back(i);
    while (!ready.empty()) {
        std::size_t i = ready.front();
        ready.erase(ready.begin());
        order.push_back(i);
        for (auto j : out[i])
            if (--indeg[j] == 0) ready.push_back(j);
    }
    if (order.size() != nodes.size()) {
        // Walk back along inputs from a node left over to print the cycle itself.
        std::size_t start = 0;
        while (indeg[start] == 0) ++start;
        std::vector<std::size_t> path;
        std::vector<int> seen(nodes.size(), -1);
        std::size_t cur = start;
        while (seen[cur] < 0) {
            seen[cur] = int(path.size());
            path.push_back(cur);
            for (const auto& [port, src] : nodes[cur].inputs)
                if (indeg[index[src]] > 0) { cur = index[src]; break; }
        }
        // path follows inputs backwards; print the cycle in data-flow order.
        std::string cyc;
        for (std::size_t k = path.size(); k-- > std::size_t(seen[cur]);) cyc += nodes[path[k]].id + " -> ";
        cyc += nodes[path.back()].id;
        throw Error(where(nodes[cur]) + "the graph has a cycle: " + cyc);
    }
}

std::string stage_schema_json(const StageInfo& info) {
    json props = json::object();
    json required = json::array();
    for (const auto& p : info.params) {
        props[p.name] = param_schema(p);
        if (!p.default_value && !p.is_optional) required.push_back(p.name);
    }
    json inputs = json::object();
    for (const auto& port : info.inputs)
        inputs[port.name] = {{"kind", to_string(port.kind)}, {"description", port.doc}, {"optional", port.optional}};
    json j = {{"$schema", "http://json-schema.org/draft-07/schema#"},
              {"$id", "https://conceptmesh.dev/schemas/stages/" + info.name + ".schema.json"},
              {"title", info.name + " parameters"},
              {"description", info.summary},
              {"type", "object"},
              {"additionalProperties", false},
              {"properties", props},
              {"x-inputs", inputs},
              {"x-output", to_string(info.output)}};
    if (!required.empty()) j["required"] = required;
    return j.dump(2) + "\n";
}

std::string pipeline_schema_json(const Registry& registry) {
    json j = pipeline_structure(registry.names());
    // Per-stage parameter completion for editors (yaml-language-server resolves the relative refs).
    json all = json::array();
    for (const auto& name : registry.names())
        all.push_back({{"if", {{"properties", {{"stage", {{"const", name}}}}}}},
                       {"then", {{"properties", {{"params", {{"$ref", "stages/" + name + ".schema.json"}}}}}}}});
    j["definitions"]["node"]["allOf"] = all;
    return j.dump(2) + "\n";
}

} // namespace cm
