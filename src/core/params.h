// Declared stage parameters: one declaration drives YAML parsing, --set,
// `conceptmesh stages --describe`, and the generated JSON Schema.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace cm {

enum class ParamType { Bool, Int, Float, String, Path, Enum };
const char* to_string(ParamType t);

using ParamValue = std::variant<bool, std::int64_t, double, std::string>;

struct ParamSpec {
    std::string name;
    ParamType type = ParamType::Float;
    std::optional<ParamValue> default_value;   ///< empty: the parameter is required
    std::optional<double> min;                 ///< inclusive, numbers only
    std::optional<double> max;                 ///< inclusive, numbers only
    std::string unit;                          ///< "voxels", "px", "deg", ... or empty
    std::string doc;                           ///< one line
    std::vector<std::string> choices;          ///< Enum only

    // Fluent builders so a stage reads like a table.
    static ParamSpec Bool(std::string name, bool def, std::string doc);
    static ParamSpec Int(std::string name, std::int64_t def, double lo, double hi, std::string unit,
                         std::string doc);
    static ParamSpec Float(std::string name, double def, double lo, double hi, std::string unit,
                           std::string doc);
    static ParamSpec String(std::string name, std::optional<std::string> def, std::string doc);
    static ParamSpec Path(std::string name, std::optional<std::string> def, std::string doc);
    static ParamSpec Enum(std::string name, std::string def, std::vector<std::string> choices,
                          std::string doc);
    /// A file the run writes (required, a Path to the schema): configure() refuses it unless
    /// check_output_path() passes, and Context::output_file() makes its missing folders.
    static ParamSpec OutputPath(std::string name, std::vector<std::string> extensions, std::string doc);
    ParamSpec& optional();   ///< no default, may be left unset
    bool is_optional = false;
    bool is_output = false;                    ///< OutputPath
    std::vector<std::string> extensions;       ///< OutputPath: the accepted ones (".obj"), in lower case
};

std::string format_value(const ParamValue& v);
/// What a value of `spec` must be, for messages: "a number", "one of auto, on, off".
std::string type_phrase(const ParamSpec& spec);

/// Checked, typed parameter values of one node (defaults filled in).
class ParamSet {
public:
    bool has(const std::string& name) const { return values_.count(name) != 0; }
    bool get_bool(const std::string& name) const;
    std::int64_t get_int(const std::string& name) const;
    double get_float(const std::string& name) const;        ///< accepts Int values too
    const std::string& get_string(const std::string& name) const;  ///< String, Path, Enum
    const std::map<std::string, ParamValue>& values() const { return values_; }
    void set(const std::string& name, ParamValue v) { values_[name] = std::move(v); }
    /// Which values the user wrote (the rest are defaults).
    bool explicitly_set(const std::string& name) const { return explicit_.count(name) != 0; }
    void mark_explicit(const std::string& name) { explicit_[name] = true; }

private:
    std::map<std::string, ParamValue> values_;
    std::map<std::string, bool> explicit_;
};

/// Converts text (from --set) to a value of the declared type; throws cm::Error
/// with a message of the form "<what> must be ..., got ...".
ParamValue parse_param_text(const ParamSpec& spec, const std::string& text);
/// Converts a value written in YAML to the declared type. `kind` is how it was
/// written: "scalar" (plain), "quoted", "list", "mapping" or "null value".
ParamValue parse_param_yaml(const ParamSpec& spec, const std::string& text, const std::string& kind);
/// Type, range and choice checks; returns an empty string when valid, else the reason.
std::string check_param(const ParamSpec& spec, const ParamValue& v);
/// The declaration named `name` in `specs`, or null.
const ParamSpec* find_param(const std::vector<ParamSpec>& specs, const std::string& name);
/// "a, b, c" (or "none"): the declared names, for messages about an unknown one.
std::string param_names(const std::vector<ParamSpec>& specs);
/// The rule of an OutputPath: the extension is one of `spec.extensions` in any case, and
/// every folder on the way exists or can be made when the run writes. Returns the reason
/// (`path "x.abc" has an unknown extension (use .obj, .ply or .glb)`, `path "x.jpg" must
/// end in .png`, `path "a/b.png": "/.../a" is not a folder`), else an empty string.
std::string check_output_path(const ParamSpec& spec, const std::filesystem::path& path);
/// Sets every declared default that `ps` lacks. Returns the reason when a required
/// parameter is missing ("parameter "x" is required: <doc>"), else an empty string.
std::string fill_defaults(const std::vector<ParamSpec>& specs, ParamSet& ps);

/// JSON Schema (draft-07) fragment for one parameter.
nlohmann::json param_schema(const ParamSpec& spec);
nlohmann::json param_to_json(const ParamValue& v);

} // namespace cm
