// The batch's summary: batch-report.json and the table (the review page: review_page.cpp).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "core/error.h"
#include "io/file_commit.h"
#include "io/manifest.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace cm::batch {

namespace {

json result_json(const AssetResult& r, const AssetPlan& p, const fs::path& out_dir) {
    json j;
    j["asset"] = r.name;
    j["status"] = r.status;
    j["folder"] = fs::relative(r.dir, out_dir).string();
    j["seconds"] = r.seconds;
    j["peak_mib"] = r.peak_mib;
    j["memory_estimate_mib"] = p.memory_mib;
    j["faces"] = r.faces >= 0 ? json(r.faces) : json(nullptr);
    j["xor_pct"] = r.xor_pct >= 0 ? json(r.xor_pct) : json(nullptr);
    j["inputs_hash"] = p.inputs_hash;
    if (!p.mesh_file.empty() && r.status != "failed") j["mesh"] = (fs::relative(r.dir, out_dir) / p.mesh_file).string();
    if (r.status == "failed") j["cause"] = r.cause;
    return j;
}

} // namespace

std::string fixed_digits(double v, int digits) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(digits) << v;
    return o.str();
}

std::string write_summary(const AssetsFile& f, const std::vector<AssetPlan>& plans,
                          const std::vector<AssetResult>& results, const fs::path& out_dir, const std::string& engine) {
    const fs::path dir = fs::absolute(out_dir);
    json j;
    j["batch"] = f.name;
    j["assets_file"] = fs::absolute(f.file).string();
    j["engine"] = engine;
    j["conceptmesh_version"] = CONCEPTMESH_VERSION_STRING;
    j["assets"] = json::array();
    std::size_t ok = 0, failed = 0, skipped = 0;
    for (std::size_t i = 0; i < results.size(); ++i) {
        j["assets"].push_back(result_json(results[i], plans[i], dir));
        ok += results[i].status == "ok";
        failed += results[i].status == "failed";
        skipped += results[i].status == "skipped";
    }
    j["counts"] = {{"ok", ok}, {"failed", failed}, {"skipped", skipped}};
    write_file_atomic(dir / "batch-report.json", j.dump(2) + "\n");
    std::string page_warning;
    try {
        write_review_page(plans, results, dir, f.name);
    } catch (const Error& e) {
        page_warning = std::string("no review page: ") + e.what() + "\n";
    }

    std::size_t w = 5;
    for (const auto& r : results) w = std::max(w, r.name.size());
    std::ostringstream t;
    t << std::left << std::setw(int(w)) << "asset"
      << "  " << std::setw(7) << "status" << std::right << std::setw(8) << "wall s" << std::setw(10) << "peak MiB"
      << std::setw(10) << "faces" << std::setw(9) << "xor_pct"
      << "\n";
    for (const auto& r : results) {
        t << std::left << std::setw(int(w)) << r.name << "  " << std::setw(7) << r.status << std::right << std::setw(8)
          << fixed_digits(r.seconds, 2) << std::setw(10) << (r.peak_mib > 0 ? fixed_digits(r.peak_mib, 0) : "-")
          << std::setw(10) << (r.faces >= 0 ? std::to_string(long(r.faces)) : "-") << std::setw(9)
          << (r.xor_pct >= 0 ? fixed_digits(r.xor_pct, 3) : "-") << "\n";
    }
    t << ok << " ok, " << skipped << " up to date, " << failed << " failed\n";
    for (const auto& r : results)
        if (r.status == "failed") t << "FAILED " << r.name << ": " << r.cause << "\n";
    return t.str() + page_warning;
}

} // namespace cm::batch
