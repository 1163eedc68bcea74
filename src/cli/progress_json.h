// `conceptmesh run --progress json`: the run as a stream of JSON objects, one per line on
// stdout, for programs that drive the command (the Blender add-on). docs/pipelines.md
// describes the events.
#pragma once
#include <chrono>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/progress.h"

namespace cm::cli {

class JsonProgress : public ProgressSink {
public:
    /// `nodes`: every node of the pipeline (id, stage), in the file's order; `pipeline`: its file.
    JsonProgress(std::string pipeline, std::vector<std::pair<std::string, std::string>> nodes);
    void started(const std::string& node, const std::string& stage) override;
    void progress(const std::string& node, double percent, const std::string& what) override;
    void finished(const std::string& node, double seconds) override;
    void message(const std::string& node, const std::string& level, const std::string& text) override;

    /// The first line: the pipeline and its nodes.
    void begin();
    /// The last line of a run that succeeded: one "output" line per file, then "done".
    void done(const std::vector<std::filesystem::path>& outputs, double seconds, std::size_t peak_rss_bytes);
    /// The last line of a run that failed: the message, and the node and stage it names.
    void failed(const std::exception& e);

private:
    void emit_locked(const nlohmann::ordered_json& j);
    double overall_locked() const;
    std::string stage_of(const std::string& node) const;

    std::string pipeline_;
    std::vector<std::pair<std::string, std::string>> nodes_;
    std::mutex mutex_;
    std::map<std::string, double> fraction_; ///< per node started: 0-1
    std::map<std::string, int> last_percent_;
    int warnings_ = 0;
};

/// Node id and stage named by a message's "file:line: node "id" (stage): " prefix, and the
/// rest (the cause); empty id and stage when the message names no node.
struct MessageParts {
    std::string node, stage, file, cause;
    int line = 0;
};
MessageParts split_node_message(const std::string& text);

} // namespace cm::cli
