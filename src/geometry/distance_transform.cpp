// Exact Euclidean distance transform of a binary image (Felzenszwalb and Huttenlocher 2012).
#include "geometry/distance_transform.h"

#include <algorithm>
#include <iterator>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cm {

// 1D squared distance transform of f (Felzenszwalb and Huttenlocher 2012) into d.
static void edt_1d(const float* f, float* d, int n, int* v, float* z) {
    int k = 0;
    v[0] = 0;
    z[0] = -std::numeric_limits<float>::infinity();
    z[1] = std::numeric_limits<float>::infinity();
    auto meet = [&](int q, int p) {
        return ((f[q] + float(q) * float(q)) - (f[p] + float(p) * float(p))) / (2.0f * float(q - p));
    };
    for (int q = 1; q < n; ++q) {
        float s = meet(q, v[k]);
        while (s <= z[k]) {
            --k;
            s = meet(q, v[k]);
        }
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = std::numeric_limits<float>::infinity();
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < float(q)) ++k;
        const float dq = float(q - v[k]);
        d[q] = dq * dq + f[v[k]];
    }
}

std::vector<float> squared_edt(const std::vector<char>& seed, int w, int h) {
    std::vector<float> g(std::size_t(w) * h);
    // Columns, then rows. A row that is all seeds stays 0 and a line without any stays
    // kEdtFar (kEdtFar + n^2 rounds back to kEdtFar in float): both are skipped, which
    // for a silhouette is most of the image (its box is a fraction of the frame).
    //
    // Along a column the input is only seed (0) or not (far), so its transform is the square
    // of the distance to the nearest seed above or below: a sweep down the rows counts the
    // distance to the seed above, a sweep up takes the nearer of that and the seed below.
    // Both sweeps go along whole rows of a strip of columns (contiguous, vectorised), in
    // place. Counts stay integers (exact in float); kEdtFar + 1 rounds back to kEdtFar, so a
    // column without a seed ends at kEdtFar.
    constexpr int kStrip = 256;
    const int strips = (w + kStrip - 1) / kStrip;
    tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> below(kStrip);
        for (int t = r.begin(); t != r.end(); ++t) {
            const int x0 = t * kStrip, nx = std::min(kStrip, w - x0);
            for (int y = 0; y < h; ++y) {
                const char* s = seed.data() + std::size_t(y) * w + x0;
                float* row = g.data() + std::size_t(y) * w + x0;
                if (y == 0) {
                    for (int b = 0; b < nx; ++b) row[b] = s[b] ? 0.0f : kEdtFar;
                } else {
                    const float* above = row - w;
                    for (int b = 0; b < nx; ++b) row[b] = s[b] ? 0.0f : above[b] + 1.0f;
                }
            }
            std::fill_n(below.begin(), nx, kEdtFar);
            for (int y = h - 1; y >= 0; --y) {
                float* row = g.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) {
                    const float m = std::min(row[b], below[b] + 1.0f);
                    below[b] = m;
                    row[b] = m >= kEdtFar ? kEdtFar : m * m;
                }
            }
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> f(w), z(w + 1);
        std::vector<int> v(w);
        for (int y = r.begin(); y != r.end(); ++y) {
            float* row = g.data() + std::size_t(y) * w;
            // Only the stretch from the first to the last pixel away from a seed changes, and
            // only the seeds just beyond it can be nearest there (any seed farther out is
            // farther from every pixel of the stretch): the transform of that stretch and its
            // two neighbours gives the same values as the whole row's, and the rest stays 0.
            // A silhouette's row of distances to the outside is the silhouette's width only.
            const auto nonzero = [](float x) { return x != 0.0f; };
            float* first = std::find_if(row, row + w, nonzero);
            if (first == row + w) continue; // all seeds
            float* last =
                std::find_if(std::make_reverse_iterator(row + w), std::make_reverse_iterator(first), nonzero).base();
            const int a = std::max(0, int(first - row) - 1), b = std::min(w, int(last - row) + 1);
            std::copy(row + a, row + b, f.begin());
            edt_1d(f.data(), row + a, b - a, v.data(), z.data());
        }
    });
    return g;
}

} // namespace cm
