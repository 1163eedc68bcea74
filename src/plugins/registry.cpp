#include "plugins/registry.h"

#include <dlfcn.h>
#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "plugins/plugin_abi.h"

namespace fs = std::filesystem;

namespace cm {

namespace {

bool is_plugin_file(const fs::path& p) {
    const std::string name = p.filename().string();
    return name.rfind("libcm_", 0) == 0 && p.extension() == ".so";
}

fs::path executable_dir() {
    std::error_code ec;
    auto exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::current_path() : exe.parent_path();
}

} // namespace

std::vector<fs::path> Registry::default_dirs() {
    std::vector<fs::path> dirs;
    const fs::path exe = executable_dir();
    // <prefix>/bin/conceptmesh -> <prefix>/<libdir>/conceptmesh/plugins (build and install trees
    // alike; libdir is lib, or lib/<multiarch> for an install into /usr).
    dirs.push_back(exe.parent_path() / CONCEPTMESH_PLUGIN_SUBDIR);
    if (const char* env = std::getenv("CONCEPTMESH_PLUGIN_PATH")) {
        std::stringstream ss(env);
        std::string item;
        while (std::getline(ss, item, ':'))
            if (!item.empty()) dirs.emplace_back(item);
    }
    return dirs;
}

Registry& Registry::global() {
    static Registry r = [] {
        Registry reg;
        reg.load_directories(default_dirs());
        return reg;
    }();
    return r;
}

Registry::Registry(Registry&& o) noexcept {
    std::lock_guard<std::mutex> lock(o.mutex_);
    stages_ = std::move(o.stages_);
    diagnostics_ = std::move(o.diagnostics_);
    handles_ = std::move(o.handles_);
    files_ = std::move(o.files_);
    lazy_ = std::move(o.lazy_);
}

namespace {

// A folder's index: plugin file name -> the stages it says the plugin has. Empty when the
// folder has none; lines that do not parse are skipped with a diagnostic.
std::map<std::string, std::vector<std::string>> read_index(const fs::path& dir, std::vector<std::string>& diagnostics) {
    std::map<std::string, std::vector<std::string>> index;
    const fs::path file = dir / Registry::kIndexFile;
    std::ifstream in(file);
    if (!in) return index;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        std::istringstream words(line);
        std::string name;
        if (!(words >> name) || name[0] == '#') continue;
        std::vector<std::string> stages;
        for (std::string s; words >> s;) stages.push_back(s);
        if (!is_plugin_file(name) || stages.empty()) {
            diagnostics.push_back("plugin index \"" + file.string() + "\" line " + std::to_string(n) +
                                  ": expected a plugin file (libcm_*.so) and its stages; the line is skipped");
            continue;
        }
        index[name] = std::move(stages);
    }
    return index;
}

} // namespace

void Registry::load_directories(const std::vector<fs::path>& dirs) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& dir : dirs) {
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) continue;
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.is_regular_file() && is_plugin_file(e.path())) files.push_back(e.path());
        std::sort(files.begin(), files.end()); // deterministic "first wins"
        const auto index = read_index(dir, diagnostics_);
        for (const auto& f : files) {
            const auto it = index.find(f.filename().string());
            PluginFile pf;
            pf.path = f;
            pf.indexed = it != index.end();
            if (pf.indexed) pf.stages = it->second;
            files_.push_back(std::move(pf));
            if (!files_.back().indexed) {
                load_locked(files_.size() - 1);
                continue;
            }
            for (const auto& s : files_.back().stages) lazy_.emplace(s, files_.size() - 1);
        }
    }
}

bool Registry::load_library(const fs::path& file) {
    std::lock_guard<std::mutex> lock(mutex_);
    files_.push_back({file, false, {}, false});
    return load_locked(files_.size() - 1);
}

bool Registry::load_locked(std::size_t at) const {
    if (files_[at].loaded) return false;
    files_[at].loaded = true;
    const fs::path file = files_[at].path;
    const std::string name = file.string();
    // RTLD_NODELETE: a plugin is never unmapped, not even when the last registry holding
    // it goes. Its stages run TBB tasks whose code (the parallel_for templates) lives in
    // the plugin; a worker thread can still be returning through that code after the
    // caller has seen the work finish, and unmapping it then crashes the process on its
    // way out (seen as an exit-time SIGSEGV of short commands such as compare).
    void* h = ::dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!h) {
        const char* why = ::dlerror();
        diagnostics_.push_back("plugin \"" + name + "\" could not be loaded: " + (why ? why : "unknown reason"));
        return false;
    }
    std::shared_ptr<void> handle(h, [](void* p) { ::dlclose(p); });
    auto entry = reinterpret_cast<ConceptmeshPluginEntry>(::dlsym(h, CONCEPTMESH_PLUGIN_ENTRY_NAME));
    if (!entry) {
        diagnostics_.push_back("plugin \"" + name + "\" is not a conceptmesh plugin: it has no " +
                               CONCEPTMESH_PLUGIN_ENTRY_NAME + " symbol");
        return false;
    }
    const ConceptmeshPluginDescriptor* d = nullptr;
    try {
        d = entry();
    } catch (const std::exception& e) {
        diagnostics_.push_back("plugin \"" + name + "\" failed in its entry point: " + e.what());
        return false;
    } catch (...) {
        diagnostics_.push_back("plugin \"" + name + "\" failed in its entry point");
        return false;
    }
    if (!d) {
        diagnostics_.push_back("plugin \"" + name + "\" returned no descriptor");
        return false;
    }
    if (d->plugin_abi != CONCEPTMESH_PLUGIN_ABI_VERSION) {
        diagnostics_.push_back("plugin \"" + name + "\" was refused: built for plugin ABI " +
                               std::to_string(d->plugin_abi) + ", this conceptmesh needs ABI " +
                               std::to_string(CONCEPTMESH_PLUGIN_ABI_VERSION) + "; rebuild the plugin");
        return false;
    }
    if (d->openvdb_abi != OPENVDB_ABI_VERSION_NUMBER) {
        diagnostics_.push_back("plugin \"" + name + "\" was refused: built against OpenVDB ABI " +
                               std::to_string(d->openvdb_abi) + ", this conceptmesh uses OpenVDB ABI " +
                               std::to_string(OPENVDB_ABI_VERSION_NUMBER));
        return false;
    }
    const std::string pname = d->name ? d->name : file.stem().string();
    const std::string pversion = d->version ? d->version : "?";
    bool any = false;
    std::vector<std::string> found;
    for (std::size_t i = 0; i < d->stage_count; ++i) {
        const ConceptmeshStageFactory& f = d->stages[i];
        if (!f.stage_name || !f.create) {
            diagnostics_.push_back("plugin \"" + name + "\" declares an incomplete stage factory #" +
                                   std::to_string(i));
            continue;
        }
        found.emplace_back(f.stage_name);
        // The first plugin in the search order that has the stage keeps it: one that an index
        // says has it and that comes earlier is loaded first.
        if (auto it = lazy_.find(f.stage_name); it != lazy_.end() && it->second < at) load_locked(it->second);
        if (auto it = stages_.find(f.stage_name); it != stages_.end()) {
            diagnostics_.push_back("stage \"" + std::string(f.stage_name) + "\" is defined by both \"" +
                                   it->second.library.string() + "\" and \"" + name + "\"; using the first");
            continue;
        }
        StageEntry e;
        e.name = f.stage_name;
        e.library = file;
        e.plugin = pname;
        e.plugin_version = pversion;
        auto create = f.create;
        e.create = [create, handle]() { return std::unique_ptr<Stage>(create()); };
        stages_.emplace(e.name, std::move(e));
        any = true;
    }
    if (any) handles_.push_back(handle);
    for (const auto& s : files_[at].stages)
        if (std::find(found.begin(), found.end(), s) == found.end()) {
            diagnostics_.push_back("plugin index \"" + (file.parent_path() / kIndexFile).string() +
                                   "\" is out of date: \"" + name + "\" has no stage \"" + s +
                                   "\"; every plugin is loaded instead");
            load_all_locked();
            break;
        }
    return any;
}

void Registry::load_all_locked() const {
    for (std::size_t i = 0; i < files_.size(); ++i) load_locked(i);
}

void Registry::add(StageEntry e) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = stages_.find(e.name); it != stages_.end()) {
        diagnostics_.push_back("stage \"" + e.name + "\" is defined twice; using the first");
        return;
    }
    stages_.emplace(e.name, std::move(e));
}

const StageEntry* Registry::find_locked(const std::string& stage) const {
    if (auto it = stages_.find(stage); it != stages_.end()) return &it->second;
    if (auto it = lazy_.find(stage); it != lazy_.end() && !files_[it->second].loaded) {
        load_locked(it->second);
        if (auto s = stages_.find(stage); s != stages_.end()) return &s->second;
    }
    // No index names it (or its plugin did not have it): it may be in any plugin not loaded yet.
    load_all_locked();
    auto it = stages_.find(stage);
    return it == stages_.end() ? nullptr : &it->second;
}

const StageEntry* Registry::find(const std::string& stage) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return find_locked(stage);
}

std::unique_ptr<Stage> Registry::create(const std::string& stage) const {
    const StageEntry* e = find(stage);
    if (!e) {
        std::string known;
        for (const auto& n : names()) known += (known.empty() ? "" : ", ") + n;
        throw Error("unknown stage \"" + stage +
                    "\" (known stages: " + (known.empty() ? "none; no plugin was found" : known) + ")");
    }
    std::unique_ptr<Stage> s;
    try {
        s = e->create();
    } catch (const std::exception& ex) {
        throw Error("stage \"" + stage + "\" from \"" + e->library.string() + "\" could not be created: " + ex.what());
    } catch (...) {
        throw Error("stage \"" + stage + "\" from \"" + e->library.string() + "\" could not be created");
    }
    if (!s)
        throw Error("stage \"" + stage + "\" from \"" + e->library.string() +
                    "\" could not be created: its factory returned nothing");
    return s;
}

std::vector<std::string> Registry::names() const {
    std::lock_guard<std::mutex> lock(mutex_);
    load_all_locked();
    std::vector<std::string> v;
    for (const auto& [n, _] : stages_) v.push_back(n);
    return v;
}

std::vector<std::string> Registry::diagnostics() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return diagnostics_;
}

std::vector<fs::path> Registry::loaded_files() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<fs::path> v;
    for (const auto& f : files_)
        if (f.loaded) v.push_back(f.path);
    return v;
}

} // namespace cm
