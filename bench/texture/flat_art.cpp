// flat_art MODEL UP FRONT OUT_DIR [SIZE] [STYLE]: concept art of a model as a colourist paints a
// turnaround: flat fills (a palette of six colours over horizontal bands of the model and
// its left and right halves, so regions meet at lines that views must agree on), an ink
// outline 2 px wide inside the silhouette and ink lines 1.5 px wide where two fills meet,
// on off-white paper. The model is turned so UP is +Y and FRONT faces +Z (bench/models.txt)
// and stands on Y = 0, framed as render-views frames (0.9 * SIZE / largest extent px per
// unit, box centre at the image centre). Writes OUT_DIR/art/{front,right,top}.png with
// views.yaml (exact cameras, bounds) and OUT_DIR/fill/ the same without ink, so the colour
// error can be measured against the drawing as drawn and against its fills.
// STYLE flat (default) or marker: the fills laid in marker strokes, as a marker drawing by hand:
// diagonal strokes about 1/70 of the image apart, each a darker shade of its fill where strokes
// overlap and a paler streak where the marker ran dry, their edges wavering; same ink lines.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/image_io.h"
#include "io/manifest.h"
#include "io/mesh_io.h"
#include "render/raster.h"

namespace fs = std::filesystem;
using namespace cm;

namespace {

Vec3d axis(const std::string& s) {
    if (s.size() != 2 || (s[0] != '+' && s[0] != '-')) throw Error("axis must be +X, -X, +Y, -Y, +Z or -Z: " + s);
    const double sign = s[0] == '+' ? 1 : -1;
    switch (s[1]) {
    case 'X': return {sign, 0, 0};
    case 'Y': return {0, sign, 0};
    case 'Z': return {0, 0, sign};
    default: throw Error("axis must be +X, -X, +Y, -Y, +Z or -Z: " + s);
    }
}

const std::array<std::array<float, 3>, 6> kPalette = {{{0.82f, 0.33f, 0.24f},
                                                       {0.93f, 0.73f, 0.30f},
                                                       {0.36f, 0.58f, 0.42f},
                                                       {0.30f, 0.45f, 0.70f},
                                                       {0.62f, 0.40f, 0.63f},
                                                       {0.85f, 0.62f, 0.52f}}};

// A marker's stroke pattern over a fill at pixel (x, y): diagonal strokes `period` px apart,
// wavering along their length; where two strokes overlap the ink is darker, between them the
// marker leaves a paler streak.
std::array<float, 3> marker_shade(const std::array<float, 3>& c, int x, int y, double period) {
    const double along = (x - y) / period, across = (x + y) / period;
    const double t = across + 0.18 * std::sin(0.9 * along + 1.7 * std::floor(across));
    const double f = t - std::floor(t);
    const auto stroke = static_cast<unsigned>(std::floor(t)) * 2654435761u;
    const float jitter = 0.04f * float((stroke >> 16) % 5) - 0.08f;
    float k = 1.0f;
    if (f < 0.28) k = 0.74f + jitter; // overlap of two strokes
    else if (f > 0.86) k = -0.35f;    // a dry streak: towards the paper
    std::array<float, 3> out{};
    for (int i = 0; i < 3; ++i)
        out[std::size_t(i)] = k > 0 ? std::clamp(c[std::size_t(i)] * k, 0.0f, 1.0f)
                                    : c[std::size_t(i)] + 0.35f * (0.96f - c[std::size_t(i)]);
    return out;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 5) {
        std::fprintf(stderr, "usage: flat_art MODEL UP FRONT OUT_DIR [SIZE] [flat|marker]\n");
        return 2;
    }
    try {
        Mesh m = read_mesh(argv[1]);
        const Vec3d up = axis(argv[2]), front = axis(argv[3]), right = cross(up, front);
        for (auto& p : m.positions) {
            const Vec3d q(p);
            p = Vec3f(Vec3d(dot(q, right), dot(q, up), dot(q, front)));
        }
        Vec3f lo, hi;
        m.bounds(lo, hi);
        const Vec3f pivot(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
        for (auto& p : m.positions) p -= pivot;
        m.bounds(lo, hi);
        const int size = argc > 5 ? std::stoi(argv[5]) : 512;
        const std::string style = argc > 6 ? argv[6] : "flat";
        if (style != "flat" && style != "marker") throw Error("style must be flat or marker: " + style);
        // The fill of each face: five height bands, the right half one palette step on.
        std::vector<int> fill(m.triangles.size());
        for (std::size_t f = 0; f < m.triangles.size(); ++f) {
            Vec3f c(0, 0, 0);
            for (int k = 0; k < 3; ++k) c += m.positions[m.triangles[f][k]] / 3.0f;
            const int band = std::clamp(int(5.0f * (c.y - lo.y) / (hi.y - lo.y)), 0, 4);
            fill[f] = (band + (c.x > 0 ? 1 : 0)) % int(kPalette.size());
        }
        const fs::path out = argv[4];
        Manifest art, plain;
        art.comment = "flat_art of " + fs::path(argv[1]).filename().string() +
                      (style == "marker" ? ": fills in marker strokes with ink lines" : ": flat fills with ink lines");
        plain.comment = "flat_art of " + fs::path(argv[1]).filename().string() + ": the same fills without ink";
        art.bounds = plain.bounds = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
        for (const char* name : {"front", "right", "top"}) {
            const Camera cam = framed_camera(*Camera::named(name), Vec3d(lo), Vec3d(hi), size, size);
            const DepthImage d = render_depth(m, cam, size, size);
            Image filled, inked;
            filled.width = filled.height = size;
            filled.channels = 3;
            filled.pixels.assign(std::size_t(size) * size * 3, 0.0f);
            const std::array<float, 3> paper{0.96f, 0.95f, 0.91f}, ink{0.10f, 0.09f, 0.11f};
            auto fill_at = [&](int x, int y) -> int {
                if (x < 0 || y < 0 || x >= size || y >= size || !d.covered(x, y)) return -1;
                return fill[d.face[std::size_t(y) * size + x]];
            };
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) {
                    const int f = fill_at(x, y);
                    const auto& c = f < 0 ? paper : kPalette[std::size_t(f)];
                    for (int k = 0; k < 3; ++k) filled.pixels[(std::size_t(y) * size + x) * 3 + k] = c[k];
                }
            inked = filled;
            if (style == "marker")
                for (int y = 0; y < size; ++y)
                    for (int x = 0; x < size; ++x) {
                        const int f = fill_at(x, y);
                        if (f < 0) continue;
                        const auto c = marker_shade(kPalette[std::size_t(f)], x, y, size / 70.0);
                        for (int k = 0; k < 3; ++k)
                            inked.pixels[(std::size_t(y) * size + x) * 3 + k] = c[std::size_t(k)];
                    }
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) {
                    const int f = fill_at(x, y);
                    if (f < 0) continue;
                    bool line = false;
                    for (int dy = -2; dy <= 2 && !line; ++dy)
                        for (int dx = -2; dx <= 2 && !line; ++dx) {
                            const int g = fill_at(x + dx, y + dy);
                            const int r2 = dx * dx + dy * dy;
                            if (g < 0 && r2 <= 4) line = true;                                  // the outline, 2 px
                            if (g >= 0 && g != f && r2 <= 1 && (dx > 0 || dy > 0)) line = true; // fills meet
                        }
                    if (line)
                        for (int k = 0; k < 3; ++k) inked.pixels[(std::size_t(y) * size + x) * 3 + k] = ink[k];
                }
            for (auto* set : {&art, &plain}) {
                const fs::path dir = out / (set == &art ? "art" : "fill");
                fs::create_directories(dir);
                ManifestView v;
                v.key = name;
                v.view = name;
                v.image = dir / (std::string(name) + ".png");
                v.scale = cam.scale;
                v.origin = {cam.cx, cam.cy};
                write_image(set == &art ? inked : filled, v.image);
                set->views.push_back(v);
            }
        }
        write_manifest(out / "art" / "views.yaml", art);
        write_manifest(out / "fill" / "views.yaml", plain);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "flat_art: %s\n", e.what());
        return 1;
    }
}
