// sketch_views IN/views.yaml OUT_DIR [--seed N] [--close-gaps G]: turns the masks of a
// render-views manifest (style mask) into sketchy line drawings, as an artist hands them
// over: an outline stroke 1-2 px wide drawn just inside each silhouette, broken at random
// points (breaks 1-3 px along the stroke), dark ink on off-white paper. Writes
// OUT_DIR/<view>.png and OUT_DIR/views.yaml with the same cameras and bounds (and
// close_gaps: G on every view when given), so `conceptmesh compare MODEL OUT_DIR/views.yaml`
// measures the silhouettes views.load extracts from the drawings.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "geometry/distance_transform.h"
#include "io/image_io.h"
#include "io/manifest.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

// The drawing of one mask: stroke width and breaks from `rng`.
Image sketch(const Image& mask, std::mt19937& rng) {
    const int w = mask.width, h = mask.height;
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> in(n), out(n);
    for (std::size_t i = 0; i < n; ++i) {
        in[i] = mask.pixels[i * 4] >= 0.5f;
        out[i] = !in[i];
    }
    const std::vector<float> to_out = squared_edt(out, w, h);
    // Stroke width wavers between 1 and 2 px along the outline.
    std::uniform_real_distribution<double> phase(0, 6.283);
    const double p1 = phase(rng), p2 = phase(rng);
    std::vector<char> ink(n, 0);
    std::vector<int> rim;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            if (!in[i]) continue;
            const double width = 1.5 + 0.5 * std::sin(0.031 * x + p1) * std::cos(0.027 * y + p2);
            ink[i] = std::sqrt(to_out[i]) <= width;
            if (to_out[i] <= 1.0f) rim.push_back(int(i));
        }
    // Breaks: one per ~80 px of outline, 1-3 px wide along the local tangent.
    std::uniform_int_distribution<std::size_t> pick(0, rim.empty() ? 0 : rim.size() - 1);
    std::uniform_real_distribution<double> gap(1.0, 3.0);
    const std::size_t breaks = rim.size() / 80 + 1;
    std::vector<std::pair<int, int>> placed;
    for (std::size_t b = 0; b < breaks && !rim.empty(); ++b) {
        const int c = rim[pick(rng)], cx = c % w, cy = c / w;
        // Breaks at least 20 px apart: two breaks side by side would make one wider than 3 px.
        bool crowded = false;
        for (const auto& [bx, by] : placed) crowded = crowded || std::hypot(bx - cx, by - cy) < 20;
        if (crowded) continue;
        placed.push_back({cx, cy});
        // The break: the outline pixels within `half` of the centre, and every stroke pixel
        // whose nearest outline pixel is one of them (so it cuts the stroke across, g wide
        // along the outline, whatever the outline's shape there).
        const double half = 0.5 * gap(rng);
        std::vector<std::pair<int, int>> near_rim;
        for (int dy = -8; dy <= 8; ++dy)
            for (int dx = -8; dx <= 8; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= w || y >= h) continue;
                const std::size_t i = std::size_t(y) * w + x;
                if (in[i] && to_out[i] <= 1.0f) near_rim.push_back({dx, dy});
            }
        std::vector<std::size_t> erase;
        for (int dy = -5; dy <= 5; ++dy)
            for (int dx = -5; dx <= 5; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= w || y >= h || !ink[std::size_t(y) * w + x]) continue;
                double best = 1e9, to_centre = 1e9;
                for (const auto& [rx, ry] : near_rim) {
                    const double d = std::hypot(rx - dx, ry - dy);
                    if (d < best) {
                        best = d;
                        to_centre = std::hypot(rx, ry);
                    }
                }
                if (to_centre < half) erase.push_back(std::size_t(y) * w + x);
            }
        for (std::size_t i : erase) ink[i] = 0;
    }
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.resize(n * 3);
    for (std::size_t i = 0; i < n; ++i) {
        const float paper[3] = {0.97f, 0.96f, 0.93f}, pen[3] = {0.12f, 0.12f, 0.14f};
        for (int k = 0; k < 3; ++k) img.pixels[i * 3 + k] = ink[i] ? pen[k] : paper[k];
    }
    return img;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: sketch_views IN/views.yaml OUT_DIR [--seed N] [--close-gaps G]\n");
        return 2;
    }
    try {
        unsigned seed = 1;
        std::optional<double> close_gaps;
        for (int a = 3; a + 1 < argc; a += 2) {
            const std::string k = argv[a];
            if (k == "--seed") seed = unsigned(std::stoul(argv[a + 1]));
            else if (k == "--close-gaps") close_gaps = std::stod(argv[a + 1]);
            else throw Error("unknown option " + k);
        }
        Manifest m = read_manifest(argv[1]);
        const fs::path out = argv[2];
        fs::create_directories(out);
        std::mt19937 rng(seed);
        for (auto& v : m.views) {
            const fs::path file = out / (v.key + ".png");
            write_image(sketch(read_image(v.image), rng), file);
            v.image = file;
            v.close_gaps = close_gaps;
        }
        m.comment = "Sketchy line drawings of render-views masks (bench/views/sketch_views).";
        write_manifest(out / "views.yaml", m);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sketch_views: %s\n", e.what());
        return 1;
    }
    return 0;
}
