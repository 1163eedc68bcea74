// Exact Euclidean distance transform of a binary image (Felzenszwalb and Huttenlocher 2012).
#include "geometry/distance_transform.h"

#include <algorithm>
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
    for (std::size_t i = 0; i < g.size(); ++i) g[i] = seed[i] ? 0.0f : kEdtFar;
    // Columns, then rows. A line that is all seeds stays 0 and a line without any stays
    // kEdtFar (kEdtFar + n^2 rounds back to kEdtFar in float): both are skipped, which
    // for a silhouette is most of the image (its box is a fraction of the frame).
    tbb::parallel_for(tbb::blocked_range<int>(0, w, 16), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> f(h), d(h), z(h + 1);
        std::vector<int> v(h);
        for (int x = r.begin(); x != r.end(); ++x) {
            bool any = false, all = true;
            for (int y = 0; y < h; ++y) {
                f[y] = g[std::size_t(y) * w + x];
                any |= f[y] == 0.0f;
                all &= f[y] == 0.0f;
            }
            if (!any || all) continue;
            edt_1d(f.data(), d.data(), h, v.data(), z.data());
            for (int y = 0; y < h; ++y) g[std::size_t(y) * w + x] = d[y];
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> f(w), z(w + 1);
        std::vector<int> v(w);
        for (int y = r.begin(); y != r.end(); ++y) {
            float* row = g.data() + std::size_t(y) * w;
            if (std::all_of(row, row + w, [](float x) { return x == 0.0f; })) continue;
            std::copy(row, row + w, f.begin());
            edt_1d(f.data(), row, w, v.data(), z.data());
        }
    });
    return g;
}

} // namespace cm
