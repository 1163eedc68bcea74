// fill_delta_e [--dry-as-fill] MESH VIEWS.yaml [RADIUS] [MAP_DIR]: the colour error of a
// coloured mesh against the fill of hand-drawn views (docs/results/real-drawings.md): per
// view, the mesh's colour rendered through the view's camera (as views.load aligns it)
// against the drawing's fill, the mean of the pixels that are not strokes (ink, black or
// grey, with its fringe, the paper showing between marker strokes and, as texturing finds
// them, the pale streaks where the marker ran dry; coloured strokes are fill; with
// --dry-as-fill the dry streaks are fill, as before they were found) over a square of side
// 2 RADIUS + 1 (default 6 px), in CIE76 delta E, over the silhouette eroded by 3 px without
// the strokes. Also the error against those pixels one by one. Prints one line per view:
// name, mean delta E against the fill, against the pixels, the pixels compared, then what a
// mean hides (flecks of the stroke pattern left in the texture): the 95th and 99th
// percentiles of the delta E against the fill and the share of the compared pixels over 10
// against it, in per cent. With MAP_DIR, writes MAP_DIR/VIEW.png: the mesh's colour where
// compared, white elsewhere.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "drawing/fill.h"
#include "drawing/ink.h"
#include "geometry/distance_transform.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "load.h"
#include "render/colour.h"
#include "render/textured.h"

using namespace cm;

int main(int argc, char** argv) {
    bool dry_as_fill = false;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--dry-as-fill") {
            dry_as_fill = true;
            for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
            --argc;
            break;
        }
    if (argc < 3) {
        std::fprintf(stderr, "usage: fill_delta_e [--dry-as-fill] MESH VIEWS.yaml [RADIUS] [MAP_DIR]\n");
        return 2;
    }
    try {
        const Mesh mesh = read_mesh(argv[1]);
        const Views views = load_views(argv[2], {}).value;
        const int radius = argc > 3 ? std::stoi(argv[3]) : 6;
        for (const View& v : views.views) {
            const int w = v.width, h = v.height;
            const std::size_t n = std::size_t(w) * h;
            std::vector<char> inside(n), outside(n);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    inside[std::size_t(y) * w + x] = v.inside(x, y);
                    outside[std::size_t(y) * w + x] = !v.inside(x, y);
                }
            // Ink as texturing takes it: thin dark strokes that are not coloured (marker and
            // coloured hatching are the fill), with their fringe.
            std::vector<char> ink = find_ink(v.image, inside, 4, 0.12f, false);
            keep_neutral_ink(v.image, ink, 0.25f);
            std::vector<char> strokes = grow_ink(ink, inside, w, h);
            const std::vector<char> slivers =
                find_paper_slivers(v.image, inside, paper_colour(v.image, inside), 4, 0.12f);
            std::vector<char> keep(n);
            for (std::size_t i = 0; i < n; ++i) {
                strokes[i] = strokes[i] || slivers[i];
                keep[i] = inside[i] && !strokes[i];
            }
            if (!dry_as_fill) {
                // The pale streaks where a marker ran dry, as texturing finds them.
                std::vector<float> unused;
                const auto around = fill_under_strokes(v.image, keep, strokes, 8, unused);
                const auto pale = find_pale_streaks(v.image, inside, around, paper_colour(v.image, inside), 4);
                for (std::size_t i = 0; i < n; ++i)
                    if (pale[i]) {
                        strokes[i] = 1;
                        keep[i] = 0;
                    }
            }
            std::vector<float> share;
            const auto fill = fill_under_strokes(v.image, keep, strokes, radius, share);
            const std::vector<float> d_out = squared_edt(outside, w, h);
            const Image rendered = render_colour(mesh, v.camera, w, h);
            double sum_fill = 0, sum_px = 0, count = 0;
            std::vector<double> de_fill;
            Image map;
            map.width = w;
            map.height = h;
            map.channels = 3;
            map.pixels.assign(n * 3, 1.0f);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = std::size_t(y) * w + x;
                    if (!keep[i] || d_out[i] <= 9.0f || rendered.at(x, y, 3) < 0.5f) continue;
                    const std::array<float, 3> c{rendered.at(x, y, 0), rendered.at(x, y, 1), rendered.at(x, y, 2)};
                    de_fill.push_back(delta_e76(c, fill[i]));
                    sum_fill += de_fill.back();
                    for (int k = 0; k < 3; ++k) map.at(x, y, k) = c[std::size_t(k)];
                    sum_px += delta_e76(c, {v.image.at(x, y, 0), v.image.at(x, y, 1), v.image.at(x, y, 2)});
                    count += 1;
                }
            if (argc > 4) write_image(map, std::string(argv[4]) + "/" + v.name + ".png");
            std::sort(de_fill.begin(), de_fill.end());
            auto pct = [&](double q) {
                return de_fill.empty() ? 0.0 : de_fill[std::size_t(q * double(de_fill.size() - 1) + 0.5)];
            };
            const double over = double(de_fill.end() - std::upper_bound(de_fill.begin(), de_fill.end(), 10.0));
            std::printf("%s %.2f %.2f %.0f %.2f %.2f %.2f\n", v.name.c_str(), count ? sum_fill / count : 0.0,
                        count ? sum_px / count : 0.0, count, pct(0.95), pct(0.99), count ? 100.0 * over / count : 0.0);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fill_delta_e: %s\n", e.what());
        return 1;
    }
}
