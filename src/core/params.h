// Declared stage parameters: one declaration drives YAML parsing, --set,
// `conceptmesh stages --describe`, and the generated JSON Schema.
#pragma once
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
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
    std::optional<ParamValue> default_value; ///< empty: the parameter is required
    std::optional<double> min;               ///< inclusive, numbers only
    std::optional<double> max;               ///< inclusive, numbers only
    std::string unit;                        ///< "voxels", "px", "deg", ... or empty
    std::string doc;                         ///< one line
    std::vector<std::string> choices;        ///< Enum only

    // Fluent builders so a stage reads like a table.
    static ParamSpec Bool(std::string name, bool def, std::string doc);
    static ParamSpec Int(std::string name, std::int64_t def, double lo, double hi, std::string unit, std::string doc);
    static ParamSpec Float(std::string name, double def, double lo, double hi, std::string unit, std::string doc);
    static ParamSpec String(std::string name, std::optional<std::string> def, std::string doc);
    static ParamSpec Path(std::string name, std::optional<std::string> def, std::string doc);
    static ParamSpec Enum(std::string name, std::string def, std::vector<std::string> choices, std::string doc);
    /// A file the run writes (required, a Path to the schema): configure() refuses it unless
    /// check_output_path() passes, and Context::output_file() makes its missing folders.
    static ParamSpec OutputPath(std::string name, std::vector<std::string> extensions, std::string doc);
    ParamSpec& optional(); ///< no default, may be left unset
    bool is_optional = false;
    bool is_output = false;              ///< OutputPath
    std::vector<std::string> extensions; ///< OutputPath: the accepted ones (".obj"), in lower case
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
    double get_float(const std::string& name) const;              ///< accepts Int values too
    const std::string& get_string(const std::string& name) const; ///< String, Path, Enum
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

// ---- Binding declared parameters to a stage's members ----------------------------
// Declaring a stage's parameters and binding each to the member that holds its value,
// in one place. A stage's declare() adds each parameter once:
//
//     b.add(opt_.max_angle_deg, ParamSpec::Float("max_angle_deg", 15.0, 0.1, 89.0, "deg", "..."));
//
// info() collects the declarations from it; configure() sets every bound member from
// the checked value, typed, before the stage's check() and run() see it.

/// A bound value and whether the user gave it (rather than it being the declared default),
/// for stages whose behaviour depends on which of two parameters was written.
template <typename T>
struct Param {
    T value{};
    bool given = false;
    operator const T&() const { return value; }
};

namespace param_binding {

template <typename T>
struct Member { // the member's own value type, and how it is wrapped
    using type = T;
    static constexpr bool optional = false;
    static constexpr bool tracks_given = false;
};
template <typename T>
struct Member<std::optional<T>> : Member<T> {
    static constexpr bool optional = true;
};
template <typename T>
struct Member<Param<T>> : Member<T> {
    static constexpr bool tracks_given = true;
};

/// Whether a member of type T can hold values of the declared type.
template <typename T>
constexpr bool holds(ParamType t) {
    if constexpr (std::is_same_v<T, bool>) return t == ParamType::Bool;
    else if constexpr (std::is_integral_v<T>) return t == ParamType::Int;
    else if constexpr (std::is_floating_point_v<T>) return t == ParamType::Float;
    else if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::filesystem::path>)
        return t == ParamType::String || t == ParamType::Path || t == ParamType::Enum;
    else static_assert(sizeof(T) == 0, "a parameter binds to bool, an integer, float/double, std::string or a path");
}

/// The value converted to the member's type (the declared type matches: holds()).
template <typename T>
T convert(const ParamValue& v) {
    if constexpr (std::is_same_v<T, bool>) return std::get<bool>(v);
    else if constexpr (std::is_integral_v<T>) return static_cast<T>(std::get<std::int64_t>(v));
    else if constexpr (std::is_floating_point_v<T>)
        return static_cast<T>(std::holds_alternative<std::int64_t>(v) ? double(std::get<std::int64_t>(v))
                                                                      : std::get<double>(v));
    else return T(std::get<std::string>(v));
}

template <typename M>
void store(M& member, const ParamValue* v, bool given) {
    using Traits = Member<M>;
    using T = typename Traits::type;
    if constexpr (Traits::optional) {
        if (v) member = convert<T>(*v);
        else member.reset();
    } else if constexpr (Traits::tracks_given) {
        member.value = convert<T>(*v);
        member.given = given;
    } else {
        member = convert<T>(*v);
    }
}

} // namespace param_binding

/// Collects a stage's parameter declarations and, for configure(), where each value goes.
class ParamBinder {
public:
    /// Declares `spec` and binds it to `member`: bool for Bool; any integer type for Int;
    /// float or double for Float; std::string or std::filesystem::path for String, Path and
    /// Enum. A parameter declared optional() (no default, may stay unset) binds to a
    /// std::optional<...>, reset when unset; Param<...> also records whether it was given.
    /// A member of the wrong type for the declaration is a std::logic_error (a stage bug).
    template <typename M>
    void add(M& member, ParamSpec spec) {
        using Traits = param_binding::Member<M>;
        require(param_binding::holds<typename Traits::type>(spec.type), spec, "its type");
        require(spec.is_optional == Traits::optional, spec,
                spec.is_optional ? "a std::optional (it may be unset)" : "a plain value (it is always set)");
        add_binding(std::move(spec),
                    [&member](const ParamValue* v, bool given) { param_binding::store(member, v, given); });
    }
    /// Declares an Enum and binds it to a member of any type (an enumeration, mostly):
    /// `values[i]` is what `spec.choices[i]` stands for.
    template <typename E>
    void add(E& member, ParamSpec spec, std::vector<E> values) {
        require(spec.type == ParamType::Enum && values.size() == spec.choices.size() && !spec.is_optional, spec,
                "one enumerator for each of its choices");
        std::vector<std::string> choices = spec.choices;
        add_binding(std::move(spec), [&member, choices, values](const ParamValue* v, bool) {
            const auto& s = std::get<std::string>(*v);
            for (std::size_t i = 0; i < choices.size(); ++i)
                if (choices[i] == s) member = values[i];
        });
    }

    /// Declares the Enum `name` with the choices "auto" (the default), "on" and "off", and
    /// binds it to an enumeration with the enumerators Auto, On and Off.
    template <typename E>
    void add_auto_on_off(E& member, std::string name, std::string doc) {
        add(member, ParamSpec::Enum(std::move(name), "auto", {"auto", "on", "off"}, std::move(doc)),
            {E::Auto, E::On, E::Off});
    }

    /// The declarations, in the order they were added.
    std::vector<ParamSpec> specs() const;
    /// Sets every bound member from `values`: checked values (check_param()) of every
    /// declared parameter that is not optional, as configure() has them.
    void assign(const ParamSet& values) const;
    /// Sets every bound member to its declared default (an optional one without a default:
    /// unset); a required parameter's member is left as it is.
    void assign_defaults() const;

private:
    using Setter = std::function<void(const ParamValue* value, bool given)>;
    struct Binding {
        ParamSpec spec;
        Setter set;
    };
    void add_binding(ParamSpec spec, Setter set);
    static void require(bool ok, const ParamSpec& spec, const std::string& what);
    std::vector<Binding> bindings_;
};

/// Sets every member `options.declare(b)` binds to its declared default. An options struct's
/// constructor calls it, so each default is written once, in its declaration (core/algorithm.h).
template <typename Options>
void set_declared_defaults(Options& options) {
    ParamBinder b;
    options.declare(b);
    b.assign_defaults();
}

} // namespace cm
