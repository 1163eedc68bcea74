#include "ink.h"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>

#include "pixel_flood.h"

namespace cm {

std::optional<SheetPanel> ink_window(const Image& img, const BackgroundModel& model, double t, int margin) {
    BackgroundField field;
    field.model = model;
    field.w = img.width;
    field.h = img.height;
    struct Box {
        int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max(), x1 = -1, y1 = -1;
    };
    tbb::enumerable_thread_specific<std::vector<double>> rows;
    const Box box = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, img.height, 16), Box{},
        [&](const tbb::blocked_range<int>& r, Box b) {
            std::vector<double>& d = rows.local();
            d.resize(std::size_t(img.width));
            for (int y = r.begin(); y != r.end(); ++y) {
                field.model_distance_row(img, y, d.data()); // the distances BackgroundCut computes
                int first = -1, last = -1;
                for (int x = 0; x < img.width; ++x)
                    if (d[std::size_t(x)] >= t) {
                        if (first < 0) first = x;
                        last = x;
                    }
                if (first < 0) continue;
                b = {std::min(b.x0, first), std::min(b.y0, y), std::max(b.x1, last), std::max(b.y1, y)};
            }
            return b;
        },
        [](const Box& a, const Box& b) {
            return Box{std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
        });
    if (box.x1 < 0) return std::nullopt;
    SheetPanel win;
    win.x0 = std::max(0, box.x0 - margin);
    win.y0 = std::max(0, box.y0 - margin);
    win.width = std::min(img.width, box.x1 + margin + 1) - win.x0;
    win.height = std::min(img.height, box.y1 + margin + 1) - win.y0;
    return win;
}

double weak_ink_threshold(double t, double noise) { return std::min(t, std::max(0.1 - 2.0 * noise, 4.0 * noise)); }

namespace {

// A drawing whose strokes are no wider than this by their ink (px) is in thin lines.
constexpr double kThinDrawing = 1.75;

// The width of the drawing's strokes by their ink: the lower quartile of the ink across them
// (the runs of pixels at `weak` or more along the rows and the columns, each pixel its
// distance over the full ink's, at most 1; a faint 1 px line split between two pixels holds
// no clear ink where it is crossed). A straight stroke w px wide at
// angle a is crossed by w / |sin a| along the rows and w / |cos a| along the columns; runs
// along a stroke, through junctions and across strokes run together are the longer ones.
double drawing_ink_width(const std::vector<double>& d, double weak, double full, int w, int h) {
    std::vector<double> runs;
    auto cross = [&](int count, auto at) {
        double sum = 0;
        for (int k = 0; k <= count; ++k) {
            const double v = k < count ? d[at(k)] : 0.0;
            if (v >= weak) {
                sum += std::min(1.0, v / full);
                continue;
            }
            if (sum > 0) runs.push_back(sum);
            sum = 0;
        }
    };
    for (int y = 0; y < h; ++y) cross(w, [&](int k) { return std::size_t(y) * w + k; });
    for (int x = 0; x < w; ++x) cross(h, [&](int k) { return std::size_t(k) * w + x; });
    if (runs.empty()) return 0;
    const auto q = runs.begin() + std::ptrdiff_t(runs.size() / 4);
    std::nth_element(runs.begin(), q, runs.end());
    return *q;
}

} // namespace

std::size_t raise_weak_ink(std::vector<double>& d, double t, double weak, int w, int h) {
    if (!(weak < t)) return 0;
    const std::size_t n = std::size_t(w) * h;
    // The full ink: the 95th percentile of the clear ink's distances.
    std::vector<double> strong;
    for (const double v : d)
        if (v >= t) strong.push_back(v);
    if (strong.empty()) return 0;
    const auto q = strong.begin() + std::ptrdiff_t(0.95 * double(strong.size() - 1));
    std::nth_element(strong.begin(), q, strong.end());
    const double full = *q;
    // Only a drawing in thin lines: wider strokes are whole by their clear ink, and their
    // faint pixels are their anti-aliased fringe, which would widen them.
    if (drawing_ink_width(d, weak, full, w, h) > kThinDrawing) return 0;
    std::vector<char> done(n, 0);
    std::vector<int> stack;
    std::size_t raised = 0;
    auto open = [&](int p) { return !done[std::size_t(p)] && d[std::size_t(p)] >= weak; };
    auto take = [&](int row, int l, int r) {
        for (int x = l; x <= r; ++x) {
            const std::size_t i = std::size_t(row + x);
            done[i] = 1;
            if (d[i] < t) {
                d[i] = t;
                ++raised;
            }
        }
    };
    for (std::size_t i = 0; i < n; ++i)
        if (d[i] >= t && !done[i]) scanline_fill(w, h, int(i), true, stack, open, take);
    return raised;
}

} // namespace cm
