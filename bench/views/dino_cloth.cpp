// dino_cloth DINO_DIR OUT_DIR: the Middlebury dinoSparseRing photographs (white plaster on
// black) with a textured dark cloth composited into the lower part of each frame, touching
// the border and kept clear of the object, for docs/results/real-drawings.md (bar 3). Writes
//   OUT_DIR/masks/<view>.png   hand-made masks the data set's authors' way: grey above 0.19,
//                              dilated by 10 px, eroded by 7 px (3 px beyond the plaster)
//   OUT_DIR/traced/<view>.png  masks traced along the plaster's edge: grey above 0.19,
//                              closed (dilated by 10 px, eroded by 10), enclosed regions filled
//   OUT_DIR/cloth/<view>.png   the photographs with the cloth
//   OUT_DIR/auto.yaml          the cloth photographs, background: auto (threshold 0.19)
//   OUT_DIR/black.yaml         the cloth photographs, background: black (threshold 0.19)
//   OUT_DIR/mask.yaml          the cloth photographs with mask: masks/<view>.png
//   OUT_DIR/traced.yaml        the cloth photographs with mask: traced/<view>.png
// Views as in dinoSR_par.txt (P = K [R | t]), the images of dinoSR_good_silhouette_images.txt.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "geometry/distance_transform.h"
#include "io/image_io.h"
#include "io/manifest.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

// Grey above 0.19, dilated by 10 px and eroded by `erode` (exact Euclidean discs).
std::vector<char> hand_mask(const Image& img, double erode) {
    const int w = img.width, h = img.height;
    const std::size_t n = std::size_t(w) * h;
    std::vector<char> m(n);
    for (std::size_t i = 0; i < n; ++i)
        m[i] = (img.pixels[i * 4] + img.pixels[i * 4 + 1] + img.pixels[i * 4 + 2]) / 3.0f > 0.19f;
    const std::vector<float> to_obj = squared_edt(m, w, h);
    std::vector<char> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = to_obj[i] > 100.0f; // outside the dilation
    const std::vector<float> to_out = squared_edt(out, w, h);
    for (std::size_t i = 0; i < n; ++i) m[i] = to_out[i] > float(erode * erode);
    return m;
}

// What the border does not reach (4-connected) through the rest is object.
std::vector<char> fill_enclosed(const std::vector<char>& m, int w, int h) {
    std::vector<char> out(m.size(), 1);
    std::vector<int> stack;
    auto reach = [&](int x, int y) {
        const std::size_t i = std::size_t(y) * w + x;
        if (m[i] || !out[i]) return;
        out[i] = 0;
        stack.push_back(int(i));
    };
    for (int x = 0; x < w; ++x) {
        reach(x, 0);
        reach(x, h - 1);
    }
    for (int y = 0; y < h; ++y) {
        reach(0, y);
        reach(w - 1, y);
    }
    while (!stack.empty()) {
        const int p = stack.back(), x = p % w, y = p / w;
        stack.pop_back();
        if (x > 0) reach(x - 1, y);
        if (x + 1 < w) reach(x + 1, y);
        if (y > 0) reach(x, y - 1);
        if (y + 1 < h) reach(x, y + 1);
    }
    return out;
}

// A woven brown-grey cloth with folds, over the rows below a wavy line, kept 12 px clear of
// the object.
void add_cloth(Image& img, const std::vector<char>& mask, std::mt19937& rng) {
    const int w = img.width, h = img.height;
    std::vector<char> obj(mask);
    const std::vector<float> to_obj = squared_edt(obj, w, h);
    std::uniform_real_distribution<double> u(0, 1);
    const double top = h * (0.68 + 0.1 * u(rng)), phase = 6.28 * u(rng), tilt = (u(rng) - 0.5) * 0.15;
    std::normal_distribution<double> grain(0, 0.025);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const double edge = top + tilt * (x - w / 2.0) + 10 * std::sin(x / 37.0 + phase);
            if (y < edge || to_obj[i] < 144.0f) continue;
            const double fold = 0.06 * std::sin(x / 23.0 + 0.4 * y / 17.0 + phase);
            const double weave = 0.025 * std::sin(x * 1.7) * std::sin(y * 1.7);
            const double g = fold + weave + grain(rng);
            const double c[3] = {0.34 + g, 0.27 + g, 0.21 + 0.8 * g};
            for (int k = 0; k < 3; ++k) img.pixels[i * 4 + k] = float(std::clamp(c[k], 0.0, 1.0));
        }
}

Image grey(const std::vector<char>& m, int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = 1;
    img.pixels.resize(m.size());
    for (std::size_t i = 0; i < m.size(); ++i) img.pixels[i] = m[i] ? 1.0f : 0.0f;
    return img;
}

struct Camera3x4 {
    std::string file;
    std::array<double, 12> P{};
};

std::vector<Camera3x4> read_cameras(const fs::path& dir) {
    std::ifstream in(dir / "dinoSR_par.txt");
    if (!in) throw Error("cannot read \"" + (dir / "dinoSR_par.txt").string() + "\"");
    std::set<std::string> good;
    std::ifstream g(dir / "dinoSR_good_silhouette_images.txt");
    for (std::string f; g >> f;) good.insert(f);
    int count = 0;
    in >> count;
    std::vector<Camera3x4> out;
    for (int v = 0; v < count; ++v) {
        Camera3x4 c;
        double K[9], R[9], t[3];
        in >> c.file;
        for (double& x : K) in >> x;
        for (double& x : R) in >> x;
        for (double& x : t) in >> x;
        if (!in) throw Error("dinoSR_par.txt: short line for view " + std::to_string(v + 1));
        if (!good.empty() && !good.count(c.file)) continue;
        for (int r = 0; r < 3; ++r) {
            for (int k = 0; k < 3; ++k)
                c.P[std::size_t(4 * r + k)] = K[3 * r] * R[k] + K[3 * r + 1] * R[3 + k] + K[3 * r + 2] * R[6 + k];
            c.P[std::size_t(4 * r + 3)] = K[3 * r] * t[0] + K[3 * r + 1] * t[1] + K[3 * r + 2] * t[2];
        }
        out.push_back(c);
    }
    return out;
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: dino_cloth DINO_DIR OUT_DIR\n");
        return 2;
    }
    try {
        const fs::path dir = argv[1], out = fs::absolute(argv[2]);
        fs::create_directories(out / "masks");
        fs::create_directories(out / "cloth");
        fs::create_directories(out / "traced");
        std::mt19937 rng(5);
        Manifest automatic, black, masked, traced;
        automatic.bounds = black.bounds = masked.bounds =
            traced.bounds = {-0.061897, -0.018874, -0.057845, 0.010897, 0.068227, 0.015495};
        automatic.comment = "dinoSparseRing photographs with a cloth, background: auto (bench/views/dino_cloth).";
        black.comment = "dinoSparseRing photographs with a cloth, background: black (bench/views/dino_cloth).";
        masked.comment = "dinoSparseRing photographs with a cloth, hand-made masks (bench/views/dino_cloth).";
        traced.comment =
            "dinoSparseRing photographs with a cloth, masks traced along the edge (bench/views/dino_cloth).";
        for (const auto& c : read_cameras(dir)) {
            Image img = read_image(dir / c.file);
            const std::vector<char> m = hand_mask(img, 7);
            const std::string key = fs::path(c.file).stem().string();
            write_image(grey(m, img.width, img.height), out / "masks" / (key + ".png"));
            write_image(grey(fill_enclosed(hand_mask(img, 10), img.width, img.height), img.width, img.height),
                        out / "traced" / (key + ".png"));
            add_cloth(img, m, rng);
            write_image(img, out / "cloth" / (key + ".png"));
            ManifestView v;
            v.key = key;
            v.image = out / "cloth" / (key + ".png");
            v.matrix = c.P;
            v.threshold = 0.19;
            automatic.views.push_back(v);
            v.background = "black";
            black.views.push_back(v);
            v.background = "auto";
            v.mask = out / "masks" / (key + ".png");
            masked.views.push_back(v);
            v.mask = out / "traced" / (key + ".png");
            traced.views.push_back(v);
        }
        write_manifest(out / "auto.yaml", automatic);
        write_manifest(out / "black.yaml", black);
        write_manifest(out / "mask.yaml", masked);
        write_manifest(out / "traced.yaml", traced);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dino_cloth: %s\n", e.what());
        return 1;
    }
    return 0;
}
