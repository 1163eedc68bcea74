#include "core/params.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/data.h"
#include "core/error.h"

namespace cm {

const char* to_string(ParamType t) {
    switch (t) {
    case ParamType::Bool: return "bool";
    case ParamType::Int: return "int";
    case ParamType::Float: return "float";
    case ParamType::String: return "string";
    case ParamType::Path: return "path";
    case ParamType::Enum: return "enum";
    }
    return "?";
}

ParamSpec ParamSpec::Bool(std::string name, bool def, std::string doc) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = ParamType::Bool;
    s.default_value = def;
    s.doc = std::move(doc);
    return s;
}
namespace {
// Int and Float: a number with a range and a unit.
ParamSpec number(std::string name, ParamType type, ParamValue def, double lo, double hi, std::string unit,
                 std::string doc) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = type;
    s.default_value = std::move(def);
    s.min = lo;
    s.max = hi;
    s.unit = std::move(unit);
    s.doc = std::move(doc);
    return s;
}
} // namespace

ParamSpec ParamSpec::Int(std::string name, std::int64_t def, double lo, double hi, std::string unit, std::string doc) {
    return number(std::move(name), ParamType::Int, def, lo, hi, std::move(unit), std::move(doc));
}
ParamSpec ParamSpec::Float(std::string name, double def, double lo, double hi, std::string unit, std::string doc) {
    return number(std::move(name), ParamType::Float, def, lo, hi, std::move(unit), std::move(doc));
}
ParamSpec ParamSpec::String(std::string name, std::optional<std::string> def, std::string doc) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = ParamType::String;
    if (def) s.default_value = *def;
    s.doc = std::move(doc);
    return s;
}
ParamSpec ParamSpec::Path(std::string name, std::optional<std::string> def, std::string doc) {
    ParamSpec s = String(std::move(name), std::move(def), std::move(doc));
    s.type = ParamType::Path;
    return s;
}
ParamSpec ParamSpec::Enum(std::string name, std::string def, std::vector<std::string> choices, std::string doc) {
    ParamSpec s;
    s.name = std::move(name);
    s.type = ParamType::Enum;
    s.default_value = std::move(def);
    s.choices = std::move(choices);
    s.doc = std::move(doc);
    return s;
}
ParamSpec ParamSpec::OutputPath(std::string name, std::vector<std::string> extensions, std::string doc) {
    ParamSpec s = Path(std::move(name), std::nullopt, std::move(doc));
    s.is_output = true;
    s.extensions = std::move(extensions);
    return s;
}
ParamSpec& ParamSpec::optional() {
    default_value.reset();
    is_optional = true;
    return *this;
}

std::string format_value(const ParamValue& v) {
    std::ostringstream os;
    std::visit(
        [&](const auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, bool>) os << (x ? "true" : "false");
            else if constexpr (std::is_same_v<T, std::string>) os << '"' << x << '"';
            else os << x;
        },
        v);
    return os.str();
}

namespace {
const ParamValue& lookup(const std::map<std::string, ParamValue>& m, const std::string& name) {
    auto it = m.find(name);
    if (it == m.end()) throw Error("parameter \"" + name + "\" is not set");
    return it->second;
}

bool parse_bool(const std::string& t, bool& out) {
    if (t == "true" || t == "True" || t == "TRUE" || t == "yes" || t == "on" || t == "1") {
        out = true;
        return true;
    }
    if (t == "false" || t == "False" || t == "FALSE" || t == "no" || t == "off" || t == "0") {
        out = false;
        return true;
    }
    return false;
}
} // namespace

std::string type_phrase(const ParamSpec& s) {
    switch (s.type) {
    case ParamType::Bool: return "a boolean (true or false)";
    case ParamType::Int: return "an integer";
    case ParamType::Float: return "a number";
    case ParamType::String: return "a string";
    case ParamType::Path: return "a file path";
    case ParamType::Enum: {
        std::string c;
        for (auto& x : s.choices) c += (c.empty() ? "" : ", ") + x;
        return "one of " + c;
    }
    }
    return "?";
}

bool ParamSet::get_bool(const std::string& name) const { return std::get<bool>(lookup(values_, name)); }
std::int64_t ParamSet::get_int(const std::string& name) const { return std::get<std::int64_t>(lookup(values_, name)); }
double ParamSet::get_float(const std::string& name) const {
    const auto& v = lookup(values_, name);
    if (auto* i = std::get_if<std::int64_t>(&v)) return double(*i);
    return std::get<double>(v);
}
const std::string& ParamSet::get_string(const std::string& name) const {
    return std::get<std::string>(lookup(values_, name));
}

ParamValue parse_param_text(const ParamSpec& spec, const std::string& text) {
    auto bad = [&]() -> Error { return Error(spec.name + " must be " + type_phrase(spec) + ", got \"" + text + "\""); };
    switch (spec.type) {
    case ParamType::Bool: {
        bool b;
        if (!parse_bool(text, b)) throw bad();
        return b;
    }
    case ParamType::Int: {
        std::size_t pos = 0;
        long long v = 0;
        try {
            v = std::stoll(text, &pos);
        } catch (...) {
            throw bad();
        }
        if (pos != text.size()) throw bad();
        return std::int64_t(v);
    }
    case ParamType::Float: {
        std::size_t pos = 0;
        double v = 0;
        try {
            v = std::stod(text, &pos);
        } catch (...) {
            throw bad();
        }
        if (pos != text.size() || !std::isfinite(v)) throw bad();
        return v;
    }
    case ParamType::String:
    case ParamType::Path:
    case ParamType::Enum: return text;
    }
    throw bad();
}

ParamValue parse_param_yaml(const ParamSpec& spec, const std::string& text, const std::string& kind) {
    if (kind != "scalar" && kind != "quoted") {
        if (kind == "null value" && spec.is_optional) return std::string();
        throw Error(spec.name + " must be " + type_phrase(spec) + ", got a " + kind);
    }
    // A quoted YAML string is never a number or a boolean.
    if (kind == "quoted" &&
        (spec.type == ParamType::Int || spec.type == ParamType::Float || spec.type == ParamType::Bool))
        throw Error(spec.name + " must be " + type_phrase(spec) + ", got the string \"" + text + "\"");
    return parse_param_text(spec, text);
}

namespace {
bool holds_declared_type(const ParamSpec& spec, const ParamValue& v) {
    switch (spec.type) {
    case ParamType::Bool: return std::holds_alternative<bool>(v);
    case ParamType::Int: return std::holds_alternative<std::int64_t>(v);
    case ParamType::Float: return std::holds_alternative<double>(v) || std::holds_alternative<std::int64_t>(v);
    case ParamType::String:
    case ParamType::Path:
    case ParamType::Enum: return std::holds_alternative<std::string>(v);
    }
    return false;
}
} // namespace

std::string check_param(const ParamSpec& spec, const ParamValue& v) {
    if (!holds_declared_type(spec, v)) return spec.name + " must be " + type_phrase(spec) + ", got " + format_value(v);
    if (spec.type == ParamType::Int || spec.type == ParamType::Float) {
        double x = std::holds_alternative<std::int64_t>(v) ? double(std::get<std::int64_t>(v)) : std::get<double>(v);
        if ((spec.min && x < *spec.min) || (spec.max && x > *spec.max)) {
            std::ostringstream os;
            os << spec.name << " must be in [" << (spec.min ? *spec.min : -INFINITY) << ", "
               << (spec.max ? *spec.max : INFINITY) << "]";
            if (!spec.unit.empty()) os << " " << spec.unit;
            os << ", got " << format_value(v);
            return os.str();
        }
    }
    if (spec.type == ParamType::Enum) {
        const auto& s = std::get<std::string>(v);
        for (auto& c : spec.choices)
            if (c == s) return {};
        return spec.name + " must be " + type_phrase(spec) + ", got \"" + s + "\"";
    }
    if ((spec.type == ParamType::Path || spec.type == ParamType::String) && !spec.is_optional &&
        std::get<std::string>(v).empty() && !spec.default_value)
        return spec.name + " must not be empty";
    return {};
}

const ParamSpec* find_param(const std::vector<ParamSpec>& specs, const std::string& name) {
    for (const auto& s : specs)
        if (s.name == name) return &s;
    return nullptr;
}

std::string param_names(const std::vector<ParamSpec>& specs) {
    std::string known;
    for (const auto& s : specs) known += (known.empty() ? "" : ", ") + s.name;
    return known.empty() ? "none" : known;
}

std::string check_output_path(const ParamSpec& spec, const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    const std::string what = spec.name + " \"" + path.string() + "\"";
    const std::string ext = lower_extension(path);
    bool known = false;
    for (const auto& e : spec.extensions) known = known || e == ext;
    if (!known && spec.extensions.size() == 1) return what + " must end in " + spec.extensions[0];
    if (!known) {
        std::string list;
        for (std::size_t i = 0; i < spec.extensions.size(); ++i)
            list += (i == 0 ? "" : i + 1 == spec.extensions.size() ? " or " : ", ") + spec.extensions[i];
        return what + " has an unknown extension (use " + list + ")";
    }
    if (fs::is_directory(path)) return what + " is a folder; name the file to write";
    // A missing folder is created when the run writes; refuse only what cannot become one.
    for (auto dir = fs::absolute(path).parent_path(); !dir.empty(); dir = dir.parent_path()) {
        if (fs::is_directory(dir)) break;
        if (fs::exists(dir)) return what + ": \"" + dir.string() + "\" is not a folder";
        if (dir == dir.parent_path()) break;
    }
    return {};
}

std::string fill_defaults(const std::vector<ParamSpec>& specs, ParamSet& ps) {
    for (const auto& s : specs) {
        if (ps.has(s.name)) continue;
        if (s.default_value) ps.set(s.name, *s.default_value);
        else if (!s.is_optional) return "parameter \"" + s.name + "\" is required: " + s.doc;
    }
    return {};
}

nlohmann::json param_to_json(const ParamValue& v) {
    return std::visit([](const auto& x) { return nlohmann::json(x); }, v);
}

nlohmann::json param_schema(const ParamSpec& spec) {
    nlohmann::json j;
    switch (spec.type) {
    case ParamType::Bool: j["type"] = "boolean"; break;
    case ParamType::Int: j["type"] = "integer"; break;
    case ParamType::Float: j["type"] = "number"; break;
    case ParamType::String: j["type"] = "string"; break;
    case ParamType::Path:
        j["type"] = "string";
        j["format"] = "path";
        break;
    case ParamType::Enum:
        j["type"] = "string";
        j["enum"] = spec.choices;
        break;
    }
    std::string doc = spec.doc;
    if (!spec.unit.empty()) doc += " [" + spec.unit + "]";
    j["description"] = doc;
    auto num = [&](double x) {
        return spec.type == ParamType::Int ? nlohmann::json(std::int64_t(x)) : nlohmann::json(x);
    };
    if (spec.min) j["minimum"] = num(*spec.min);
    if (spec.max) j["maximum"] = num(*spec.max);
    if (spec.default_value) j["default"] = param_to_json(*spec.default_value);
    if (!spec.unit.empty()) j["x-unit"] = spec.unit;
    return j;
}

void ParamBinder::require(bool ok, const ParamSpec& spec, const std::string& what) {
    if (!ok)
        throw std::logic_error("parameter \"" + spec.name + "\" (" + to_string(spec.type) +
                               ") must be bound to a member that fits " + what);
}

void ParamBinder::add_binding(ParamSpec spec, Setter set) {
    for (const auto& b : bindings_)
        if (b.spec.name == spec.name) throw std::logic_error("parameter \"" + spec.name + "\" is declared twice");
    bindings_.push_back({std::move(spec), std::move(set)});
}

std::vector<ParamSpec> ParamBinder::specs() const {
    std::vector<ParamSpec> out;
    out.reserve(bindings_.size());
    for (const auto& b : bindings_) out.push_back(b.spec);
    return out;
}

void ParamBinder::assign(const ParamSet& values) const {
    for (const auto& b : bindings_) {
        const auto it = values.values().find(b.spec.name);
        const ParamValue* v = it == values.values().end() ? nullptr : &it->second;
        if (!v && !b.spec.is_optional) throw Error("parameter \"" + b.spec.name + "\" is not set");
        b.set(v, values.explicitly_set(b.spec.name));
    }
}

void ParamBinder::assign_defaults() const {
    for (const auto& b : bindings_) {
        if (b.spec.default_value) b.set(&*b.spec.default_value, false);
        else if (b.spec.is_optional) b.set(nullptr, false);
    }
}

} // namespace cm
