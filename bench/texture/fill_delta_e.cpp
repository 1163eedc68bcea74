// fill_delta_e MESH VIEWS.yaml [RADIUS]: the colour error of a coloured mesh against the
// fill of hand-drawn views (docs/results/real-drawings.md): per view, the mesh's colour
// rendered through the view's camera (as views.load aligns it) against the drawing's fill,
// the mean of the pixels that are not strokes (ink, black or grey, with its fringe, and the
// paper showing between marker strokes; coloured strokes are fill) over a square of side 2 RADIUS + 1 (default 6 px), in CIE76
// delta E, over the silhouette eroded by 3 px without the strokes. Also the error against
// those pixels one by one. Prints one line per view: name, mean delta E against the fill,
// against the pixels, and the pixels compared.
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "drawing/fill.h"
#include "drawing/ink.h"
#include "geometry/distance_transform.h"
#include "io/mesh_io.h"
#include "load.h"
#include "render/colour.h"
#include "render/textured.h"

using namespace cm;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: fill_delta_e MESH VIEWS.yaml [RADIUS]\n");
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
            std::vector<float> share;
            const auto fill = fill_under_strokes(v.image, keep, strokes, radius, share);
            const std::vector<float> d_out = squared_edt(outside, w, h);
            const Image rendered = render_colour(mesh, v.camera, w, h);
            double sum_fill = 0, sum_px = 0, count = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = std::size_t(y) * w + x;
                    if (!keep[i] || d_out[i] <= 9.0f || rendered.at(x, y, 3) < 0.5f) continue;
                    const std::array<float, 3> c{rendered.at(x, y, 0), rendered.at(x, y, 1), rendered.at(x, y, 2)};
                    sum_fill += delta_e76(c, fill[i]);
                    sum_px += delta_e76(c, {v.image.at(x, y, 0), v.image.at(x, y, 1), v.image.at(x, y, 2)});
                    count += 1;
                }
            std::printf("%s %.2f %.2f %.0f\n", v.name.c_str(), count ? sum_fill / count : 0.0,
                        count ? sum_px / count : 0.0, count);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fill_delta_e: %s\n", e.what());
        return 1;
    }
}
