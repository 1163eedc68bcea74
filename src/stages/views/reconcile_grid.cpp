#include "reconcile_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace cm {

ReconcileGrid ReconcileGrid::over(const Vec3d& lo, const Vec3d& size, int cells) {
    ReconcileGrid g;
    g.lo = lo;
    const double longest = std::max({size.x, size.y, size.z});
    for (int k = 0; k < 3; ++k) {
        g.n[std::size_t(k)] = std::max(1, int(std::ceil(size[k] / longest * cells - 1e-9)));
        g.h[std::size_t(k)] = size[k] > 0 ? size[k] / g.n[std::size_t(k)] : 1.0;
    }
    return g;
}

AxisMask sample_mask(const ReconcileGrid& g, int a, int b, const std::function<bool(const Vec3d&)>& inside) {
    AxisMask m;
    m.a = a, m.b = b;
    const int na = g.n[std::size_t(a)], nb = g.n[std::size_t(b)];
    const int c = 3 - a - b;
    m.in.assign(std::size_t(na) * nb, 0);
    tbb::parallel_for(0, nb, [&](int j) {
        std::array<int, 3> idx{0, 0, 0};
        idx[std::size_t(b)] = j;
        idx[std::size_t(c)] = g.n[std::size_t(c)] / 2;
        for (int i = 0; i < na; ++i) {
            idx[std::size_t(a)] = i;
            m.in[std::size_t(i) + std::size_t(na) * j] = inside(g.centre(idx[0], idx[1], idx[2])) ? 1 : 0;
        }
    });
    return m;
}

AxisMask merge_masks(const std::vector<const AxisMask*>& masks, const std::string& mode) {
    AxisMask m = *masks.front();
    if (mode == "primary") return m;
    for (std::size_t k = 1; k < masks.size(); ++k)
        for (std::size_t i = 0; i < m.in.size(); ++i)
            m.in[i] = mode == "union" ? (m.in[i] | masks[k]->in[i]) : (m.in[i] & masks[k]->in[i]);
    return m;
}

std::vector<std::uint8_t> missing_cells(const ReconcileGrid& g, const AxisMask& own,
                                        const std::vector<const AxisMask*>& groups) {
    const int a = own.a, b = own.b, c = 3 - a - b;
    const int na = g.n[std::size_t(a)], nb = g.n[std::size_t(b)], nc = g.n[std::size_t(c)];
    std::vector<std::uint8_t> out(own.in.size(), 0);
    tbb::parallel_for(0, nb, [&](int j) {
        std::array<int, 3> idx{0, 0, 0};
        idx[std::size_t(b)] = j;
        for (int i = 0; i < na; ++i) {
            const std::size_t cell = std::size_t(i) + std::size_t(na) * j;
            if (!own.in[cell]) continue;
            idx[std::size_t(a)] = i;
            bool hit = false;
            for (int k = 0; k < nc && !hit; ++k) {
                idx[std::size_t(c)] = k;
                hit = true;
                for (const AxisMask* m : groups) {
                    const std::size_t q = std::size_t(idx[std::size_t(m->a)]) +
                                          std::size_t(g.n[std::size_t(m->a)]) * std::size_t(idx[std::size_t(m->b)]);
                    if (!m->in[q]) {
                        hit = false;
                        break;
                    }
                }
            }
            out[cell] = hit ? 0 : 1;
        }
    });
    return out;
}

double hull_share(const ReconcileGrid& g, const std::vector<const AxisMask*>& groups) {
    const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
    std::vector<double> per(std::size_t(nz), 0.0);
    tbb::parallel_for(0, nz, [&](int k) {
        double n = 0;
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const std::array<int, 3> idx{i, j, k};
                bool in = true;
                for (const AxisMask* m : groups) {
                    const std::size_t q = std::size_t(idx[std::size_t(m->a)]) +
                                          std::size_t(g.n[std::size_t(m->a)]) * std::size_t(idx[std::size_t(m->b)]);
                    if (!m->in[q]) {
                        in = false;
                        break;
                    }
                }
                n += in;
            }
        per[std::size_t(k)] = n;
    });
    double n = 0;
    for (double x : per) n += x;
    return n / (double(nx) * ny * nz);
}

std::vector<float> distance_to_mask(const ReconcileGrid& g, const AxisMask& m) {
    const int na = g.n[std::size_t(m.a)], nb = g.n[std::size_t(m.b)];
    const float far = std::numeric_limits<float>::max() / 4, d1 = 1.0f, d2 = 1.41421356f;
    std::vector<float> d(m.in.size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = m.in[i] ? 0.0f : far;
    auto at = [&](int i, int j) -> float& { return d[std::size_t(i) + std::size_t(na) * j]; };
    // Two passes of the 3x3 chamfer, forward then backward.
    for (int j = 0; j < nb; ++j)
        for (int i = 0; i < na; ++i) {
            float& v = at(i, j);
            if (i > 0) v = std::min(v, at(i - 1, j) + d1);
            if (j > 0) {
                v = std::min(v, at(i, j - 1) + d1);
                if (i > 0) v = std::min(v, at(i - 1, j - 1) + d2);
                if (i + 1 < na) v = std::min(v, at(i + 1, j - 1) + d2);
            }
        }
    for (int j = nb - 1; j >= 0; --j)
        for (int i = na - 1; i >= 0; --i) {
            float& v = at(i, j);
            if (i + 1 < na) v = std::min(v, at(i + 1, j) + d1);
            if (j + 1 < nb) {
                v = std::min(v, at(i, j + 1) + d1);
                if (i + 1 < na) v = std::min(v, at(i + 1, j + 1) + d2);
                if (i > 0) v = std::min(v, at(i - 1, j + 1) + d2);
            }
        }
    return d;
}

} // namespace cm
