#include "silhouette_extent.h"

#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"

namespace cm {

// The first and last columns (rows) with a pixel of coverage >= 0.5, moved by the largest
// partial coverage of the column itself and of the one beyond: an anti-aliased extreme
// lands to a fraction of a pixel, a binary one on the pixel edge (its expected place).
Extent silhouette_extent(const View& v) {
    const int w = v.width, h = v.height;
    // The largest coverage per column and row, taken over the floats (exact, and a loop the
    // compiler runs over several pixels at once), then widened.
    // Blocks of rows side by side, each with its own column maxima (a maximum is the same in
    // any order).
    std::vector<double> row(static_cast<std::size_t>(h), 0.0);
    tbb::enumerable_thread_specific<std::vector<float>> cols(std::vector<float>(std::size_t(w), 0.0f));
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 64), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float>& colf = cols.local();
        // Beyond the coverage's window every value is 0, which changes no maximum.
        const int x0 = v.coverage.x0(), ww = v.coverage.window_width();
        for (int y = rows.begin(); y != rows.end(); ++y) {
            const float* c = v.coverage.window_row(y);
            if (!c) continue;
            float r = 0.0f;
            for (int x = 0; x < ww; ++x) {
                colf[std::size_t(x0 + x)] = std::max(colf[std::size_t(x0 + x)], c[x]);
                r = std::max(r, c[x]);
            }
            row[std::size_t(y)] = double(r);
        }
    });
    std::vector<double> col(static_cast<std::size_t>(w), 0.0);
    for (const auto& colf : cols)
        for (std::size_t x = 0; x < colf.size(); ++x) col[x] = std::max(col[x], double(colf[x]));
    auto range = [](const std::vector<double>& a, double& lo, double& hi) {
        int first = -1, last = -1;
        for (int i = 0; i < int(a.size()); ++i)
            if (a[std::size_t(i)] >= 0.5) {
                if (first < 0) first = i;
                last = i;
            }
        if (first < 0) return false;
        lo = first + 0.5 - (first > 0 ? a[std::size_t(first - 1)] : 0.0) - (a[std::size_t(first)] - 0.5);
        hi = last + 0.5 + (last + 1 < int(a.size()) ? a[std::size_t(last + 1)] : 0.0) + (a[std::size_t(last)] - 0.5);
        return true;
    };
    Extent e;
    if (!range(col, e.x0, e.x1) || !range(row, e.y0, e.y1))
        throw Error("view \"" + v.name + "\" (" + v.source.string() +
                    ") has an empty silhouette: no object was found in it");
    return e;
}

} // namespace cm
