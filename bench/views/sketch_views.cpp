// sketch_views IN/views.yaml OUT_DIR [--seed N] [--close-gaps G] [--width W|A:B]
// [--place centre|inside] [--wobble PX]: turns the masks of a render-views manifest (style
// mask) into sketchy line drawings, as an artist hands them over: an anti-aliased outline
// stroke (width wavering between A and B px, 1-2 by default) drawn centred on each
// silhouette's outline, its centre line wobbling up to PX to either side (0.5 by default;
// `--place inside`: half a width inside the outline, as a renderer draws it), broken at
// random points (breaks 1-3 px along the stroke), dark ink on off-white paper. Writes
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

// How the outline is drawn: its width wavering between `width_min` and `width_max` px, its
// centre line `place`d on the true outline (as an artist draws) or just inside it (as a
// renderer's outline), wobbling up to `wobble` px to either side.
struct Pen {
    double width_min = 1.0, width_max = 2.0;
    std::string place = "centre";
    double wobble = 0.5;
};

// Each pixel centre's signed distance to the mask's outline (px, positive inside): the
// distance to the nearest pixel of the other kind less half a pixel.
std::vector<double> signed_distance(const std::vector<char>& in, int w, int h) {
    std::vector<char> out(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = !in[i];
    const std::vector<float> to_out = squared_edt(out, w, h), to_in = squared_edt(in, w, h);
    std::vector<double> s(in.size());
    for (std::size_t i = 0; i < in.size(); ++i)
        s[i] = in[i] ? std::sqrt(double(to_out[i])) - 0.5 : 0.5 - std::sqrt(double(to_in[i]));
    return s;
}

// A smooth wave over the image in [-1, 1]: the sum of two products of sines, periods of
// 60 to 200 px.
struct Wave {
    double a[4], p[4];
    explicit Wave(std::mt19937& rng) {
        std::uniform_real_distribution<double> freq(0.031, 0.105), phase(0, 6.283);
        for (int k = 0; k < 4; ++k) {
            a[k] = freq(rng);
            p[k] = phase(rng);
        }
    }
    double operator()(int x, int y) const {
        return 0.5 * (std::sin(a[0] * x + p[0]) * std::cos(a[1] * y + p[1]) +
                      std::sin(a[2] * y + p[2]) * std::cos(a[3] * x + p[3]));
    }
};

// The ink of one mask's outline, anti-aliased: per pixel the share of it the stroke covers.
std::vector<float> stroke(const std::vector<double>& s, int w, int h, const Pen& pen, std::mt19937& rng) {
    const Wave width_wave(rng), wobble_wave(rng);
    std::vector<float> ink(s.size(), 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const double width = pen.width_min + (pen.width_max - pen.width_min) * (0.5 + 0.5 * width_wave(x, y));
            // The centre line: on the outline, or half a width inside it; then the wobble.
            const double centre = (pen.place == "inside" ? 0.5 * width : 0.0) + pen.wobble * wobble_wave(x, y);
            ink[i] = float(std::clamp(0.5 * width + 0.5 - std::abs(s[i] - centre), 0.0, 1.0));
        }
    return ink;
}

// Breaks: one per ~80 px of outline, 1-3 px wide along the local tangent, at least 20 px
// apart (two side by side would make one wider than 3 px).
void break_stroke(std::vector<float>& ink, const std::vector<double>& s, int w, int h, std::mt19937& rng) {
    std::vector<int> rim; // the outline's inner pixels
    for (std::size_t i = 0; i < s.size(); ++i)
        if (s[i] > 0 && s[i] < 1) rim.push_back(int(i));
    std::uniform_int_distribution<std::size_t> pick(0, rim.empty() ? 0 : rim.size() - 1);
    std::uniform_real_distribution<double> gap(1.0, 3.0);
    const std::size_t breaks = rim.size() / 80 + 1;
    std::vector<std::pair<int, int>> placed;
    for (std::size_t b = 0; b < breaks && !rim.empty(); ++b) {
        const int c = rim[pick(rng)], cx = c % w, cy = c / w;
        bool crowded = false;
        for (const auto& [bx, by] : placed) crowded = crowded || std::hypot(bx - cx, by - cy) < 20;
        if (crowded) continue;
        placed.push_back({cx, cy});
        // The break: the outline pixels within `half` of the centre, and every stroke pixel
        // whose nearest outline pixel is one of them (so it cuts the stroke across, g wide
        // along the outline, whatever the outline's shape there).
        const double half = 0.5 * gap(rng);
        std::vector<std::pair<int, int>> near_rim;
        for (int dy = -10; dy <= 10; ++dy)
            for (int dx = -10; dx <= 10; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= w || y >= h) continue;
                const double si = s[std::size_t(y) * w + x];
                if (si > 0 && si < 1) near_rim.push_back({dx, dy});
            }
        std::vector<std::size_t> erase;
        for (int dy = -6; dy <= 6; ++dy)
            for (int dx = -6; dx <= 6; ++dx) {
                const int x = cx + dx, y = cy + dy;
                if (x < 0 || y < 0 || x >= w || y >= h || ink[std::size_t(y) * w + x] <= 0) continue;
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
}

// The drawing of one mask: the stroke's wavering and breaks from `rng`.
Image sketch(const Image& mask, const Pen& pen, std::mt19937& rng) {
    const int w = mask.width, h = mask.height;
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> in(n);
    for (std::size_t i = 0; i < n; ++i) in[i] = mask.pixels[i * 4] >= 0.5f;
    const std::vector<double> s = signed_distance(in, w, h);
    std::vector<float> ink = stroke(s, w, h, pen, rng);
    break_stroke(ink, s, w, h, rng);
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    img.pixels.resize(n * 3);
    const float paper[3] = {0.97f, 0.96f, 0.93f}, ink_colour[3] = {0.12f, 0.12f, 0.14f};
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) img.pixels[i * 3 + k] = paper[k] + ink[i] * (ink_colour[k] - paper[k]);
    return img;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: sketch_views IN/views.yaml OUT_DIR [--seed N] [--close-gaps G] [--width W|A:B] "
                     "[--place centre|inside] [--wobble PX]\n");
        return 2;
    }
    try {
        unsigned seed = 1;
        std::optional<double> close_gaps;
        Pen pen;
        for (int a = 3; a + 1 < argc; a += 2) {
            const std::string k = argv[a];
            if (k == "--seed") seed = unsigned(std::stoul(argv[a + 1]));
            else if (k == "--close-gaps") close_gaps = std::stod(argv[a + 1]);
            else if (k == "--width") {
                const std::string v = argv[a + 1];
                const std::size_t colon = v.find(':');
                pen.width_min = std::stod(v.substr(0, colon));
                pen.width_max = colon == std::string::npos ? pen.width_min : std::stod(v.substr(colon + 1));
            } else if (k == "--place") pen.place = argv[a + 1];
            else if (k == "--wobble") pen.wobble = std::stod(argv[a + 1]);
            else throw Error("unknown option " + k);
        }
        if (pen.width_min <= 0 || pen.width_max < pen.width_min)
            throw Error("--width must be W or A:B with 0 < A <= B");
        if (pen.place != "centre" && pen.place != "inside") throw Error("--place must be centre or inside");
        Manifest m = read_manifest(argv[1]);
        const fs::path out = argv[2];
        fs::create_directories(out);
        std::mt19937 rng(seed);
        for (auto& v : m.views) {
            const fs::path file = out / (v.key + ".png");
            write_image(sketch(read_image(v.image), pen, rng), file);
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
