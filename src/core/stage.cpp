#include "core/stage.h"

#include <unistd.h>
#include <atomic>
#include <cctype>
#include <nlohmann/json.hpp>

namespace cm {

const char* to_string(DataKind k) {
    switch (k) {
    case DataKind::Views: return "views";
    case DataKind::Volume: return "volume";
    case DataKind::Mesh: return "mesh";
    case DataKind::File: return "file";
    case DataKind::Report: return "report";
    }
    return "?";
}

DataKind kind_of(const Data& d) {
    switch (d.index()) {
    case 1: return DataKind::Views;
    case 2: return DataKind::Volume;
    case 3: return DataKind::Mesh;
    case 4: return DataKind::File;
    case 5: return DataKind::Report;
    default: throw Error("a stage returned no data");
    }
}

Context::Context(std::string node, std::string stage, Hooks hooks)
    : node_(std::move(node)),
      stage_(std::move(stage)),
      hooks_(std::move(hooks)),
      interrupter_(node_, hooks_.sink, hooks_.stop) {}

void Context::warn(const std::string& text) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        warnings_.push_back(text);
    }
    if (hooks_.sink) hooks_.sink->message(node_, "warning", text);
}

void Context::info(const std::string& text) {
    if (hooks_.sink) hooks_.sink->message(node_, "info", text);
}

void Context::metric(const std::string& key, double value) {
    std::lock_guard<std::mutex> lock(mutex_);
    metrics_[key] = nlohmann::json(value).dump();
}

void Context::metric(const std::string& key, const std::string& value) {
    std::lock_guard<std::mutex> lock(mutex_);
    metrics_[key] = nlohmann::json(value).dump();
}

void Context::metric_json(const std::string& key, const std::string& json_text) {
    std::lock_guard<std::mutex> lock(mutex_);
    metrics_[key] = json_text;
}

namespace {

// {"front": 1.5, ...}: figures as doubles, counts as whole numbers.
template <typename T>
std::string per_view_json(const std::vector<std::string>& views, const std::vector<T>& values) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t i = 0; i < views.size() && i < values.size(); ++i) j[views[i]] = values[i];
    return j.dump();
}

} // namespace

void Metrics::per_view(const std::string& key, const std::vector<std::string>& views,
                       const std::vector<double>& values) {
    metric_json(key, per_view_json(views, values));
}

void Metrics::per_view(const std::string& key, const std::vector<std::string>& views,
                       const std::vector<std::size_t>& counts) {
    metric_json(key, per_view_json(views, counts));
}

StageInfo Stage::info() const {
    ParamBinder b;
    // declare() only records where each value goes; nothing is written through it here.
    const_cast<Stage*>(this)->declare(b);
    return {signature(), b.specs()};
}

void Stage::configure(const ParamSet& params) {
    ParamBinder b;
    declare(b);
    const std::vector<ParamSpec> specs = b.specs();
    for (const auto& [name, value] : params.values()) {
        const ParamSpec* spec = find_param(specs, name);
        if (!spec) throw Error("unknown parameter \"" + name + "\" (parameters: " + param_names(specs) + ")");
        std::string why = check_param(*spec, value);
        if (why.empty() && spec->is_output) why = check_output_path(*spec, std::get<std::string>(value));
        if (!why.empty()) throw Error(why);
    }
    ParamSet filled = params;
    if (auto missing = fill_defaults(specs, filled); !missing.empty()) throw Error(missing);
    b.assign(filled);
    params_ = std::move(filled);
    check();
}

std::filesystem::path temporary_path(const std::filesystem::path& final_path) {
    static std::atomic<unsigned> counter{0};
    auto tmp = final_path;
    tmp += ".part-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + final_path.extension().string();
    return tmp;
}

std::string lower_extension(const std::filesystem::path& path) {
    std::string e = path.extension().string();
    for (auto& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

std::filesystem::path Context::output_file(const std::filesystem::path& final_path) {
    const auto tmp = temporary_path(final_path);
    // The host's hook makes the missing folders (and takes them back if the run fails).
    if (hooks_.stage_file) hooks_.stage_file(tmp, final_path);
    else std::filesystem::create_directories(std::filesystem::absolute(final_path).parent_path());
    return tmp;
}

} // namespace cm
