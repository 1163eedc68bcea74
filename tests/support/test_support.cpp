#include "support/test_support.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace cm::test {

TempDir::TempDir(const std::string& name) {
    static std::mt19937_64 rng(std::random_device{}());
    path_ = fs::path(CM_BINARY_DIR) / "test-tmp" / (name + "-" + std::to_string(::getpid()) + "-" + std::to_string(rng() % 1000000));
    fs::remove_all(path_);
    fs::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ec;
    if (!std::getenv("CM_KEEP_TEST_FILES")) fs::remove_all(path_, ec);
}

CommandResult run_cli(const std::string& args, const fs::path& cwd) {
    static std::atomic<int> counter{0};
    const fs::path base = fs::temp_directory_path() / ("cm-cli-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    const std::string cmd = "cd '" + cwd.string() + "' && '" + std::string(CM_EXE) + "' " + args + " >'" + base.string() +
                            ".out' 2>'" + base.string() + ".err' </dev/null";
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_text(base.string() + ".out");
    r.err = read_text(base.string() + ".err");
    fs::remove(base.string() + ".out");
    fs::remove(base.string() + ".err");
    return r;
}

void write_text(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary);
    out << text;
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

fs::path shared_dir() { return fs::path(CM_SHARED_DIR); }
fs::path source_dir() { return fs::path(CM_SOURCE_DIR); }

Mesh make_box(Vec3f lo, Vec3f hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Two outward triangles per face.
    const std::array<std::array<std::uint32_t, 4>, 6> quads = {{{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

Mesh make_sphere(Vec3f c, float r, int subdivisions) {
    Mesh m;
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<Vec3f> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                                   {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                   {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                                   {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (auto& v : p) v = normalize(v);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            p.push_back(normalize((p[a] + p[b]) * 0.5f));
            return mid[key] = std::uint32_t(p.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> nf;
        for (const auto& tri : f) {
            const std::uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), cc = midpoint(tri[2], tri[0]);
            nf.push_back({tri[0], a, cc});
            nf.push_back({tri[1], b, a});
            nf.push_back({tri[2], cc, b});
            nf.push_back({a, b, cc});
        }
        f.swap(nf);
    }
    for (auto& v : p) m.positions.push_back(c + v * r);
    m.triangles = f;
    return m;
}

void append_mesh(Mesh& into, const Mesh& part, bool flip) {
    const auto base = std::uint32_t(into.positions.size());
    into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
    for (auto t : part.triangles)
        into.triangles.push_back(flip ? std::array<std::uint32_t, 3>{t[0] + base, t[2] + base, t[1] + base}
                                      : std::array<std::uint32_t, 3>{t[0] + base, t[1] + base, t[2] + base});
}

Mesh make_crossing_boxes() {
    Mesh m = make_box({0, 0, 0}, {1, 1, 1});
    append_mesh(m, make_box({0.5f, 0.3f, 0.6f}, {1.5f, 1.4f, 1.7f}));
    return m;
}

Mesh make_lopsided() {
    Mesh m = make_sphere({0, 0, 0}, 1.0f, 4);
    append_mesh(m, make_box({0.5f, 0.5f, -0.2f}, {1.4f, 1.1f, 0.4f}));
    return m;
}

} // namespace cm::test
