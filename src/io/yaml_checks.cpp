#include "io/yaml_checks.h"

#include <map>
#include <string>

#include "core/error.h"

namespace cm {

namespace {

struct Walk {
    const std::filesystem::path& file;
    std::size_t max_nodes;
    std::size_t seen = 0;

    std::string at(const YAML::Node& n) const {
        return file.string() + (n.Mark().line >= 0 ? ":" + std::to_string(n.Mark().line + 1) : "");
    }

    void visit(const YAML::Node& n) {
        if (++seen > max_nodes)
            throw Error(at(n) + ": the document holds more than " + std::to_string(max_nodes) +
                        " values once its aliases (*name) are expanded; refused");
        if (n.IsSequence()) {
            for (const auto& x : n) visit(x);
        } else if (n.IsMap()) {
            std::map<std::string, int> lines;
            for (auto it = n.begin(); it != n.end(); ++it) {
                // Copies: it-> gives a temporary, and a reference into it dangles.
                const YAML::Node key = it->first, value = it->second;
                if (key.IsScalar()) {
                    const auto [first, fresh] = lines.emplace(key.Scalar(), key.Mark().line + 1);
                    if (!fresh)
                        throw Error(at(key) + ": \"" + key.Scalar() +
                                    "\" is given twice in one mapping (first on line " + std::to_string(first->second) +
                                    "); keep one");
                }
                visit(value);
            }
        }
    }
};

} // namespace

void check_yaml_document(const YAML::Node& doc, const std::filesystem::path& file, std::size_t max_nodes) {
    Walk{file, max_nodes}.visit(doc);
}

} // namespace cm
