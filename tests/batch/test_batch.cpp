// conceptmesh batch end to end: ASSETS.yaml checks, --scan, the local engine and --resume, the
// Slurm engine on a one-node cluster (tests/batch/slurm_cluster.sh), and the review page in a
// headless Chromium.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sys/wait.h>
#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include "batch/keys.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "pipeline/pipeline.h"
#include "pipeline/yaml_values.h"
#include "support/shapes.h"
#include "support/test_support.h"

using namespace cm;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Shell {
    int exit_code = 0;
    std::string out;
};
// Runs a shell command line; stdout and stderr together.
Shell sh(const std::string& cmd) {
    static int n = 0;
    const fs::path f =
        fs::temp_directory_path() / ("cm-batch-sh-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    const int st = std::system(("{ " + cmd + "; } >'" + f.string() + "' 2>&1 </dev/null").c_str());
    Shell r{WIFEXITED(st) ? WEXITSTATUS(st) : -1, test::read_text(f)};
    fs::remove(f);
    return r;
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

const std::vector<std::string> kGood = {"box", "sphere", "crossing", "lopsided", "bumpy", "capsule"};

// Six small assets drawn in code (shapes written as OBJ, drawn by render-views at 128 px) and
// a seventh, "broken", whose front drawing is cut short. Made once per test process.
const fs::path& kit() {
    static test::TempDir dir("batch-kit");
    static const bool made = [] {
        std::map<std::string, Mesh> shapes;
        shapes["box"] = test::make_box({-1.0f, 0.0f, -0.5f}, {1.0f, 1.5f, 0.5f});
        shapes["sphere"] = test::make_sphere({0, 0, 0}, 1.0f, 3);
        shapes["crossing"] = test::make_crossing_boxes();
        shapes["lopsided"] = test::make_lopsided();
        Mesh bumpy = test::make_sphere({0, 0, 0}, 1.0f, 3);
        test::add_radial_noise(bumpy, {0, 0, 0}, 0.15f, 7);
        shapes["bumpy"] = bumpy;
        Mesh capsule = test::make_box({-0.4f, -1.0f, -0.4f}, {0.4f, 1.0f, 0.4f});
        test::append_mesh(capsule, test::make_sphere({0, 1.0f, 0}, 0.4f, 3));
        shapes["capsule"] = capsule;
        shapes["broken"] = test::make_box({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f});
        for (const auto& [name, m] : shapes) {
            write_mesh(m, dir / (name + ".obj"));
            auto r = test::run_cli("render-views '" + (dir / (name + ".obj")).string() + "' -o '" +
                                   (dir / name).string() + "' --size 128 -q");
            if (r.exit_code != 0) ADD_FAILURE() << r.err;
        }
        const std::string front = test::read_text(dir / "broken" / "front.png");
        test::write_text(dir / "broken" / "front.good.png", front);
        test::write_text(dir / "broken" / "front.png", front.substr(0, front.size() / 3));
        return true;
    }();
    (void)made;
    return dir.path();
}

std::string assets_yaml(const std::string& extra_top = "") {
    std::string y = "batch: kit\npipeline: '" + (test::source_dir() / "pipelines" / "paper.yaml").string() +
                    "'\nset: {hull.resolution: 40}\n" + extra_top + "assets:\n";
    for (const auto& n : kGood) y += "  - name: " + n + "\n    views: " + n + "/views.yaml\n";
    y += "  - name: broken\n    views: broken/views.yaml\n";
    return y;
}

// A copy of the kit with its ASSETS.yaml, for a test to change as it likes.
fs::path copy_kit(const test::TempDir& dir) {
    fs::copy(kit(), dir / "kit", fs::copy_options::recursive);
    test::write_text(dir / "kit" / "assets.yaml", assets_yaml());
    return dir / "kit" / "assets.yaml";
}

json read_json(const fs::path& f) { return json::parse(test::read_text(f)); }

std::map<std::string, json> by_asset(const json& report) {
    std::map<std::string, json> m;
    for (const auto& a : report.at("assets")) m[a.at("asset").get<std::string>()] = a;
    return m;
}

// The checks every finished batch of the kit passes: six meshes, one failure with its cause.
void expect_kit_outcome(const fs::path& out, const std::string& status_of_good) {
    const json report = read_json(out / "batch-report.json");
    auto a = by_asset(report);
    ASSERT_EQ(a.size(), 7u);
    for (const auto& n : kGood) {
        EXPECT_EQ(a[n]["status"], status_of_good) << n;
        EXPECT_GT(a[n]["faces"].get<double>(), 50) << n;
        EXPECT_LT(a[n]["xor_pct"].get<double>(), 10.0) << n;
        EXPECT_TRUE(fs::is_regular_file(out / n / (n + ".glb"))) << n;
        const json run = read_json(out / n / "run.json");
        EXPECT_EQ(run["labels"]["inputs_hash"], a[n]["inputs_hash"]) << n;
        EXPECT_EQ(run["labels"]["asset"], n);
    }
    EXPECT_EQ(a["broken"]["status"], "failed");
    const std::string cause = a["broken"]["cause"].get<std::string>();
    EXPECT_NE(cause.find("cannot read image"), std::string::npos) << cause;
    EXPECT_NE(cause.find("broken/front.png"), std::string::npos) << cause;
    EXPECT_FALSE(fs::exists(out / "broken" / "broken.glb"));
}

std::string mtime_of(const fs::path& f) { return std::to_string(fs::last_write_time(f).time_since_epoch().count()); }

// One-node Slurm cluster for the test's lifetime, or the reason it cannot start.
class SlurmCluster {
public:
    explicit SlurmCluster(const fs::path& dir) : dir_(dir) {
        const Shell r = sh("'" + script() + "' start '" + dir_.string() + "'");
        up_ = r.exit_code == 0;
        why_ = r.out;
        if (up_) ::setenv("SLURM_CONF", (dir_ / "slurm.conf").c_str(), 1);
    }
    ~SlurmCluster() {
        sh("'" + script() + "' stop '" + dir_.string() + "'");
        ::unsetenv("SLURM_CONF");
    }
    bool up() const { return up_; }
    const std::string& why() const { return why_; }

private:
    static std::string script() { return (test::source_dir() / "tests" / "batch" / "slurm_cluster.sh").string(); }
    fs::path dir_;
    bool up_ = false;
    std::string why_;
};

} // namespace

TEST(Batch, FileErrorsNameTheFileLineAndAsset) {
    test::TempDir dir("batch-errors");
    const fs::path assets = copy_kit(dir);
    const std::string good = assets_yaml();
    struct Case {
        std::string yaml, expect;
    };
    const std::vector<Case> cases = {
        {good + "  - name: box2\n    views: box/views.yaml\n    veiws: x\n",
         ":21: asset \"box2\": unknown key \"veiws\""},
        {good + "  - name: box\n    views: box/views.yaml\n",
         ":19: asset \"box\": the name is given twice (first on line 5)"},
        {good + "  - name: ghost\n    views: ghost/views.yaml\n",
         ":20: asset \"ghost\": views \"ghost/views.yaml\" does not exist"},
        {good + "  - name: both\n    views: box/views.yaml\n    sheet: {image: box/front.png, views: [front]}\n",
         ":19: asset \"both\": give either views"},
        {good + "  - name: ../up\n    views: box/views.yaml\n", ":19: asset \"../up\": a name must be letters"},
        {good + "  - name: m\n    views: box/views.yaml\n    memory_mib: -3\n", ":19: asset \"m\": memory_mib must be"},
        {"pipelin: x.yaml\n" + good, ":1: unknown key \"pipelin\""},
        {"output: flat\n" + good, ":1: output must be a relative folder pattern holding {name}"},
        {"assets: []\n", ":1: assets must be a non-empty list"},
        {"assets:\n  - name: x\n    views: box/views.yaml\n", ":2: asset \"x\": no pipeline"},
        {good + "  - name: s\n    views: box/views.yaml\n    set: [hull.resolution]\n",
         "set: each entry must be NODE.PARAM=VALUE"},
        {"assets: [\n", "assets.yaml:"},
    };
    for (const auto& c : cases) {
        test::write_text(assets, c.yaml);
        auto r = test::run_cli("batch '" + assets.string() + "' --dry-run -o '" + (dir / "out").string() + "'");
        EXPECT_EQ(r.exit_code, 1) << c.yaml;
        EXPECT_EQ(lines(r.err), 1u) << r.err;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << "expected \"" << c.expect << "\" in: " << r.err;
        EXPECT_NE(r.err.find(assets.string()), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out")) << c.yaml;
    }
}

TEST(Batch, DryRunValidatesEveryAssetsPipeline) {
    test::TempDir dir("batch-dry");
    const fs::path assets = copy_kit(dir);
    auto r = test::run_cli("batch '" + assets.string() + "' --dry-run -o '" + (dir / "out").string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const auto& n : kGood) EXPECT_NE(r.out.find(n + ": valid"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "out" / "box" / "box.glb"));
    // A parameter out of range for one asset: that asset is named, with its line, the node and the stage.
    test::write_text(assets,
                     assets_yaml() + "  - name: coarse\n    views: box/views.yaml\n    set: {hull.resolution: 3}\n");
    r = test::run_cli("batch '" + assets.string() + "' --dry-run -o '" + (dir / "out").string() + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("assets.yaml:19: asset \"coarse\": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("node \"hull\" (hull.carve): resolution must be in [8, 16384]"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("box: valid"), std::string::npos) << r.out;
}

TEST(Batch, SchemaMatchesTheReader) {
    const json schema = read_json(test::source_dir() / "schemas" / "batch.schema.json");
    std::set<std::string> top, asset;
    for (const auto& [k, v] : schema.at("properties").items()) top.insert(k);
    for (const auto& [k, v] : schema.at("definitions").at("asset").at("properties").items()) asset.insert(k);
    EXPECT_EQ(top, std::set<std::string>(batch::kTopKeys.begin(), batch::kTopKeys.end()));
    EXPECT_EQ(asset, std::set<std::string>(batch::kAssetKeys.begin(), batch::kAssetKeys.end()));

    valijson::Schema s;
    valijson::SchemaParser parser;
    valijson::adapters::NlohmannJsonAdapter sa(schema);
    parser.populateSchema(sa, s);
    auto valid = [&](const std::string& yaml) {
        const json doc = yaml_to_json(YAML::Load(yaml));
        valijson::adapters::NlohmannJsonAdapter da(doc);
        return valijson::Validator().validate(s, da, nullptr);
    };
    EXPECT_TRUE(valid(assets_yaml()));
    EXPECT_TRUE(valid("assets:\n  - name: s\n    sheet: {image: s.png, views: [front, right]}\n    memory_mib: 900\n"));
    EXPECT_FALSE(valid(assets_yaml() + "  - name: x\n    views: a.yaml\n    veiws: b\n"));
    EXPECT_FALSE(valid("assets:\n  - name: x\n"));
    EXPECT_FALSE(valid("output: flat\n" + assets_yaml()));
}

TEST(Batch, ScanWritesAnAssetsFileForEveryFolderWithAManifest) {
    test::TempDir dir("batch-scan");
    fs::copy(kit(), dir / "shows", fs::copy_options::recursive);
    fs::create_directories(dir / "shows" / "notes"); // no manifest: left out
    const std::string pipeline = (test::source_dir() / "pipelines" / "paper.yaml").string();
    auto r = test::run_cli("batch --scan '" + (dir / "shows").string() + "' --pipeline '" + pipeline + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("(7 assets)"), std::string::npos) << r.out;
    const std::string y = test::read_text(dir / "shows" / "assets.yaml");
    for (const auto& n : kGood) EXPECT_NE(y.find("name: " + n + "\n"), std::string::npos) << y;
    EXPECT_EQ(y.find("notes"), std::string::npos) << y;
    r = test::run_cli("batch '" + (dir / "shows" / "assets.yaml").string() + "' --dry-run -o '" + (dir / "o").string() +
                      "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(lines(r.out), 7u) << r.out;
    r = test::run_cli("batch --scan '" + (dir / "shows" / "notes").string() + "' --pipeline '" + pipeline + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("no subfolder holds a views.yaml"), std::string::npos) << r.err;
}

TEST(Batch, LocalRunsEachAssetAndResumeRunsOnlyWhatChanged) {
    test::TempDir dir("batch-local");
    const fs::path assets = copy_kit(dir);
    const fs::path out = dir / "out";
    auto r = test::run_cli("batch '" + assets.string() + "' --jobs 2 -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 1) << r.err; // one asset failed
    expect_kit_outcome(out, "ok");
    // The table: a line per asset, then the counts and the failure's cause.
    EXPECT_NE(r.out.find("6 ok, 0 up to date, 1 failed"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("FAILED broken: "), std::string::npos) << r.out;
    for (const auto& n : kGood) EXPECT_NE(r.err.find(n + ": done"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("broken: FAILED"), std::string::npos) << r.err;
    // The meshes are what `conceptmesh run` makes of the same asset alone.
    fs::create_directories(dir / "alone");
    auto alone = test::run_cli("run '" + (test::source_dir() / "pipelines" / "paper.yaml").string() +
                                   "' --set views.manifest=../kit/box/views.yaml --set hull.resolution=40 --set "
                                   "write.path=box.glb --set preview.path=box.png -q",
                               dir / "alone");
    ASSERT_EQ(alone.exit_code, 0) << alone.err;
    const std::string box = test::read_text(out / "box" / "box.glb");
    EXPECT_TRUE(box == test::read_text(dir / "alone" / "box.glb"));
    std::map<std::string, std::string> stamps;
    for (const auto& n : kGood) stamps[n] = mtime_of(out / n / "run.json");

    // Fixed: only the broken asset runs again.
    fs::copy_file(dir / "kit" / "broken" / "front.good.png", dir / "kit" / "broken" / "front.png",
                  fs::copy_options::overwrite_existing);
    r = test::run_cli("batch '" + assets.string() + "' --resume -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.err.find("1 to run, 6 up to date"), std::string::npos) << r.err;
    auto a = by_asset(read_json(out / "batch-report.json"));
    EXPECT_EQ(a["broken"]["status"], "ok");
    EXPECT_TRUE(fs::is_regular_file(out / "broken" / "broken.glb"));
    for (const auto& n : kGood) {
        EXPECT_EQ(a[n]["status"], "skipped") << n;
        EXPECT_EQ(mtime_of(out / n / "run.json"), stamps[n]) << n << " ran again";
    }
    // A parameter changed for one asset: that one runs again; a mesh removed: that one too.
    std::string y = test::read_text(assets);
    y.replace(y.find("views: sphere/views.yaml"), 24, "views: sphere/views.yaml\n    set: {hull.resolution: 48}");
    test::write_text(assets, y);
    fs::remove(out / "box" / "box.glb");
    r = test::run_cli("batch '" + assets.string() + "' --resume -q -o '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    a = by_asset(read_json(out / "batch-report.json"));
    EXPECT_EQ(a["sphere"]["status"], "ok");
    EXPECT_EQ(a["box"]["status"], "ok");
    EXPECT_EQ(a["crossing"]["status"], "skipped");
    EXPECT_EQ(test::read_text(out / "box" / "box.glb"), box);
}

TEST(Batch, SlurmArrayJobMatchesTheLocalEngineByteForByte) {
    test::TempDir dir("batch-slurm");
    SlurmCluster cluster(dir / "cluster");
    if (!cluster.up()) GTEST_SKIP() << "no Slurm cluster for this test: " << cluster.why();
    const fs::path assets = copy_kit(dir);
    const fs::path outs = dir / "slurm", outl = dir / "local";
    auto r = test::run_cli("batch '" + assets.string() + "' --engine slurm --jobs 3 --time 10:00 -o '" + outs.string() +
                           "'");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    expect_kit_outcome(outs, "ok");
    EXPECT_NE(r.err.find("submitted slurm job"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("7/7 assets done, 1 failed"), std::string::npos) << r.err;
    const std::string sbatch = test::read_text(outs / ".batch" / "sbatch.txt");
    EXPECT_NE(sbatch.find("--array=0-6%3"), std::string::npos) << sbatch;
    EXPECT_NE(sbatch.find("--time=10:00"), std::string::npos) << sbatch;
    EXPECT_NE(sbatch.find("--mem="), std::string::npos) << sbatch;
    for (const auto& n : kGood) EXPECT_TRUE(fs::is_regular_file(outs / n / "log.txt")) << n;
    EXPECT_NE(test::read_text(outs / "broken" / "log.txt").find("cannot read image"), std::string::npos);

    // Fixed and resumed, detached: only the broken asset is submitted; --status gathers.
    fs::copy_file(dir / "kit" / "broken" / "front.good.png", dir / "kit" / "broken" / "front.png",
                  fs::copy_options::overwrite_existing);
    r = test::run_cli("batch '" + assets.string() + "' --engine slurm --resume --detach -o '" + outs.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("1 to run, 6 up to date"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("conceptmesh batch --status"), std::string::npos) << r.out;
    EXPECT_NE(test::read_text(outs / ".batch" / "sbatch.txt").find("--array=0-0 "), std::string::npos);
    int code = 75;
    for (int i = 0; i < 240 && code == 75; ++i) {
        r = test::run_cli("batch --status '" + outs.string() + "' -q");
        code = r.exit_code;
        if (code == 75) std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    ASSERT_EQ(code, 0) << r.out << r.err;
    auto a = by_asset(read_json(outs / "batch-report.json"));
    EXPECT_EQ(a["broken"]["status"], "ok");
    for (const auto& n : kGood) EXPECT_EQ(a[n]["status"], "skipped") << n;

    // The same batch through the local engine: byte-identical meshes.
    r = test::run_cli("batch '" + assets.string() + "' -q -o '" + outl.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const auto& n : kGood) {
        const std::string s = test::read_text(outs / n / (n + ".glb")), l = test::read_text(outl / n / (n + ".glb"));
        EXPECT_FALSE(s.empty()) << n;
        EXPECT_TRUE(s == l) << n << ": the Slurm and local meshes differ";
    }
    EXPECT_TRUE(test::read_text(outs / "broken" / "broken.glb") == test::read_text(outl / "broken" / "broken.glb"));
}

TEST(Batch, SlurmRefusalIsOneLine) {
    test::TempDir dir("batch-slurm-refused");
    SlurmCluster cluster(dir / "cluster");
    if (!cluster.up()) GTEST_SKIP() << "no Slurm cluster for this test: " << cluster.why();
    const fs::path assets = copy_kit(dir);
    auto r = test::run_cli("batch '" + assets.string() + "' --engine slurm --partition nosuch -o '" +
                           (dir / "o").string() + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(lines(r.err), 2u) << r.err; // the plan line, then the error
    EXPECT_NE(r.err.find("sbatch refused the batch"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nosuch"), std::string::npos) << r.err;
}

// A pipeline that writes a USD package keeps its format in a batch: each asset gets
// <name>.usdz, listed in the report and linked from its card, which has no 3D view (the
// page's three.js reads glTF only); an asset's own `set` may ask for one too.
TEST(Batch, APipelineWritingUsdzGivesEachAssetAUsdz) {
    test::TempDir dir("batch-usdz");
    const fs::path assets = copy_kit(dir);
    std::string pipeline = test::read_text(test::source_dir() / "pipelines" / "paper.yaml");
    pipeline.replace(pipeline.find("out/spot.obj"), 12, "out/spot.usdz");
    test::write_text(dir / "usdz.yaml", pipeline);
    test::write_text(assets, "pipeline: '" + (dir / "usdz.yaml").string() +
                                 "'\nset: {hull.resolution: 40}\nassets:\n  - name: box\n    views: box/views.yaml\n"
                                 "  - name: sphere\n    views: sphere/views.yaml\n    pipeline: '" +
                                 (test::source_dir() / "pipelines" / "paper.yaml").string() +
                                 "'\n    set: {write.path: ball.usdz}\n");
    const fs::path out = dir / "out";
    auto r = test::run_cli("batch '" + assets.string() + "' -q -o '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    auto a = by_asset(read_json(out / "batch-report.json"));
    EXPECT_EQ(a["box"]["mesh"], "box/box.usdz");
    EXPECT_EQ(a["sphere"]["mesh"], "sphere/ball.usdz");
    EXPECT_TRUE(fs::is_regular_file(out / "box" / "box.usdz"));
    EXPECT_FALSE(fs::exists(out / "box" / "box.glb"));
    if (!fs::is_regular_file(out / "index.html")) GTEST_SKIP() << "no review page here (three.js missing)";
    const std::string page = test::read_text(out / "index.html");
    EXPECT_HAS(page, "<a href=\"box/box.usdz\">mesh</a>");
    EXPECT_HAS(page, "<a href=\"sphere/ball.usdz\">mesh</a>");
    EXPECT_HAS(page, "no 3D view of a .usdz");
    EXPECT_EQ(page.find("data-model="), std::string::npos) << page;
    EXPECT_FALSE(fs::exists(out / "box" / "model.js"));
}

TEST(Batch, ReviewPageDrawsEveryModelInHeadlessChromium) {
    if (sh("command -v chromium").exit_code != 0) GTEST_SKIP() << "chromium is not installed (Debian: chromium)";
    test::TempDir dir("batch-page");
    const fs::path assets = copy_kit(dir);
    std::string y = "batch: kit\npipeline: '" + (test::source_dir() / "pipelines" / "paper.yaml").string() +
                    "'\nset: {hull.resolution: 40}\nassets:\n";
    for (const char* n : {"box", "sphere", "broken"})
        y += std::string("  - name: ") + n + "\n    views: " + n + "/views.yaml\n";
    test::write_text(assets, y);
    const fs::path out = dir / "out";
    auto r = test::run_cli("batch '" + assets.string() + "' -q -o '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 1) << r.err;
    ASSERT_TRUE(fs::is_regular_file(out / "three" / "three.min.js"));
    ASSERT_TRUE(fs::is_regular_file(out / "three" / "GLTFLoader.js"));

    // Opened from disk as a user does: file://, no server.
    const std::string flags =
        "chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
        "--user-data-dir='" +
        (dir / "profile").string() + "' --window-size=1200,900 --virtual-time-budget=15000 ";
    const std::string url = "'file://" + (out / "index.html").string() + "'";
    auto count_drawn = [](const std::string& d) {
        std::size_t n = 0;
        for (std::size_t at = 0; (at = d.find("data-drawn=\"yes\"", at)) != std::string::npos; ++at) ++n;
        return n;
    };
    // Chromium's virtual time can run out on a busy machine before software WebGL is up:
    // a page that has not drawn yet is asked again, an error is not.
    Shell dom;
    std::size_t drawn = 0;
    for (int attempt = 0; attempt < 3 && drawn < 2; ++attempt) {
        dom = sh(flags + "--enable-logging=stderr --v=0 --dump-dom " + url);
        drawn = count_drawn(dom.out);
        if (dom.out.find("data-errors=\"") != std::string::npos) break;
    }
    ASSERT_NE(dom.out.find("</html>"), std::string::npos) << dom.out;
    EXPECT_EQ(dom.out.find("data-errors=\""), std::string::npos) << "the page recorded errors: " << dom.out;
    EXPECT_EQ(dom.out.find("Uncaught"), std::string::npos) << dom.out;
    EXPECT_EQ(dom.out.find(":ERROR:CONSOLE"), std::string::npos) << dom.out;
    EXPECT_EQ(drawn, 2u) << "every model drawn (the broken asset has none): " << dom.out;
    EXPECT_NE(dom.out.find("cannot read image"), std::string::npos); // the failure's card says why

    // The screenshot shows the models: inside the 3D views' background, pixels of another colour.
    const Shell shot = sh(flags + "--screenshot='" + (dir / "page.png").string() + "' " + url);
    ASSERT_TRUE(fs::is_regular_file(dir / "page.png")) << shot.out;
    const Image img = read_image(dir / "page.png");
    int x0 = img.width, y0 = img.height, x1 = -1, y1 = -1;
    auto px = [&](int x, int yy, int c) { return int(img.at(x, yy, c) * 255 + 0.5f); };
    auto is_bg = [&](int x, int yy) {
        return std::abs(px(x, yy, 0) - 0x2a) <= 1 && std::abs(px(x, yy, 1) - 0x2f) <= 1 &&
               std::abs(px(x, yy, 2) - 0x38) <= 1;
    };
    for (int yy = 0; yy < img.height; ++yy)
        for (int x = 0; x < img.width; ++x)
            if (is_bg(x, yy)) {
                x0 = std::min(x0, x), y0 = std::min(y0, yy), x1 = std::max(x1, x), y1 = std::max(y1, yy);
            }
    ASSERT_GT(x1, x0) << "no 3D view on the screenshot";
    std::size_t model = 0, area = 0;
    for (int yy = y0; yy <= y1; ++yy)
        for (int x = x0; x <= x1; ++x) {
            ++area;
            const int lum = px(x, yy, 0) + px(x, yy, 1) + px(x, yy, 2);
            model += !is_bg(x, yy) && lum > 3 * 0x50; // lit clay, not the dark background
        }
    EXPECT_GT(double(model) / double(area), 0.02) << "the 3D views look blank";
}

TEST(Batch, WithoutThreeJsTheSummaryIsStillWritten) {
    test::TempDir dir("batch-nothree");
    const fs::path assets = copy_kit(dir);
    test::write_text(assets, "pipeline: '" + (test::source_dir() / "pipelines" / "paper.yaml").string() +
                                 "'\nset: {hull.resolution: 40}\nassets:\n  - name: box\n    views: box/views.yaml\n");
    ::setenv("CONCEPTMESH_THREE_JS", (dir / "nothing-here").c_str(), 1);
    auto r = test::run_cli("batch '" + assets.string() + "' -q -o '" + (dir / "out").string() + "'");
    ::unsetenv("CONCEPTMESH_THREE_JS");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("no review page: the review page needs three.js"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "batch-report.json"));
    EXPECT_FALSE(fs::exists(dir / "out" / "index.html"));
}

TEST(Batch, AStoppedBatchStopsItsRunsAndLeavesNoMesh) {
    test::TempDir dir("batch-stop");
    const fs::path assets = copy_kit(dir);
    // Runs long enough (a finer grid) that the stop surely lands while they run.
    std::string yaml = test::read_text(assets);
    const std::string coarse = "hull.resolution: 40";
    yaml.replace(yaml.find(coarse), coarse.size(), "hull.resolution: 360");
    test::write_text(assets, yaml);
    const fs::path out = dir / "out";
    // SIGTERM to the batch alone (as a farm's wrapper or `kill` sends it), once its first runs
    // have started: they stop too.
    const Shell r = sh("'" + std::string(CM_EXE) + "' batch '" + assets.string() + "' --jobs 2 -o '" + out.string() +
                       "' & pid=$!; for i in $(seq 600); do ls '" + out.string() +
                       "'/*/log.txt >/dev/null 2>&1 && break; sleep 0.1; done; sleep 0.5; kill -TERM $pid; wait $pid; "
                       "echo \"exit $?\"; sleep 6");
    EXPECT_NE(r.out.find("exit 143"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(SIGTERM); no output was written"), std::string::npos) << r.out;
    for (const auto& n : kGood) EXPECT_FALSE(fs::exists(out / n / (n + ".glb"))) << n << ": a run went on";
    EXPECT_FALSE(fs::exists(out / "batch-report.json"));
}
