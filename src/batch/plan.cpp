// Each asset's run: its folder, its --set list, the hash of its inputs, its memory estimate,
// its task script, and its outcome read back from the folder.
#include <unistd.h>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <memory>
#include <set>
#include <sstream>

#include <openssl/evp.h>
#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "core/data.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "pipeline/pipeline.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::batch {

namespace {

class Sha256 {
public:
    Sha256() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) { EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr); }
    // Each field is framed by its length, so "ab"+"c" and "a"+"bc" differ.
    void field(const std::string& s) {
        const std::string len = std::to_string(s.size()) + ":";
        EVP_DigestUpdate(ctx_.get(), len.data(), len.size());
        EVP_DigestUpdate(ctx_.get(), s.data(), s.size());
    }
    std::string hex() {
        unsigned char md[EVP_MAX_MD_SIZE];
        unsigned int n = 0;
        EVP_DigestFinal_ex(ctx_.get(), md, &n);
        std::ostringstream o;
        for (unsigned i = 0; i < n; ++i) o << std::hex << std::setw(2) << std::setfill('0') << int(md[i]);
        return o.str();
    }

private:
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

std::string self_exe() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw Error("cannot find the conceptmesh executable (/proc/self/exe): " + ec.message());
    return p.string();
}

// The value a node's parameter ends up with, as text: the last --set, else the file's.
std::string param_text(const PipelineNode& n, const std::string& param) {
    auto it = n.raw_params.find(param);
    if (it == n.raw_params.end()) return {};
    return it->second.text; // a YAML value that is no scalar has none
}

// Pixels of every image the manifest reads (0 when it cannot be read: the run will say why).
double manifest_pixels(const fs::path& manifest) {
    double px = 0;
    try {
        const Manifest m = read_manifest(manifest);
        std::vector<fs::path> seen;
        for (const auto& v : m.views) {
            if (std::find(seen.begin(), seen.end(), v.image) != seen.end()) continue;
            seen.push_back(v.image);
            int w = 0, h = 0;
            if (image_size(v.image, w, h)) px += double(w) * h;
        }
    } catch (const std::exception&) {}
    return px;
}

// A run's peak memory, from docs/results/speed.md (spot and armadillo, 256 to 2048): the
// views take at most about 48 bytes per input pixel (RGBA float, coverage, masks; an 8-bit
// drawing, kept as its bytes, 12 less), the grids and the mesh grow with the surface, about
// 520 bytes per resolution^2 at 1024 and 2048 (400 under glibc's malloc: the command's
// mimalloc keeps what it frees on huge pages, a third more at the peak); plus the process
// itself (about 165 MiB: plugins and libraries loaded, measured on a run that fails at its
// first stage). A quarter more for safety.
double memory_estimate_mib(double pixels, double resolution) {
    const double bytes = 48.0 * pixels + 520.0 * resolution * resolution + 200.0 * 1048576.0;
    return std::ceil(1.25 * bytes / 1048576.0);
}

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

} // namespace

bool batch_mesh(const fs::path& file) {
    const std::string ext = lower_extension(file);
    return ext == ".glb" || ext == ".usdz";
}

std::string read_bytes(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string inputs_hash(const AssetPlan& p, const fs::path& pipeline) {
    Sha256 h;
    h.field(std::string("conceptmesh ") + CONCEPTMESH_VERSION_STRING);
    h.field(read_bytes(pipeline));
    for (const auto& s : p.sets) h.field(s);
    h.field(read_bytes(p.manifest));
    try {
        // Every file the manifest reads, with the numbers it takes from other files (matrix_file).
        const Manifest m = read_manifest(p.manifest);
        for (const auto& v : m.views) {
            h.field(v.key);
            h.field(read_bytes(v.image));
            if (!v.mask.empty()) h.field(read_bytes(v.mask));
            if (v.matrix)
                for (double x : *v.matrix) h.field(std::to_string(x));
        }
    } catch (const std::exception& e) {
        h.field(std::string("unreadable manifest: ") + e.what());
    }
    return h.hex();
}

std::vector<AssetPlan> plan_assets(const AssetsFile& f, const fs::path& out_dir) {
    std::vector<AssetPlan> plans;
    const std::string exe = self_exe();
    const fs::path out = fs::absolute(out_dir).lexically_normal();
    std::set<fs::path> dirs;
    for (const auto& a : f.assets) {
        AssetPlan p;
        p.spec = &a;
        std::string rel = f.output;
        for (std::size_t at; (at = rel.find("{name}")) != std::string::npos;) rel.replace(at, 6, a.name);
        p.dir = (out / rel).lexically_normal();
        if (!dirs.insert(p.dir).second) throw Error(f.where(a) + "two assets share the folder " + p.dir.string());
        if (!a.sheet_yaml.empty()) {
            fs::create_directories(p.dir);
            p.manifest = p.dir / "views.yaml";
            write_file_atomic(p.manifest, a.sheet_yaml);
        } else {
            p.manifest = a.views;
        }
        Pipeline pl;
        try {
            pl = Pipeline::load(a.pipeline);
        } catch (const std::exception& e) {
            throw Error(f.where(a) + e.what());
        }
        // The batch's own settings come first, so the asset's `set` can still override them.
        int writes = 0, previews = 0;
        for (const auto& n : pl.nodes) {
            writes += n.stage == "mesh.write";
            previews += n.stage == "eval.preview";
        }
        for (const auto& n : pl.nodes) {
            if (n.stage == "views.load") p.sets.push_back(n.id + ".manifest=" + p.manifest.string());
            if (n.stage == "mesh.write" && writes == 1) {
                // The glTF binary the review page shows, unless the pipeline writes a USD package.
                p.mesh_file = a.name + (lower_extension(param_text(n, "path")) == ".usdz" ? ".usdz" : ".glb");
                p.sets.push_back(n.id + ".path=" + p.mesh_file);
            }
            if (n.stage == "eval.preview" && previews == 1) {
                p.preview_file = a.name + ".preview.png";
                p.sets.push_back(n.id + ".path=" + p.preview_file);
            }
        }
        p.sets.insert(p.sets.end(), a.sets.begin(), a.sets.end());
        double resolution = 256;
        try {
            for (const auto& s : p.sets) pl.apply_override(s);
        } catch (const std::exception& e) {
            throw Error(f.where(a) + e.what());
        }
        for (const auto& n : pl.nodes) {
            if (n.stage == "mesh.write" && writes == 1) p.mesh_file = param_text(n, "path");
            if (n.stage == "eval.preview" && previews == 1) p.preview_file = param_text(n, "path");
            if (n.stage != "hull.carve") continue;
            try {
                const std::string r = param_text(n, "resolution");
                if (!r.empty()) resolution = std::max(resolution, std::stod(r));
            } catch (const std::exception&) {}
        }
        if (!batch_mesh(p.mesh_file)) p.mesh_file.clear();
        p.memory_mib = a.memory_mib ? *a.memory_mib : memory_estimate_mib(manifest_pixels(p.manifest), resolution);
        p.inputs_hash = inputs_hash(p, a.pipeline);
        p.argv = {exe, "run", a.pipeline.string()};
        for (const auto& s : p.sets) {
            p.argv.push_back("--set");
            p.argv.push_back(s);
        }
        const std::vector<std::string> tail = {"--report", "run.json",        "--label", "inputs_hash=" + p.inputs_hash,
                                               "--label",  "asset=" + a.name, "-q"};
        p.argv.insert(p.argv.end(), tail.begin(), tail.end());
        plans.push_back(std::move(p));
    }
    return plans;
}

bool up_to_date(const AssetPlan& p) {
    const fs::path report = p.dir / "run.json";
    if (!fs::is_regular_file(report)) return false;
    try {
        const json j = json::parse(read_bytes(report));
        if (j.value("/labels/inputs_hash"_json_pointer, std::string()) != p.inputs_hash) return false;
        for (const auto& o : j.at("outputs")) {
            fs::path f = o.get<std::string>();
            if (f.is_relative()) f = p.dir / f;
            if (!fs::exists(f)) return false;
        }
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

void write_task_script(const AssetPlan& p) {
    fs::create_directories(p.dir);
    std::error_code ec;
    fs::remove(p.dir / "exit-status", ec);
    std::string cmd;
    for (const auto& a : p.argv) cmd += (cmd.empty() ? "" : " ") + shell_quote(a);
    std::ostringstream s;
    s << "#!/bin/sh\n"
      << "# Written by conceptmesh batch: runs asset " << p.spec->name << " and records how it ended.\n"
      << "cd " << shell_quote(p.dir.string()) << " || exit 1\n"
      << "rm -f exit-status\n"
      << "start=$(date +%s.%N)\n"
      << cmd << " > log.txt 2>&1\n"
      << "rc=$?\n"
      << "printf '%s %s %s\\n' \"$rc\" \"$start\" \"$(date +%s.%N)\" > exit-status.part && mv exit-status.part "
         "exit-status\n"
      << "exit $rc\n";
    write_file_atomic(p.dir / "task.sh", s.str());
}

AssetResult read_result(const AssetPlan& p, bool skipped) {
    AssetResult r;
    r.name = p.spec->name;
    r.dir = p.dir;
    r.status = skipped ? "skipped" : "failed";
    // The task's wall time, process start included; a skipped asset keeps its last run's.
    std::ifstream st(p.dir / "exit-status");
    int rc = -1;
    double t0 = 0, t1 = 0;
    if (st >> rc >> t0 >> t1) {
        r.seconds = t1 - t0;
        if (rc == 0 && !skipped) r.status = "ok";
    }
    if (!skipped) {
        if (r.status == "failed") {
            // The run's own one-line cause: the last error line of its log.
            std::ifstream log(p.dir / "log.txt");
            std::string line;
            const std::string tag = "conceptmesh: error: ";
            while (std::getline(log, line))
                if (line.rfind(tag, 0) == 0) r.cause = line.substr(tag.size());
            if (r.cause.empty())
                r.cause = rc < 0 ? "the task ended without recording its status (killed by the engine: time or "
                                   "memory limit?); see " +
                                       (p.dir / "log.txt").string()
                                 : "exited with status " + std::to_string(rc) + " without a message; see " +
                                       (p.dir / "log.txt").string();
            return r;
        }
    }
    try {
        const json j = json::parse(read_bytes(p.dir / "run.json"));
        if (r.seconds <= 0) r.seconds = j.value("seconds", 0.0);
        r.peak_mib = double(j.value("peak_rss_bytes", std::size_t(0))) / 1048576.0;
        for (const auto& n : j.at("nodes")) {
            const auto& m = n.at("metrics");
            const std::string stage = n.value("stage", "");
            if (stage == "mesh.write" && m.contains("faces")) r.faces = m["faces"].get<double>();
            if ((stage == "eval.silhouette_error" || (stage == "eval.preview" && r.xor_pct < 0)) &&
                m.contains("xor_pct"))
                r.xor_pct = m["xor_pct"].get<double>();
            if (stage == "eval.silhouette_error" && m.contains("views")) {
                r.view_xor.clear();
                for (const auto& v : m["views"]) r.view_xor.emplace_back(v.value("view", ""), v.value("xor_pct", 0.0));
            }
        }
    } catch (const std::exception& e) {
        r.status = "failed";
        r.cause = "the run report " + (p.dir / "run.json").string() + " cannot be read: " + e.what();
    }
    return r;
}

} // namespace cm::batch
