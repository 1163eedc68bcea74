// Reading a pipeline file: YAML -> Pipeline, checked against the structure schema
// (pipeline_structure_schema()), and the --set overrides.
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include "core/error.h"
#include "io/yaml_checks.h"
#include "pipeline/pipeline.h"
#include "pipeline/yaml_values.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm {

namespace {

std::string file_line(const fs::path& file, int line) {
    std::string s = file.string();
    if (line > 0) s += ":" + std::to_string(line);
    return s;
}

// Follows a valijson context path ("<root>", "[nodes]", "[0]", ...) into the YAML document.
YAML::Node follow(const YAML::Node& root, const std::vector<std::string>& ctx) {
    YAML::Node cur = root;
    for (const auto& c : ctx) {
        if (c == "<root>" || c.size() < 3 || c.front() != '[') continue;
        const std::string key = c.substr(1, c.size() - 2);
        YAML::Node next(YAML::NodeType::Undefined);
        if (cur.IsSequence()) {
            try {
                next.reset(cur[std::stoul(key)]);
            } catch (...) {
                break;
            }
        } else if (cur.IsMap()) {
            for (auto it = cur.begin(); it != cur.end(); ++it)
                if (it->first.Scalar() == key) {
                    next.reset(it->second);
                    break;
                }
        }
        if (!next.IsDefined()) break;
        cur.reset(next); // operator= would assign into the document
    }
    return cur;
}

void validate_structure(const YAML::Node& doc, const fs::path& file) {
    static const json schema_doc = pipeline_structure_schema({});
    static const std::unique_ptr<valijson::Schema> schema = [] {
        auto s = std::make_unique<valijson::Schema>();
        valijson::SchemaParser parser;
        valijson::adapters::NlohmannJsonAdapter a(schema_doc);
        parser.populateSchema(a, *s);
        return s;
    }();
    valijson::Validator validator;
    valijson::ValidationResults results;
    const json as_json = yaml_to_json(doc);
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
    throw Error(file_line(file, yaml_line(at)) + ": " + node_part + "does not match the pipeline schema at " +
                (path.empty() ? "the top level" : path) + ": " + best.description);
}

/// One entry of the `nodes` list (the structure schema has checked its shape).
PipelineNode parse_node(const YAML::Node& n) {
    PipelineNode node;
    node.id = n["id"].Scalar();
    node.stage = n["stage"].Scalar();
    node.line = yaml_line(n);
    if (n["inputs"]) {
        for (auto it = n["inputs"].begin(); it != n["inputs"].end(); ++it) {
            node.inputs[it->first.Scalar()] = it->second.Scalar();
            node.input_lines[it->first.Scalar()] = yaml_line(it->second);
        }
    }
    if (n["params"]) {
        for (auto it = n["params"].begin(); it != n["params"].end(); ++it) {
            node.raw_params[it->first.Scalar()] = raw_param(it->second);
        }
    }
    return node;
}

} // namespace

Pipeline Pipeline::load(const fs::path& file) {
    std::error_code ec;
    if (fs::is_directory(file, ec)) throw Error("cannot open pipeline \"" + file.string() + "\": it is a folder");
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
    check_yaml_document(doc, file);
    validate_structure(doc, file);

    Pipeline p;
    p.file = file;
    if (doc["pipeline"]) p.name = doc["pipeline"].Scalar();
    if (doc["description"]) p.description = doc["description"].Scalar();
    std::set<std::string> ids;
    for (const auto& n : doc["nodes"]) {
        PipelineNode node = parse_node(n);
        if (!ids.insert(node.id).second)
            throw Error(file_line(file, node.line) + ": node \"" + node.id + "\" (" + node.stage +
                        "): the id is used by another node already");
        p.nodes.push_back(std::move(node));
    }
    return p;
}

std::string Pipeline::where(const PipelineNode& n, int line) const {
    return file_line(file, line ? line : n.line) + ": node \"" + n.id + "\" (" + n.stage + "): ";
}

void Pipeline::apply_override(const std::string& assignment, const std::string& source) {
    const auto eq = assignment.find('=');
    const auto dot = assignment.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
        throw UsageError(source + " \"" + assignment + "\": expected NODE.PARAM=VALUE");
    const std::string id = assignment.substr(0, dot), param = assignment.substr(dot + 1, eq - dot - 1),
                      value = assignment.substr(eq + 1);
    for (auto& n : nodes) {
        if (n.id != id) continue;
        RawParam raw;
        raw.text = value;
        raw.source = source;
        n.raw_params[param] = raw;
        validated = false;
        return;
    }
    std::string known;
    for (auto& n : nodes) known += (known.empty() ? "" : ", ") + n.id;
    throw UsageError(source + " \"" + assignment + "\": " + file.string() + " has no node \"" + id +
                     "\" (nodes: " + known + ")");
}

std::map<std::string, std::size_t> Pipeline::node_index() const {
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < nodes.size(); ++i) index[nodes[i].id] = i;
    return index;
}

} // namespace cm
