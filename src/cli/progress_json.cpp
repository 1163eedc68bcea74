#include "cli/progress_json.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <regex>

#include "cli/commands.h"
#include "core/error.h"

namespace cm::cli {

JsonProgress::JsonProgress(std::string pipeline, std::vector<std::pair<std::string, std::string>> nodes)
    : pipeline_(std::move(pipeline)), nodes_(std::move(nodes)) {}

void JsonProgress::emit_locked(const nlohmann::ordered_json& j) {
    // One object per line, flushed: a reader sees each event as it happens. Invalid UTF-8
    // (a file name in another encoding) is replaced, so every line parses.
    std::cout << j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << '\n' << std::flush;
}

double JsonProgress::overall_locked() const {
    if (nodes_.empty()) return 0;
    double sum = 0;
    for (const auto& [id, f] : fraction_) sum += f;
    return std::clamp(sum / double(nodes_.size()), 0.0, 1.0);
}

std::string JsonProgress::stage_of(const std::string& node) const {
    for (const auto& [id, stage] : nodes_)
        if (id == node) return stage;
    return {};
}

void JsonProgress::begin() {
    nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
    for (const auto& [id, stage] : nodes_) nodes.push_back({{"node", id}, {"stage", stage}});
    std::lock_guard<std::mutex> lock(mutex_);
    emit_locked({{"event", "begin"}, {"pipeline", pipeline_}, {"nodes", nodes}});
}

void JsonProgress::started(const std::string& node, const std::string& stage) {
    std::lock_guard<std::mutex> lock(mutex_);
    fraction_[node] = 0;
    last_percent_[node] = 0;
    emit_locked({{"event", "start"}, {"node", node}, {"stage", stage}, {"overall", overall_locked()}});
}

void JsonProgress::progress(const std::string& node, double percent, const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex_);
    const double f = std::clamp(percent / 100.0, 0.0, 1.0);
    fraction_[node] = std::max(fraction_[node], f);
    // A line per whole percent at most: stages report far more often than a reader needs.
    const int whole = int(f * 100.0);
    auto it = last_percent_.find(node);
    if (it != last_percent_.end() && whole <= it->second) return;
    last_percent_[node] = whole;
    nlohmann::ordered_json j = {{"event", "progress"}, {"node", node},    {"stage", stage_of(node)},
                                {"fraction", f},       {"message", what}, {"overall", overall_locked()}};
    emit_locked(j);
}

void JsonProgress::finished(const std::string& node, double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    fraction_[node] = 1;
    emit_locked({{"event", "finish"},
                 {"node", node},
                 {"stage", stage_of(node)},
                 {"seconds", seconds},
                 {"overall", overall_locked()}});
}

void JsonProgress::message(const std::string& node, const std::string& level, const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (level == "warning") ++warnings_;
    emit_locked({{"event", "message"},
                 {"level", level},
                 {"node", node},
                 {"stage", stage_of(node)},
                 {"message", shorten_long_words(text)}});
}

void JsonProgress::done(const std::vector<std::filesystem::path>& outputs, double seconds, std::size_t peak_rss_bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    nlohmann::ordered_json files = nlohmann::ordered_json::array();
    for (const auto& out : outputs) {
        const std::string path = std::filesystem::absolute(out).lexically_normal().string();
        files.push_back(path);
        emit_locked({{"event", "output"}, {"path", path}});
    }
    emit_locked({{"event", "end"},
                 {"status", "ok"},
                 {"outputs", files},
                 {"warnings", warnings_},
                 {"seconds", seconds},
                 {"peak_memory_bytes", peak_rss_bytes}});
}

void JsonProgress::failed(const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string text = shorten_long_words(e.what());
    const MessageParts parts = split_node_message(text);
    nlohmann::ordered_json j = {{"event", "end"},
                                {"status", dynamic_cast<const Cancelled*>(&e) ? "cancelled" : "error"},
                                {"message", text},
                                {"cause", parts.cause},
                                {"warnings", warnings_}};
    if (!parts.node.empty()) {
        j["node"] = parts.node;
        j["stage"] = parts.stage;
    }
    if (!parts.file.empty()) j["file"] = parts.file;
    if (parts.line > 0) j["line"] = parts.line;
    emit_locked(j);
}

MessageParts split_node_message(const std::string& text) {
    // Pipeline::where's prefix: "file:line: node "id" (stage): ".
    static const std::regex prefix(R"re(^(.*?)(?::(\d+))?: node "([^"]*)" \(([^()\s]*)\): )re");
    MessageParts parts;
    std::smatch m;
    if (!std::regex_search(text, m, prefix)) {
        parts.cause = text;
        return parts;
    }
    parts.file = m[1];
    if (m[2].matched) parts.line = int(std::strtol(std::string(m[2]).c_str(), nullptr, 10));
    parts.node = m[3];
    parts.stage = m[4];
    parts.cause = m.suffix();
    return parts;
}

} // namespace cm::cli
