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

std::size_t raise_weak_ink(std::vector<double>& d, double t, double weak, int w, int h) {
    if (!(weak < t)) return 0;
    const std::size_t n = std::size_t(w) * h;
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
