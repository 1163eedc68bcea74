// perturb_views IN/views.yaml OUT_DIR [--seed N] [--scale S] [--turn DEG] [--shift F] [--wobble F]
//   [--erase VIEW]
// Redraws the render-views images of a manifest the way people draw turnarounds: every view
// but the first with each image axis scaled on its own by up to S (default 0.08), turned by
// up to DEG degrees (3), shifted by up to F of the side (0.01) and its outline wobbled by a
// smooth displacement of up to F of the side (0.006), each drawn at random from the seed.
// The cameras (scale, origin) and box of the manifest are dropped, as from drawings.
// --erase VIEW (a mask render) erases, in VIEW, the part that stands out farthest from
// the silhouette's centre along its top (a spike, an ear, a horn) before anything else, so
// that an opposite view can draw what this one does not. Writes OUT_DIR/<view>.png,
// OUT_DIR/views.yaml and OUT_DIR/perturbation.txt (what each view got).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

struct Perturbation {
    double sx = 1, sy = 1, turn = 0, tx = 0, ty = 0; // turn in radians, shift in px
    double amp = 0, fx = 0, fy = 0, px = 0, py = 0;  // wobble: amplitude px, frequencies, phases
};

Perturbation draw(std::mt19937& rng, int side, double scale, double turn_deg, double shift, double wobble) {
    std::uniform_real_distribution<double> u(-1.0, 1.0), f(1.5, 3.5), ph(0.0, 6.2832);
    Perturbation p;
    p.sx = 1 + scale * u(rng);
    p.sy = 1 + scale * u(rng);
    p.turn = turn_deg * u(rng) * 3.14159265358979 / 180.0;
    p.tx = shift * side * u(rng);
    p.ty = shift * side * u(rng);
    p.amp = wobble * side * (0.5 + 0.5 * std::abs(u(rng)));
    p.fx = f(rng), p.fy = f(rng), p.px = ph(rng), p.py = ph(rng);
    return p;
}

// Bilinear RGBA of `img` at continuous (x, y), the border colour (its top-left pixel) beyond.
std::array<float, 4> bilinear(const Image& img, double x, double y) {
    const double fx = x - 0.5, fy = y - 0.5;
    const int i = int(std::floor(fx)), j = int(std::floor(fy));
    const double ax = fx - i, ay = fy - j;
    std::array<float, 4> out{0, 0, 0, 0};
    const auto border = img.rgba(0);
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            const int xi = i + di, yj = j + dj;
            const auto c = xi >= 0 && yj >= 0 && xi < img.width && yj < img.height
                               ? img.rgba(std::size_t(yj) * img.width + xi)
                               : border;
            const double w = (di ? ax : 1 - ax) * (dj ? ay : 1 - ay);
            for (int k = 0; k < 4; ++k) out[std::size_t(k)] += float(w * c[std::size_t(k)]);
        }
    return out;
}

// The drawing redrawn: output pixel q shows the input at the inverse of the stretch, turn
// and shift about the image centre, moved by the wobble.
Image redraw(const Image& in, const Perturbation& p) {
    const int W = in.width, H = in.height;
    Image out{W, H, 4, std::vector<float>(std::size_t(W) * H * 4), {}};
    const double cx = 0.5 * W, cy = 0.5 * H, cs = std::cos(p.turn), sn = std::sin(p.turn);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double qx = x + 0.5, qy = y + 0.5;
            const double wx = p.amp * std::sin(2 * 3.14159265 * p.fx * qy / H + p.px);
            const double wy = p.amp * std::sin(2 * 3.14159265 * p.fy * qx / W + p.py);
            const double dx = (qx + wx - cx - p.tx) / p.sx, dy = (qy + wy - cy - p.ty) / p.sy;
            const auto c = bilinear(in, cx + cs * dx + sn * dy, cy - sn * dx + cs * dy);
            for (int k = 0; k < 4; ++k) out.pixels[(std::size_t(y) * W + x) * 4 + k] = c[std::size_t(k)];
        }
    return out;
}

// Erases the part of a mask render (white object on black) that reaches highest above its
// neighbours: the topmost 12 % of the silhouette's height within the column band around
// the topmost pixel, painted with the background.
// Returns the erased share of the silhouette, in %.
double erase_top_part(Image& img) {
    const int W = img.width, H = img.height;
    int top = H, tx = 0, bottom = 0;
    double area = 0, erased = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (img.rgba(std::size_t(y) * W + x)[0] >= 0.5f) {
                ++area;
                if (y < top) top = y, tx = x;
                bottom = std::max(bottom, y);
            }
    const int cut = top + int(0.12 * (bottom - top));
    const auto bg = img.rgba(0);
    // The part: pixels above the cut connected to the topmost one.
    std::vector<char> seen(std::size_t(W) * H, 0);
    std::vector<int> stack{top * W + tx};
    seen[std::size_t(top) * W + tx] = 1;
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int x = i % W, y = i / W;
        erased += img.rgba(std::size_t(i))[0] >= 0.5f;
        for (int k = 0; k < 4; ++k) img.pixels[std::size_t(i) * 4 + k] = bg[std::size_t(k)];
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= W || ny > cut || seen[std::size_t(ny) * W + nx]) continue;
            if (img.rgba(std::size_t(ny) * W + nx)[0] < 0.05f) continue;
            seen[std::size_t(ny) * W + nx] = 1;
            stack.push_back(ny * W + nx);
        }
    }
    return area > 0 ? 100.0 * erased / area : 0.0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: perturb_views IN/views.yaml OUT_DIR [--seed N] [--scale S] [--turn DEG] "
                     "[--shift F] [--wobble F] [--erase VIEW]\n");
        return 2;
    }
    try {
        unsigned seed = 1;
        double scale = 0.08, turn = 3.0, shift = 0.01, wobble = 0.006;
        std::string erase;
        for (int a = 3; a + 1 < argc; a += 2) {
            const std::string k = argv[a], v = argv[a + 1];
            if (k == "--seed") seed = unsigned(std::stoul(v));
            else if (k == "--scale") scale = std::stod(v);
            else if (k == "--turn") turn = std::stod(v);
            else if (k == "--shift") shift = std::stod(v);
            else if (k == "--wobble") wobble = std::stod(v);
            else if (k == "--erase") erase = v;
            else throw Error("unknown option " + k);
        }
        Manifest m = read_manifest(argv[1]);
        const fs::path out = argv[2];
        fs::create_directories(out);
        std::mt19937 rng(seed);
        std::ofstream log(out / "perturbation.txt");
        for (std::size_t i = 0; i < m.views.size(); ++i) {
            auto& v = m.views[i];
            Image img = read_image(v.image);
            if (v.key == erase) log << v.key << " erased_pct " << erase_top_part(img) << "\n";
            if (i > 0) {
                const Perturbation p = draw(rng, std::max(img.width, img.height), scale, turn, shift, wobble);
                img = redraw(img, p);
                log << v.key << " scale_x " << p.sx << " scale_y " << p.sy << " turn_deg "
                    << p.turn * 180 / 3.14159265358979 << " shift_px " << p.tx << " " << p.ty << " wobble_px " << p.amp
                    << "\n";
            }
            const fs::path file = out / (v.key + ".png");
            write_image(img, file);
            v.image = file;
            // Drawings come without cameras: their scale and placement are the alignment's.
            v.scale.reset();
            v.origin.reset();
        }
        m.bounds.reset();
        m.comment = "Perturbed render-views images (bench/views/perturb_views), seed " + std::to_string(seed) + ".";
        write_manifest(out / "views.yaml", m);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "perturb_views: %s\n", e.what());
        return 1;
    }
    return 0;
}
