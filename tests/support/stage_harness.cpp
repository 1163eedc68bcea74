#include "support/stage_harness.h"

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace cm::test {

StageHarness::StageHarness(std::string stage) : StageHarness(std::move(stage), Registry::global()) {}

StageHarness::StageHarness(std::string stage, const Registry& registry)
    : stage_(std::move(stage)), registry_(registry) {
    opt_.node = "test";
}

StageHarness::~StageHarness() { remove_staged(); }

void StageHarness::remove_staged() {
    if (opt_.commit) return;
    std::error_code ec;
    for (const auto& [tmp, final_path] : last_.staged) fs::remove(tmp, ec);
}

StageHarness& StageHarness::params(const std::string& yaml_mapping) {
    for (auto& [name, raw] : yaml_params(yaml_mapping)) params_[name] = raw;
    return *this;
}

std::string StageHarness::quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

StageHarness& StageHarness::side_output_dir(const fs::path& dir) {
    opt_.side_output_dir = dir;
    return *this;
}

StageHarness& StageHarness::keep_staged() {
    opt_.commit = false;
    return *this;
}

StageInfo StageHarness::info() const { return registry_.create(stage_)->info(); }

void StageHarness::configure() const { configure_stage(registry_, stage_, params_); }

Data StageHarness::run_data() {
    StageRun run = run_stage(registry_, stage_, params_, inputs_, opt_);
    remove_staged();
    last_ = std::move(run);
    return last_.output;
}

std::string StageHarness::error() {
    try {
        run_data();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

double StageHarness::metric(const std::string& name) const {
    const auto it = last_.metrics_json.find(name);
    if (it == last_.metrics_json.end()) throw Error("stage \"" + stage_ + "\" reported no metric \"" + name + "\"");
    return nlohmann::json::parse(it->second).get<double>();
}

} // namespace cm::test
