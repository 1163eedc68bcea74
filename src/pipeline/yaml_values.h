// YAML values of pipeline files and stage parameters, for the pipeline layer's own files
// (yaml-cpp stays private to the layer: pipeline.h holds RawParam, not YAML nodes).
#pragma once
#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "pipeline/pipeline.h"

namespace cm {

/// The 1-based line of a node in its file (0 when not known).
inline int yaml_line(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

/// A parameter value as written: its kind, its scalar text and its line.
RawParam raw_param(const YAML::Node& n);

/// A YAML document as JSON, for validating it against a JSON Schema (valijson's yaml-cpp
/// adapter does not compile with every constraint): plain scalars become numbers or
/// booleans when they read as one; quoted scalars stay strings.
nlohmann::json yaml_to_json(const YAML::Node& n);

} // namespace cm
