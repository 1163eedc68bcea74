// What yaml-cpp accepts silently and a user must hear about: a key given twice in one
// mapping (one of the two values would be dropped without a word), and aliases that
// expand a small file into a huge document.
#pragma once
#include <cstddef>
#include <filesystem>

#include <yaml-cpp/yaml.h>

namespace cm {

/// The most nodes a pipeline or manifest may hold once its aliases are expanded.
constexpr std::size_t kMaxYamlNodes = 200'000;

/// @brief Walks `doc`; throws cm::Error "file:line: ..." for a key given twice in one
/// mapping (naming the line of the first) or for a document of more than `max_nodes`
/// nodes with its aliases expanded. Stops as soon as the limit is passed, so an
/// alias bomb costs no more than the limit.
void check_yaml_document(const YAML::Node& doc, const std::filesystem::path& file,
                         std::size_t max_nodes = kMaxYamlNodes);

} // namespace cm
