#include "support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "core/error.h"

namespace fs = std::filesystem;

namespace cm::test {

TempDir::TempDir(const std::string& name) {
    static std::mt19937_64 rng(std::random_device{}());
    path_ = fs::path(CM_BINARY_DIR) / "test-tmp" /
            (name + "-" + std::to_string(::getpid()) + "-" + std::to_string(rng() % 1000000));
    fs::remove_all(path_);
    fs::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ec;
    if (!std::getenv("CM_KEEP_TEST_FILES")) fs::remove_all(path_, ec);
}

CommandResult run_cli(const std::string& args, const fs::path& cwd) {
    static std::atomic<int> counter{0};
    const fs::path base =
        fs::temp_directory_path() / ("cm-cli-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    const std::string cmd = "cd '" + cwd.string() + "' && '" + std::string(CM_EXE) + "' " + args + " >'" +
                            base.string() + ".out' 2>'" + base.string() + ".err' </dev/null";
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(base.string() + ".out");
    r.err = read_text(base.string() + ".err");
    fs::remove(base.string() + ".out");
    fs::remove(base.string() + ".err");
    return r;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

void write_text(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary);
    out << text;
}

void write_svg(const fs::path& file, const std::string& attributes, const std::string& shapes) {
    write_text(file, "<svg xmlns=\"http://www.w3.org/2000/svg\" " + attributes + ">\n" + shapes + "\n</svg>\n");
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

fs::path shared_dir() {
    // CONCEPTMESH_SHARED_DIR points the tests at shared data elsewhere (or at none).
    if (const char* dir = std::getenv("CONCEPTMESH_SHARED_DIR")) return fs::path(dir);
    return fs::path(CM_SHARED_DIR);
}
fs::path source_dir() { return fs::path(CM_SOURCE_DIR); }

std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace cm::test
