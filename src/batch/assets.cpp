// ASSETS.yaml: reading and checking it (read_assets), writing one for a folder of assets
// (scan_folder), and turning each asset into the command that runs it (plan_assets).
#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "batch/batch.h"
#include "batch/keys.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "io/yaml_checks.h"
#include "pipeline/pipeline.h"

namespace fs = std::filesystem;

namespace cm::batch {

namespace {

int line_of(const YAML::Node& n) { return n.Mark().line + 1; }

std::string at(const fs::path& file, int line) { return file.string() + ":" + std::to_string(line) + ": "; }

bool known(const std::vector<std::string>& keys, const std::string& k) {
    return std::find(keys.begin(), keys.end(), k) != keys.end();
}

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

// "{hull.resolution: 128}" or ["hull.resolution=128"] -> NODE.PARAM=VALUE, in file order.
std::vector<std::string> read_sets(const YAML::Node& n, const std::string& where) {
    std::vector<std::string> out;
    if (n.IsMap()) {
        for (const auto& kv : n) {
            const auto key = kv.first.as<std::string>();
            if (!kv.second.IsScalar())
                throw Error(where + "set: the value of \"" + key +
                            "\" must be a single value (a number, word or path)");
            if (key.find('.') == std::string::npos)
                throw Error(where + "set: \"" + key + "\" must be NODE.PARAM (for example hull.resolution)");
            out.push_back(key + "=" + kv.second.Scalar());
        }
    } else if (n.IsSequence()) {
        for (const auto& e : n) {
            if (!e.IsScalar() || e.Scalar().find('=') == std::string::npos)
                throw Error(where + "set: each entry must be NODE.PARAM=VALUE");
            out.push_back(e.Scalar());
        }
    } else {
        throw Error(where + "set must be a mapping {NODE.PARAM: VALUE} or a list of NODE.PARAM=VALUE");
    }
    return out;
}

fs::path resolve_file(const fs::path& base, const YAML::Node& n, const std::string& where, const std::string& key) {
    if (!n.IsScalar() || n.Scalar().empty()) throw Error(where + key + " must be a file name");
    fs::path p = n.Scalar();
    if (p.is_relative()) p = base / p;
    p = p.lexically_normal();
    if (fs::is_directory(p)) throw Error(where + key + " \"" + n.Scalar() + "\" is a folder; name the file");
    if (!fs::exists(p)) throw Error(where + key + " \"" + n.Scalar() + "\" does not exist (" + p.string() + ")");
    return fs::absolute(p);
}

// A sheet entry as a views manifest of its own, its image made absolute.
std::string sheet_manifest(const YAML::Node& sheet, const fs::path& base, const std::string& where) {
    if (!sheet.IsMap() || !sheet["image"] || !sheet["views"])
        throw Error(where + "sheet must be a mapping {image: FILE, views: [front, right, ...]}");
    YAML::Node copy = YAML::Clone(sheet);
    copy["image"] = resolve_file(base, sheet["image"], where, "sheet image").string();
    YAML::Emitter e;
    e << YAML::BeginMap << YAML::Key << "sheet" << YAML::Value << copy << YAML::EndMap;
    return std::string("# Written by conceptmesh batch from a sheet entry.\n") + e.c_str() + "\n";
}

} // namespace

std::string AssetsFile::where(const AssetSpec& a) const { return at(file, a.line) + "asset \"" + a.name + "\": "; }

AssetsFile read_assets(const fs::path& file, const std::string& pipeline_override) {
    if (fs::is_directory(file)) throw Error(file.string() + " is a folder; name the ASSETS.yaml file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error("cannot open \"" + file.string() + "\"");
    std::stringstream ss;
    ss << in.rdbuf();
    YAML::Node doc;
    try {
        doc = YAML::Load(ss.str());
    } catch (const YAML::Exception& e) {
        throw Error(at(file, e.mark.line + 1) + e.msg);
    }
    check_yaml_document(doc, file);
    if (!doc.IsMap()) throw Error(at(file, 1) + "expected a mapping with pipeline and assets");
    AssetsFile f;
    f.file = file;
    f.name = file.stem().string();
    const fs::path base = fs::absolute(file).parent_path();
    for (const auto& kv : doc) {
        const auto k = kv.first.as<std::string>();
        if (!known(kTopKeys, k))
            throw Error(at(file, line_of(kv.first)) + "unknown key \"" + k + "\" (known: " + join(kTopKeys) + ")");
    }
    fs::path pipeline;
    std::vector<std::string> default_sets;
    if (!pipeline_override.empty()) {
        YAML::Node n(pipeline_override);
        pipeline = resolve_file(fs::current_path(), n, "--pipeline: ", "the pipeline");
    } else if (doc["pipeline"]) {
        pipeline = resolve_file(base, doc["pipeline"], at(file, line_of(doc["pipeline"])), "pipeline");
    }
    if (doc["batch"]) {
        f.name = doc["batch"].as<std::string>();
        if (!std::regex_match(f.name, std::regex("[A-Za-z0-9][A-Za-z0-9_.-]*")))
            throw Error(at(file, line_of(doc["batch"])) + "batch must be a name of letters, digits and -_. only");
    }
    if (doc["set"]) default_sets = read_sets(doc["set"], at(file, line_of(doc["set"])));
    if (doc["output"]) {
        f.output = doc["output"].as<std::string>();
        const fs::path o(f.output);
        bool up = false;
        for (const auto& part : o) up = up || part == "..";
        if (f.output.find("{name}") == std::string::npos || o.is_absolute() || up)
            throw Error(at(file, line_of(doc["output"])) +
                        "output must be a relative folder pattern holding {name} and no \"..\", got \"" + f.output +
                        "\"");
    }
    const YAML::Node assets = doc["assets"];
    if (!assets || !assets.IsSequence() || assets.size() == 0)
        throw Error(at(file, assets ? line_of(assets) : 1) + "assets must be a non-empty list");
    std::map<std::string, int> seen;
    for (const auto& a : assets) {
        AssetSpec s;
        s.line = line_of(a);
        if (!a.IsMap() || !a["name"] || !a["name"].IsScalar())
            throw Error(at(file, s.line) + "each asset needs a name (name: crate)");
        s.name = a["name"].Scalar();
        const std::string where = f.where(s);
        if (!std::regex_match(s.name, std::regex("[A-Za-z0-9][A-Za-z0-9_.-]*")) || s.name.size() > 100)
            throw Error(where + "a name must be letters, digits and -_. only (it names the asset's folder)");
        if (auto it = seen.find(s.name); it != seen.end())
            throw Error(where + "the name is given twice (first on line " + std::to_string(it->second) + ")");
        seen[s.name] = s.line;
        for (const auto& kv : a) {
            const auto k = kv.first.as<std::string>();
            if (!known(kAssetKeys, k))
                throw Error(at(file, line_of(kv.first)) + "asset \"" + s.name + "\": unknown key \"" + k +
                            "\" (known: " + join(kAssetKeys) + ")");
        }
        if (bool(a["views"]) == bool(a["sheet"]))
            throw Error(where + "give either views (a views manifest) or sheet (a turnaround sheet)");
        if (a["views"])
            s.views =
                resolve_file(base, a["views"], at(file, line_of(a["views"])) + "asset \"" + s.name + "\": ", "views");
        else
            s.sheet_yaml =
                sheet_manifest(a["sheet"], base, at(file, line_of(a["sheet"])) + "asset \"" + s.name + "\": ");
        s.pipeline = pipeline;
        if (a["pipeline"] && pipeline_override.empty())
            s.pipeline = resolve_file(base, a["pipeline"], where, "pipeline");
        if (s.pipeline.empty())
            throw Error(where + "no pipeline: give pipeline: at the top, for the asset, or --pipeline");
        s.sets = default_sets;
        if (a["set"]) {
            const auto own = read_sets(a["set"], at(file, line_of(a["set"])) + "asset \"" + s.name + "\": ");
            s.sets.insert(s.sets.end(), own.begin(), own.end());
        }
        if (a["memory_mib"]) {
            try {
                s.memory_mib = a["memory_mib"].as<double>();
            } catch (const YAML::Exception&) {
                s.memory_mib = -1;
            }
            if (!(*s.memory_mib > 0 && *s.memory_mib < 1e7))
                throw Error(where + "memory_mib must be a number of MiB above 0");
        }
        f.assets.push_back(std::move(s));
    }
    return f;
}

std::size_t scan_folder(const fs::path& folder, const fs::path& out, const std::string& pipeline) {
    if (!fs::is_directory(folder)) throw Error("--scan \"" + folder.string() + "\" is not a folder");
    std::vector<fs::path> dirs;
    for (const auto& e : fs::directory_iterator(folder))
        if (e.is_directory()) dirs.push_back(e.path());
    std::sort(dirs.begin(), dirs.end());
    const fs::path base = fs::absolute(out).parent_path();
    std::ostringstream y;
    y << "# Written by conceptmesh batch --scan " << folder.string() << "\n";
    y << "pipeline: " << fs::absolute(pipeline).lexically_proximate(base).string() << "\n";
    y << "output: \"{name}\"\nassets:\n";
    std::size_t n = 0;
    for (const auto& d : dirs) {
        fs::path manifest;
        for (const char* m : {"views.yaml", "views.yml"})
            if (fs::is_regular_file(d / m)) {
                manifest = d / m;
                break;
            }
        if (manifest.empty()) continue;
        std::string name = d.filename().string();
        if (!std::regex_match(name, std::regex("[A-Za-z0-9][A-Za-z0-9_.-]*")))
            name = std::regex_replace(name, std::regex("[^A-Za-z0-9_.-]"), "_");
        if (!std::isalnum(static_cast<unsigned char>(name[0]))) name = "a" + name;
        y << "  - name: " << name << "\n    views: \"" << fs::absolute(manifest).lexically_proximate(base).string()
          << "\"\n";
        ++n;
    }
    if (n == 0) throw Error("--scan \"" + folder.string() + "\": no subfolder holds a views.yaml");
    write_file_atomic(out, y.str());
    return n;
}

} // namespace cm::batch
