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
    // The columns go in tiles of kTile side by side, gathered into (and scattered back
    // from) contiguous lines a row of the tile at a time: a column read on its own touches
    // one cache line per pixel, and an image of 2048 rows does not stay in the first-level
    // cache between neighbouring columns.
    constexpr int kTile = 16;
    const int tiles = (w + kTile - 1) / kTile;
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> lines(std::size_t(kTile) * h), d(h);
        for (int t = r.begin(); t != r.end(); ++t) {
            const int x0 = t * kTile, nx = std::min(kTile, w - x0);
            for (int y = 0; y < h; ++y) {
                const char* s = seed.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) lines[std::size_t(b) * h + y] = s[b] ? 0.0f : kEdtFar;
            }
            // Along a column the input is only seed (0) or not (kEdtFar), so its transform is
            // the square of the distance to the nearest seed above or below: two sweeps, the
            // same values as the general 1D transform (integers, exact in float).
            for (int b = 0; b < nx; ++b) {
                float* f = lines.data() + std::size_t(b) * h;
                int last = -1; // the latest seed row of the downward sweep
                for (int y = 0; y < h; ++y) {
                    if (f[y] == 0.0f) last = y;
                    d[std::size_t(y)] = last < 0 ? -1.0f : float(y - last);
                }
                if (last < 0) continue; // no seed: kEdtFar throughout
                int next = -1;
                for (int y = h - 1; y >= 0; --y) {
                    if (f[y] == 0.0f) next = y;
                    float dist = d[std::size_t(y)];
                    if (next >= 0 && (dist < 0 || float(next - y) < dist)) dist = float(next - y);
                    f[y] = dist * dist;
                }
            }
            for (int y = 0; y < h; ++y) {
                float* row = g.data() + std::size_t(y) * w + x0;
                for (int b = 0; b < nx; ++b) row[b] = lines[std::size_t(b) * h + y];
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
