#include "metrics/colour_error.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "drawing/ink.h"
#include "render/colour.h"
#include "render/textured.h"

namespace cm {

std::vector<ViewColourError> colour_error(const Mesh& mesh, const Views& views, double erode_px, float line_width,
                                          float line_contrast) {
    std::vector<ViewColourError> out;
    const int r = int(std::ceil(erode_px));
    for (const View& v : views.views) {
        ViewColourError e;
        e.view = v.name;
        if (v.image.empty() || v.image.width != v.width || v.image.height != v.height) {
            out.push_back(e);
            continue;
        }
        const Image rendered = render_colour(mesh, v.camera, v.width, v.height);
        std::vector<char> inside(std::size_t(v.width) * v.height);
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) inside[std::size_t(y) * v.width + x] = v.inside(x, y);
        const std::vector<char> ink = find_ink(v.image, inside, line_width, line_contrast, false);
        double sum = 0, over = 0, n = 0, fsum = 0, fover = 0, fn = 0;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) {
                if (rendered.at(x, y, 3) < 0.5f) continue;
                bool inner = true; // the silhouette eroded by a disc of radius erode_px
                for (int dy = -r; dy <= r && inner; ++dy)
                    for (int dx = -r; dx <= r; ++dx)
                        if (dx * dx + dy * dy <= erode_px * erode_px && !v.inside(x + dx, y + dy)) {
                            inner = false;
                            break;
                        }
                if (!inner) continue;
                const double de = delta_e76({rendered.at(x, y, 0), rendered.at(x, y, 1), rendered.at(x, y, 2)},
                                            {v.image.at(x, y, 0), v.image.at(x, y, 1), v.image.at(x, y, 2)});
                sum += de;
                over += de > 10 ? 1 : 0;
                n += 1;
                if (ink[std::size_t(y) * v.width + x]) continue;
                fsum += de;
                fover += de > 10 ? 1 : 0;
                fn += 1;
            }
        e.pixels = n;
        e.mean_de = n ? sum / n : 0;
        e.over10_pct = n ? 100.0 * over / n : 0;
        e.no_ink_pixels = fn;
        e.no_ink_mean_de = fn ? fsum / fn : 0;
        e.no_ink_over10_pct = fn ? 100.0 * fover / fn : 0;
        out.push_back(e);
    }
    return out;
}

} // namespace cm
