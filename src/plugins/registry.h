// Finds plugin libraries, checks them, and keeps the stage factories by name.
//
// A plugin folder may hold an index, `plugins.index`, naming each plugin's stages (the
// build writes one for the plugins it makes). A plugin the index names is loaded the first
// time one of its stages is asked for, as PDAL and USD load theirs: a pipeline without
// OpenVDB stages never loads OpenVDB, and a run can start its first stage while the
// plugins of the later ones still load. A plugin the index does not name is loaded at
// once. The index is a hint, checked against the plugin when it loads: a stage it names
// that the plugin lacks, or a stage no index names, makes the registry load every plugin
// left, so a stale index costs time, never a stage. Its format, one plugin per line:
//
//   # comment
//   libcm_hull.so hull.carve hull.marching_intersections hull.plausible
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
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
    Registry() = default;
    Registry(Registry&& o) noexcept;
    Registry& operator=(Registry&&) = delete;

    /// Takes in every plugin of `dirs` (files named libcm_*.so), in order: those a folder's
    /// index names on first use, the others now. Problems do not throw: they are
    /// collected as diagnostics, the host keeps working.
    void load_directories(const std::vector<std::filesystem::path>& dirs);
    /// Loads one library; returns false and records why when it is refused.
    bool load_library(const std::filesystem::path& file);
    /// Registers a stage compiled into the caller (tests).
    void add(StageEntry e);

    /// The stage's entry, loading its plugin when that is not loaded yet; null when no
    /// plugin has it. Safe to call from several threads.
    const StageEntry* find(const std::string& stage) const;
    /// A new instance of the stage, or throws cm::Error naming the known stages.
    std::unique_ptr<Stage> create(const std::string& stage) const;
    /// Every stage of every plugin (loads the plugins not loaded yet).
    std::vector<std::string> names() const;
    /// Warnings and refusals seen while loading so far, one sentence each.
    std::vector<std::string> diagnostics() const;
    /// The plugin files loaded so far (refused ones too), in search order.
    std::vector<std::filesystem::path> loaded_files() const;

    /// The default search path: the plugin folder next to the executable, then
    /// every folder of CONCEPTMESH_PLUGIN_PATH (':'-separated).
    static std::vector<std::filesystem::path> default_dirs();
    /// The process-wide registry, taking in default_dirs() on first use.
    static Registry& global();
    /// The name of a folder's index file.
    static constexpr const char* kIndexFile = "plugins.index";

private:
    struct PluginFile {
        std::filesystem::path path;
        bool indexed = false;            ///< named by its folder's index (loaded on first use)
        std::vector<std::string> stages; ///< what the index says it has
        bool loaded = false;
    };
    bool load_locked(std::size_t file) const; ///< files_[file], once; whether it added a stage
    void load_all_locked() const;
    const StageEntry* find_locked(const std::string& stage) const;

    mutable std::mutex mutex_;
    mutable std::map<std::string, StageEntry> stages_;
    mutable std::vector<std::string> diagnostics_;
    mutable std::vector<std::shared_ptr<void>> handles_;
    mutable std::vector<PluginFile> files_;           ///< in search order
    mutable std::map<std::string, std::size_t> lazy_; ///< stage -> the first indexed file naming it
};

} // namespace cm
