#include "reconcile_grid.h"

#include <algorithm>
#include <bit>
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

namespace {

// The hull's cells along lines of the grid parallel to one axis c, as 64-bit words: a mask
// that contains c is kept as one bit row along c per cell of its other axis, so a line's
// cells inside every mask are a few word ANDs, not a walk over every cell and mask.
class HullLines {
public:
    HullLines(const ReconcileGrid& g, const std::vector<const AxisMask*>& groups, int c)
        : g_(g), c_(c), words_((g.n[std::size_t(c)] + 63) / 64) {
        const int nc = g.n[std::size_t(c)];
        for (const AxisMask* m : groups) {
            if (m->a != c && m->b != c) {
                flat_.push_back(m);
                continue;
            }
            Rows r;
            r.other = m->a == c ? m->b : m->a;
            const int no = g.n[std::size_t(r.other)];
            r.bits.assign(std::size_t(no) * words_, 0);
            for (int o = 0; o < no; ++o)
                for (int k = 0; k < nc; ++k) {
                    const std::size_t q =
                        m->a == c ? std::size_t(k) + std::size_t(nc) * o : std::size_t(o) + std::size_t(no) * k;
                    if (m->in[q]) r.bits[std::size_t(o) * words_ + std::size_t(k / 64)] |= std::uint64_t(1) << (k % 64);
                }
            rows_.push_back(std::move(r));
        }
    }

    /// The words of the line through idx (its coordinate along c ignored) inside every mask,
    /// written to `out` (words() long); false when a mask without c leaves it out whole.
    bool line(std::array<int, 3> idx, std::uint64_t* out) const {
        for (const AxisMask* m : flat_)
            if (!m->in[std::size_t(idx[std::size_t(m->a)]) +
                       std::size_t(g_.n[std::size_t(m->a)]) * std::size_t(idx[std::size_t(m->b)])])
                return false;
        const int nc = g_.n[std::size_t(c_)];
        for (int w = 0; w < words_; ++w)
            out[w] = (w + 1) * 64 <= nc ? ~std::uint64_t(0) : (std::uint64_t(1) << (nc - w * 64)) - 1;
        for (const Rows& r : rows_) {
            const std::uint64_t* b = r.bits.data() + std::size_t(idx[std::size_t(r.other)]) * words_;
            for (int w = 0; w < words_; ++w) out[w] &= b[w];
        }
        return true;
    }
    int words() const { return words_; }

private:
    struct Rows {
        int other = 0;
        std::vector<std::uint64_t> bits;
    };
    const ReconcileGrid& g_;
    int c_, words_;
    std::vector<const AxisMask*> flat_;
    std::vector<Rows> rows_;
};

} // namespace

std::vector<std::uint8_t> missing_cells(const ReconcileGrid& g, const AxisMask& own,
                                        const std::vector<const AxisMask*>& groups) {
    const int a = own.a, b = own.b, c = 3 - a - b;
    const int na = g.n[std::size_t(a)], nb = g.n[std::size_t(b)];
    const HullLines lines(g, groups, c);
    std::vector<std::uint8_t> out(own.in.size(), 0);
    tbb::parallel_for(0, nb, [&](int j) {
        std::vector<std::uint64_t> acc(std::size_t(lines.words()));
        std::array<int, 3> idx{0, 0, 0};
        idx[std::size_t(b)] = j;
        for (int i = 0; i < na; ++i) {
            const std::size_t cell = std::size_t(i) + std::size_t(na) * j;
            if (!own.in[cell]) continue;
            idx[std::size_t(a)] = i;
            const bool hit = lines.line(idx, acc.data()) &&
                             std::any_of(acc.begin(), acc.end(), [](std::uint64_t w) { return w != 0; });
            out[cell] = hit ? 0 : 1;
        }
    });
    return out;
}

double hull_share(const ReconcileGrid& g, const std::vector<const AxisMask*>& groups) {
    const int nx = g.n[0], ny = g.n[1], nz = g.n[2];
    const HullLines lines(g, groups, 2);
    std::vector<double> per(std::size_t(ny), 0.0);
    tbb::parallel_for(0, ny, [&](int j) {
        std::vector<std::uint64_t> acc(std::size_t(lines.words()));
        double n = 0;
        for (int i = 0; i < nx; ++i)
            if (lines.line({i, j, 0}, acc.data()))
                for (std::uint64_t w : acc) n += std::popcount(w);
        per[std::size_t(j)] = n;
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
