// The JSON Schemas generated from the declarations: the pipeline file's structure (also
// what parse checks a file against) and each stage's parameters.
#include <nlohmann/json.hpp>

#include "pipeline/pipeline.h"

using nlohmann::json;

namespace cm {

json pipeline_structure_schema(const std::vector<std::string>& stage_names) {
    json node = {
        {"type", "object"},
        {"description", "One step of the pipeline: a stage, its inputs and its parameters."},
        {"required", {"id", "stage"}},
        {"additionalProperties", false},
        {"properties",
         {{"id",
           {{"type", "string"},
            {"pattern", "^[A-Za-z_][A-Za-z0-9_-]*$"},
            {"description", "Unique name of the node; used by inputs and by --set NODE.PARAM=VALUE."}}},
          {"stage",
           {{"type", "string"},
            {"description", "The stage this node runs (conceptmesh stages lists them)."},
            {"examples", stage_names}}},
          {"inputs",
           {{"type", "object"},
            {"description", "Input port -> id of the node that feeds it."},
            {"additionalProperties", {{"type", "string"}}}}},
          {"params",
           {{"type", "object"}, {"description", "The stage's parameters (conceptmesh stages --describe STAGE)."}}}}}};
    return {{"$schema", "http://json-schema.org/draft-07/schema#"},
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
    json j = pipeline_structure_schema(registry.names());
    // Per-stage parameter completion for editors (yaml-language-server resolves the relative refs).
    json all = json::array();
    for (const auto& name : registry.names())
        all.push_back({{"if", {{"properties", {{"stage", {{"const", name}}}}}}},
                       {"then", {{"properties", {{"params", {{"$ref", "stages/" + name + ".schema.json"}}}}}}}});
    j["definitions"]["node"]["allOf"] = all;
    return j.dump(2) + "\n";
}

} // namespace cm
