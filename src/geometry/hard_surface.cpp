// Hard-surface detection (hard_surface.h). Measured on the masks of the
// models of ../shared/data/models at 1024 px (docs/hull.md): the least straight view of the
// machined part fandisk keeps about a quarter of its outline on straight stretches, the
// creatures at most a twentieth; a disc or an ellipse none.
#include "geometry/hard_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

namespace cm {

namespace {

double smoothstep(double x, double a, double b) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Outline cells of the silhouette on a raster of `cells` along the inside box's longest side
// (point samples at the cell centres, coverage >= 0.5): inside cells with an outside
// 4-neighbour.
struct Outline {
    std::vector<int> x, y;
    int w = 0, h = 0;
    int cells = 0; ///< along the box's longest side
};

Outline outline_of(const View& view, int cells) {
    const Coverage::Box& b = view.coverage.inside_box();
    Outline o;
    if (b.empty()) return o;
    const double side = double(std::max(b.x1 - b.x0 + 1, b.y1 - b.y0 + 1));
    // Never finer than the pixels (a drawing smaller than the raster is not resampled up).
    const double step = std::max(1.0, side / double(cells));
    o.cells = int(std::lround(side / step));
    // One cell of margin on each side, so the box's own edges are outline.
    o.w = int(std::ceil(double(b.x1 - b.x0 + 1) / step)) + 2;
    o.h = int(std::ceil(double(b.y1 - b.y0 + 1) / step)) + 2;
    std::vector<std::uint8_t> in(std::size_t(o.w) * std::size_t(o.h), 0);
    for (int j = 1; j + 1 < o.h; ++j)
        for (int i = 1; i + 1 < o.w; ++i) {
            const int px = b.x0 + int(std::floor((double(i - 1) + 0.5) * step));
            const int py = b.y0 + int(std::floor((double(j - 1) + 0.5) * step));
            in[std::size_t(j) * o.w + i] = view.inside(px, py);
        }
    for (int j = 1; j + 1 < o.h; ++j)
        for (int i = 1; i + 1 < o.w; ++i) {
            const std::size_t c = std::size_t(j) * o.w + i;
            if (in[c] && !(in[c - 1] && in[c + 1] && in[c - std::size_t(o.w)] && in[c + std::size_t(o.w)])) {
                o.x.push_back(i);
                o.y.push_back(j);
            }
        }
    return o;
}

} // namespace

double outline_straightness(const View& view) {
    const Outline o = outline_of(view, kStraightCells);
    const std::size_t n = o.x.size();
    if (n == 0) return 0.0;
    const double reach = 0.1 * o.cells;
    // The outline cells in buckets of `reach` cells, so a cell's neighbours are in the 3x3
    // buckets about its own.
    const int bw = int(double(o.w) / reach) + 1, bh = int(double(o.h) / reach) + 1;
    std::vector<std::vector<std::uint32_t>> bucket(std::size_t(bw) * std::size_t(bh));
    for (std::size_t k = 0; k < n; ++k)
        bucket[std::size_t(int(o.y[k] / reach)) * bw + std::size_t(int(o.x[k] / reach))].push_back(std::uint32_t(k));
    const std::size_t straight = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n), std::size_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t acc) {
            for (std::size_t k = r.begin(); k != r.end(); ++k) {
                const int bx = int(o.x[k] / reach), by = int(o.y[k] / reach);
                double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, m = 0;
                for (int j = std::max(0, by - 1); j <= std::min(bh - 1, by + 1); ++j)
                    for (int i = std::max(0, bx - 1); i <= std::min(bw - 1, bx + 1); ++i)
                        for (const std::uint32_t q : bucket[std::size_t(j) * bw + std::size_t(i)]) {
                            const double dx = o.x[q] - o.x[k], dy = o.y[q] - o.y[k];
                            if (dx * dx + dy * dy > reach * reach) continue;
                            sx += dx;
                            sy += dy;
                            sxx += dx * dx;
                            syy += dy * dy;
                            sxy += dx * dy;
                            m += 1;
                        }
                // The smaller eigenvalue of the neighbours' covariance: their spread across
                // the best line through them.
                const double cxx = sxx / m - (sx / m) * (sx / m), cyy = syy / m - (sy / m) * (sy / m);
                const double cxy = sxy / m - (sx / m) * (sy / m);
                const double across = 0.5 * (cxx + cyy) - std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
                acc += across < 0.25; // half a cell, rms
            }
            return acc;
        },
        [](std::size_t a, std::size_t b) { return a + b; });
    return double(straight) / double(n);
}

bool along_axis(const View& view) {
    const Camera& c = view.camera;
    if (!c.orthographic()) return false;
    const double a = std::max({std::abs(c.d.x), std::abs(c.d.y), std::abs(c.d.z)});
    return a > (1.0 - 1e-9) * length(c.d); // the other two components vanish
}

double hard_surface(const Views& views, std::vector<double>& shares) {
    shares.clear();
    // The views along the grid's axes decide when there are any (an oblique view's outline
    // crowds more corners within the reach, and shows curved faces' contours that the axis
    // views see edge-on); without any, every view does.
    const bool any_axis = std::any_of(views.views.begin(), views.views.end(), along_axis);
    double least = 1.0;
    for (const View& v : views.views) {
        if (any_axis && !along_axis(v)) continue;
        shares.push_back(outline_straightness(v));
        least = std::min(least, shares.back());
    }
    return shares.empty() ? 0.0 : smoothstep(least, 0.06, 0.12);
}

} // namespace cm
