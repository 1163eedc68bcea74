#include "core/param_binder.h"

#include "core/error.h"

namespace cm {

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

} // namespace cm
