// Finds plugin libraries, checks them, and keeps the stage factories by name.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/stage.h"

namespace cm {

struct StageEntry {
    std::string name;
    std::filesystem::path library; ///< the plugin file it came from
    std::string plugin, plugin_version;
    std::function<std::unique_ptr<Stage>()> create;
};

class Registry {
public:
    /// Loads every plugin in `dirs` (files named libcm_*.so) in order.
    /// Problems do not throw: they are collected as diagnostics, the host keeps working.
    void load_directories(const std::vector<std::filesystem::path>& dirs);
    /// Loads one library; returns false and records why when it is refused.
    bool load_library(const std::filesystem::path& file);
    /// Registers a stage compiled into the caller (tests).
    void add(StageEntry e);

    const StageEntry* find(const std::string& stage) const;
    /// The stage's info, or throws cm::Error naming the known stages.
    std::unique_ptr<Stage> create(const std::string& stage) const;
    std::vector<std::string> names() const;
    /// Warnings and refusals seen while loading, one sentence each.
    const std::vector<std::string>& diagnostics() const { return diagnostics_; }

    /// The default search path: the plugin folder next to the executable, then
    /// every folder of CONCEPTMESH_PLUGIN_PATH (':'-separated).
    static std::vector<std::filesystem::path> default_dirs();
    /// The process-wide registry, loaded from default_dirs() on first use.
    static Registry& global();

private:
    std::map<std::string, StageEntry> stages_;
    std::vector<std::string> diagnostics_;
    std::vector<std::shared_ptr<void>> handles_;
};

} // namespace cm
