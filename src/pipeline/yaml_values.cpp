#include "pipeline/yaml_values.h"

namespace cm {

RawParam raw_param(const YAML::Node& n) {
    RawParam raw;
    raw.kind = n.IsScalar()     ? (n.Tag() == "!" ? "quoted" : "scalar")
               : n.IsSequence() ? "list"
               : n.IsMap()      ? "mapping"
                                : "null value";
    raw.line = yaml_line(n);
    if (n.IsScalar()) raw.text = n.Scalar();
    return raw;
}

nlohmann::json yaml_to_json(const YAML::Node& n) {
    switch (n.Type()) {
    case YAML::NodeType::Map: {
        nlohmann::json j = nlohmann::json::object();
        for (auto it = n.begin(); it != n.end(); ++it) j[it->first.Scalar()] = yaml_to_json(it->second);
        return j;
    }
    case YAML::NodeType::Sequence: {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& x : n) j.push_back(yaml_to_json(x));
        return j;
    }
    case YAML::NodeType::Scalar: {
        if (n.Tag() == "!") return n.Scalar(); // quoted: always a string
        const std::string& s = n.Scalar();
        if (s == "true" || s == "false") return s == "true";
        try {
            std::size_t pos = 0;
            long long i = std::stoll(s, &pos);
            if (pos == s.size()) return i;
            double d = std::stod(s, &pos);
            if (pos == s.size()) return d;
        } catch (...) {}
        return s;
    }
    default: return nullptr;
    }
}

} // namespace cm
