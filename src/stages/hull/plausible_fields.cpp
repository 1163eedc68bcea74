#include "plausible_fields.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace cm::plausible {

// 3x3 box passes over a raster, normalised over the cells not `masked` (all when null);
// masked cells keep their value.
void box_blur(std::vector<float>& f, const std::vector<char>* masked, int w, int h, int passes) {
    std::vector<float> tmp(f.size());
    for (int k = 0; k < passes; ++k) {
        tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
            for (int j = rows.begin(); j != rows.end(); ++j)
                for (int i = 0; i < w; ++i) {
                    const std::size_t c = std::size_t(j) * w + i;
                    if (masked && (*masked)[c]) {
                        tmp[c] = f[c];
                        continue;
                    }
                    float sum = 0;
                    int cnt = 0;
                    for (int dj = -1; dj <= 1; ++dj)
                        for (int di = -1; di <= 1; ++di) {
                            const int x = i + di, y = j + dj;
                            if (x < 0 || y < 0 || x >= w || y >= h) continue;
                            const std::size_t q = std::size_t(y) * w + x;
                            if (masked && (*masked)[q]) continue;
                            sum += f[q];
                            ++cnt;
                        }
                    tmp[c] = sum / float(cnt);
                }
        });
        f.swap(tmp);
    }
}

namespace {

using BoolLeaves = openvdb::tree::LeafManager<openvdb::BoolTree>;
constexpr int kDim = int(openvdb::BoolTree::LeafNodeType::DIM);

// The steps of smooth_field(): the voxels' sums and counts on a coarse lattice (`f` cells a
// lattice cell, starting on a leaf corner, so no lattice cell straddles two leaves (f divides
// 8) and leaves fill their own cells in parallel), binomial passes there, then back to the
// voxels trilinearly.
class FieldSmoother {
public:
    FieldSmoother(UninitVector<float>& value, const BoolLeaves& leaves, const std::vector<std::size_t>& base,
                  const openvdb::CoordBBox& box, double sigma, float reach)
        : value_(value),
          leaves_(leaves),
          base_(base),
          reach_(reach),
          f_(lattice_step(sigma)),
          lo_(box.min().x() & ~7, box.min().y() & ~7, box.min().z() & ~7),
          nx_((box.max().x() - lo_.x()) / f_ + 1),
          ny_((box.max().y() - lo_.y()) / f_ + 1),
          nz_((box.max().z() - lo_.z()) / f_ + 1) {}

    /// The voxels' sums and counts on the lattice.
    void bin();
    /// Binomial passes: each adds 1/2 coarse cell^2 of variance; the cell means f^2 - 1 over
    /// 12 and the trilinear way back about f^2 / 6 fine cells^2.
    void blur(double sigma);
    /// Back to the voxels: the normalised trilinear value about the cell centres. Voxels whose
    /// value lies farther than `reach` from 0 keep theirs.
    void sample();

private:
    // Per axis and local coordinate of a leaf: the lower padded lattice index and the weight
    // of the upper.
    struct Weights {
        int c0[3][8];
        double t[3][8];
    };
    static int lattice_step(double sigma) {
        int f = 1;
        while (f < 8 && 2 * f <= sigma) f *= 2;
        return f;
    }
    std::size_t at(int i, int j, int k) const {
        return (std::size_t(i) * std::size_t(ny_) + std::size_t(j)) * std::size_t(nz_) + std::size_t(k);
    }
    std::size_t pat(int i, int j, int k) const {
        return (std::size_t(i) * py_ + std::size_t(j)) * pz_ + std::size_t(k);
    }
    // body(voxel index, local x, y, z) for the on voxels of leaf l, from its mask's words.
    template <typename Body>
    void for_leaf(std::size_t l, Body&& body) const {
        const auto& mask = leaves_.leaf(l).getValueMask();
        std::size_t i = base_[l];
        for (openvdb::Index w = 0; w < 8; ++w)
            for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1, ++i) {
                const int b = __builtin_ctzll(word);
                body(i, int(w), b >> 3, b & 7);
            }
    }
    void pad();
    Weights weights(std::size_t l) const;
    void sample_few(std::size_t l, const Weights& wt);
    void sample_block(std::size_t l, const Weights& wt);

    UninitVector<float>& value_;
    const BoolLeaves& leaves_;
    const std::vector<std::size_t>& base_;
    const float reach_;
    const int f_;
    const Coord lo_;
    const int nx_, ny_, nz_;
    std::vector<float> sum_, weight_;
    // The lattice with a cell of zeros on every side (so no neighbour needs a bounds test),
    // sum and weight side by side.
    int px_ = 0, py_ = 0, pz_ = 0;
    std::vector<std::array<float, 2>> padded_;
};

void FieldSmoother::bin() {
    const std::size_t total = std::size_t(nx_) * std::size_t(ny_) * std::size_t(nz_);
    sum_.assign(total, 0.0f);
    weight_.assign(total, 0.0f);
    // A leaf's cells are its own: it sums them in its voxels' order (as adding into the lattice
    // would), then stores them. f is a power of 2.
    const int n = kDim / f_, shift = __builtin_ctz(unsigned(f_));
    tbb::parallel_for(std::size_t(0), leaves_.leafCount(), [&](std::size_t l) {
        std::array<float, kDim * kDim * kDim> sum, weight;
        std::fill_n(sum.begin(), n * n * n, 0.0f);
        std::fill_n(weight.begin(), n * n * n, 0.0f);
        for_leaf(l, [&](std::size_t i, int x, int y, int z) {
            const std::size_t c = std::size_t((((x >> shift) * n) + (y >> shift)) * n + (z >> shift));
            sum[c] += value_[i];
            weight[c] += 1.0f;
        });
        const Coord o = leaves_.leaf(l).origin() - lo_;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                for (int c = 0; c < n; ++c) {
                    const std::size_t k = std::size_t((a * n + b) * n + c);
                    if (weight[k] == 0.0f) continue; // (cells past the box hold no voxel)
                    const std::size_t q = at(o.x() / f_ + a, o.y() / f_ + b, o.z() / f_ + c);
                    sum_[q] = sum[k];
                    weight_[q] = weight[k];
                }
    });
}

void FieldSmoother::blur(double sigma) {
    const double f = f_;
    const double left = sigma * sigma - (f * f - 1) / 12.0 - f * f / 6.0;
    const int passes = std::max(0, int(std::lround(left / (0.5 * f * f))));
    std::vector<float> tmp(sum_.size());
    for (int pass = 0; pass < passes; ++pass)
        for (std::vector<float>* a : {&sum_, &weight_})
            for (int axis = 0; axis < 3; ++axis) {
                std::vector<float>& src = *a;
                const std::size_t st =
                    axis == 0 ? std::size_t(ny_) * std::size_t(nz_) : (axis == 1 ? std::size_t(nz_) : 1);
                const int len = axis == 0 ? nx_ : (axis == 1 ? ny_ : nz_);
                tbb::parallel_for(tbb::blocked_range<int>(0, nx_), [&](const tbb::blocked_range<int>& xs) {
                    for (int x = xs.begin(); x != xs.end(); ++x)
                        for (int y = 0; y < ny_; ++y)
                            for (int z = 0; z < nz_; ++z) {
                                const std::size_t c = at(x, y, z);
                                const int pos = axis == 0 ? x : (axis == 1 ? y : z);
                                const float lo_v = pos > 0 ? src[c - st] : 0.0f;
                                const float hi_v = pos + 1 < len ? src[c + st] : 0.0f;
                                tmp[c] = 0.25f * lo_v + 0.5f * src[c] + 0.25f * hi_v;
                            }
                });
                src.swap(tmp);
            }
}

void FieldSmoother::pad() {
    px_ = nx_ + 2, py_ = ny_ + 2, pz_ = nz_ + 2;
    padded_.assign(std::size_t(px_) * py_ * pz_, {0.0f, 0.0f});
    tbb::parallel_for(0, nx_, [&](int x) {
        for (int y = 0; y < ny_; ++y)
            for (int z = 0; z < nz_; ++z) padded_[pat(x + 1, y + 1, z + 1)] = {sum_[at(x, y, z)], weight_[at(x, y, z)]};
    });
    sum_ = {};
    weight_ = {};
}

void FieldSmoother::sample() {
    pad();
    tbb::parallel_for(std::size_t(0), leaves_.leafCount(), [&](std::size_t l) {
        const Weights wt = weights(l);
        if (leaves_.leaf(l).onVoxelCount() < 64) sample_few(l, wt);
        else sample_block(l, wt);
    });
}

FieldSmoother::Weights FieldSmoother::weights(std::size_t l) const {
    const double half = 0.5 * (f_ - 1);
    const Coord o = leaves_.leaf(l).origin() - lo_;
    Weights wt;
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 8; ++k) {
            const double p = (o[a] + k - half) / f_;
            const int q = int(std::floor(p));
            // Grid points of the leaf beyond the box (never on voxels) read the last cells.
            wt.c0[a][k] = std::min(q + 1, (a == 0 ? px_ : a == 1 ? py_ : pz_) - 2);
            wt.t[a][k] = p - q;
        }
    return wt;
}

// A few voxels: each from its 8 corners.
void FieldSmoother::sample_few(std::size_t l, const Weights& wt) {
    const std::size_t sx = std::size_t(py_) * pz_, sy = std::size_t(pz_);
    for_leaf(l, [&](std::size_t i, int x, int y, int z) {
        if (!(std::abs(value_[i]) <= reach_)) return;
        const std::size_t q = pat(wt.c0[0][x], wt.c0[1][y], wt.c0[2][z]);
        const double tx = wt.t[0][x], ty = wt.t[1][y], tz = wt.t[2][z];
        double s = 0, w = 0;
        for (int k = 0; k < 8; ++k) {
            const double wk = ((k & 1) ? tx : 1 - tx) * (((k >> 1) & 1) ? ty : 1 - ty) * (((k >> 2) & 1) ? tz : 1 - tz);
            const auto& cell = padded_[q + ((k & 1) ? sx : 0) + (((k >> 1) & 1) ? sy : 0) + (((k >> 2) & 1) ? 1 : 0)];
            s += wk * cell[0];
            w += wk * cell[1];
        }
        if (w > 1e-6) value_[i] = float(s / w);
    });
}

// Many: the whole block, one axis at a time (z, then y, then x) over the lattice cells the
// leaf reaches (at most 10 along an axis).
void FieldSmoother::sample_block(std::size_t l, const Weights& wt) {
    constexpr int kSpan = 10;
    const auto& c0 = wt.c0;
    const auto& t = wt.t;
    int base_c[3], span[3];
    for (int a = 0; a < 3; ++a) base_c[a] = c0[a][0], span[a] = c0[a][7] + 2 - c0[a][0];
    double zs[kSpan][kSpan][8][2], ys[kSpan][8][8][2];
    for (int i = 0; i < span[0]; ++i)
        for (int j = 0; j < span[1]; ++j) {
            const std::size_t row = pat(base_c[0] + i, base_c[1] + j, 0);
            for (int z = 0; z < 8; ++z) {
                const auto& a = padded_[row + std::size_t(c0[2][z])];
                const auto& b = padded_[row + std::size_t(c0[2][z]) + 1];
                const double tz = t[2][z];
                zs[i][j][z][0] = (1 - tz) * a[0] + tz * b[0];
                zs[i][j][z][1] = (1 - tz) * a[1] + tz * b[1];
            }
        }
    for (int i = 0; i < span[0]; ++i)
        for (int y = 0; y < 8; ++y) {
            const int j = c0[1][y] - base_c[1];
            const double ty = t[1][y];
            for (int z = 0; z < 8; ++z)
                for (int c = 0; c < 2; ++c) ys[i][y][z][c] = (1 - ty) * zs[i][j][z][c] + ty * zs[i][j + 1][z][c];
        }
    for_leaf(l, [&](std::size_t i, int x, int y, int z) {
        if (!(std::abs(value_[i]) <= reach_)) return;
        const int k = c0[0][x] - base_c[0];
        const double tx = t[0][x];
        const double s = (1 - tx) * ys[k][y][z][0] + tx * ys[k + 1][y][z][0];
        const double w = (1 - tx) * ys[k][y][z][1] + tx * ys[k + 1][y][z][1];
        if (w > 1e-6) value_[i] = float(s / w);
    });
}

} // namespace

void smooth_field(UninitVector<float>& value, const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                  const std::vector<std::size_t>& base, const openvdb::CoordBBox& box, double sigma, float reach) {
    if (!(sigma > 0) || leaves.leafCount() == 0) return;
    FieldSmoother smoother(value, leaves, base, box, sigma, reach);
    smoother.bin();
    smoother.blur(sigma);
    smoother.sample();
}

SwellField::SwellField(const openvdb::CoordBBox& box, int f) : lo_(box.min()), f_(std::max(1, f)) {
    const Coord d = box.dim();
    nx_ = d.x() / f_ + 2, ny_ = d.y() / f_ + 2, nz_ = d.z() / f_ + 2;
    g_.assign(std::size_t(nx_) * ny_ * nz_, 0.0f);
    // Per axis, the lattice cell and weight of each grid point with a cell above it: the
    // same divisions and floors as sampling would do, done once.
    const int n[3] = {nx_, ny_, nz_};
    for (int a = 0; a < 3; ++a) {
        steps_[a].resize(std::size_t(n[a] - 1) * std::size_t(f_));
        for (std::size_t q = 0; q < steps_[a].size(); ++q) {
            const double p = double(int(q)) / f_;
            const int i = int(std::floor(p));
            steps_[a][q] = {i, p - i};
        }
    }
}

void SwellField::seed(const Coord& c, float value) {
    if (!(value > 0)) return;
    const Coord q = c - lo_;
    const int i = std::clamp(int(std::lround(double(q.x()) / f_)), 0, nx_ - 1),
              j = std::clamp(int(std::lround(double(q.y()) / f_)), 0, ny_ - 1),
              k = std::clamp(int(std::lround(double(q.z()) / f_)), 0, nz_ - 1);
    seeds_.push_back({std::uint32_t((std::size_t(i) * ny_ + j) * nz_ + k), value});
    any_ = true;
}

template <typename Body>
void SwellField::for_box(const Box& b, Body&& body) const {
    if (b.x0 > b.x1 || b.y0 > b.y1 || b.z0 > b.z1) return;
    tbb::parallel_for(tbb::blocked_range<int>(b.x0, b.x1 + 1), [&](const tbb::blocked_range<int>& xs) {
        for (int x = xs.begin(); x != xs.end(); ++x)
            for (int y = b.y0; y <= b.y1; ++y)
                body((std::size_t(x) * ny_ + y) * nz_ + std::size_t(b.z0), std::size_t(b.z1 - b.z0 + 1));
    });
}

void SwellField::settle() {
    if (seeds_.empty()) return;
    // The lattice was raised only in the last box: clear it there.
    if (last_.empty()) last_.assign(g_.size(), 0.0f), tmp_.assign(g_.size(), 0.0f);
    for (std::vector<float>* a : {&last_, &tmp_})
        for_box(box_, [&](std::size_t c0, std::size_t n) { std::fill_n(a->begin() + std::ptrdiff_t(c0), n, 0.0f); });
    // One seed a coarse cell (the largest): the cells' largest values gathered in tmp_ (all 0
    // here), then taken back out in the seeds' order.
    std::vector<std::pair<std::uint32_t, float>> top;
    for (const auto& [c, value] : seeds_) tmp_[c] = std::max(tmp_[c], value);
    for (const auto& [c, value] : seeds_)
        if (tmp_[c] > 0) top.push_back({c, tmp_[c]}), tmp_[c] = 0.0f;
    seeds_.clear();
    // The balls (each cell takes the largest value of those reaching it, in any order), by
    // slabs of coarse x, each thread writing only its own slab; and the box they fill.
    Box box{nx_, -1, ny_, -1, nz_, -1};
    for (const auto& [c, value] : top) {
        const int i = int(c / (std::size_t(ny_) * nz_)), j = int(c / nz_ % ny_), k = int(c % nz_);
        const int ir = int(std::ceil((double(value) + 2 * f_) / f_));
        box.x0 = std::min(box.x0, std::max(0, i - ir)), box.x1 = std::max(box.x1, std::min(nx_ - 1, i + ir));
        box.y0 = std::min(box.y0, std::max(0, j - ir)), box.y1 = std::max(box.y1, std::min(ny_ - 1, j + ir));
        box.z0 = std::min(box.z0, std::max(0, k - ir)), box.z1 = std::max(box.z1, std::min(nz_ - 1, k + ir));
    }
    std::vector<float>& raised = last_;
    tbb::parallel_for(tbb::blocked_range<int>(box.x0, box.x1 + 1, 2), [&](const tbb::blocked_range<int>& xs) {
        for (const auto& [c, value] : top) {
            const int i = int(c / (std::size_t(ny_) * nz_)), j = int(c / nz_ % ny_), k = int(c % nz_);
            const double rad = (double(value) + 2 * f_) / f_;
            const int ir = int(std::ceil(rad));
            for (int x = std::max(xs.begin(), i - ir); x <= std::min(xs.end() - 1, i + ir); ++x)
                for (int y = std::max(0, j - ir); y <= std::min(ny_ - 1, j + ir); ++y)
                    for (int z = std::max(0, k - ir); z <= std::min(nz_ - 1, k + ir); ++z) {
                        const double dd = double(x - i) * (x - i) + double(y - j) * (y - j) + double(z - k) * (z - k);
                        if (dd > rad * rad) continue;
                        float& g = raised[(std::size_t(x) * ny_ + y) * nz_ + z];
                        g = std::max(g, value);
                    }
        }
    });
    // Two [1 2 1] passes along each axis (the balls' steps become slopes): each reaches a cell
    // farther, so the box grows by two cells a side and the rest stays 0.
    box.x0 = std::max(0, box.x0 - 2), box.x1 = std::min(nx_ - 1, box.x1 + 2);
    box.y0 = std::max(0, box.y0 - 2), box.y1 = std::min(ny_ - 1, box.y1 + 2);
    box.z0 = std::max(0, box.z0 - 2), box.z1 = std::min(nz_ - 1, box.z1 + 2);
    for (int pass = 0; pass < 2; ++pass)
        for (int axis = 0; axis < 3; ++axis) {
            const std::size_t st = axis == 0 ? std::size_t(ny_) * nz_ : (axis == 1 ? std::size_t(nz_) : 1);
            const int len = axis == 0 ? nx_ : (axis == 1 ? ny_ : nz_);
            const std::vector<float>& src = last_;
            std::vector<float>& dst = tmp_;
            tbb::parallel_for(tbb::blocked_range<int>(box.x0, box.x1 + 1), [&](const tbb::blocked_range<int>& xs) {
                for (int x = xs.begin(); x != xs.end(); ++x)
                    for (int y = box.y0; y <= box.y1; ++y)
                        for (int z = box.z0; z <= box.z1; ++z) {
                            const std::size_t c = (std::size_t(x) * ny_ + y) * nz_ + z;
                            const int pos = axis == 0 ? x : (axis == 1 ? y : z);
                            const float a = pos > 0 ? src[c - st] : 0.0f;
                            const float b = pos + 1 < len ? src[c + st] : 0.0f;
                            dst[c] = 0.25f * (a + 2 * src[c] + b);
                        }
            });
            last_.swap(tmp_);
        }
    for_box(box, [&](std::size_t c0, std::size_t n) {
        for (std::size_t c = c0; c < c0 + n; ++c) g_[c] += last_[c];
    });
    box_ = box;
}

// The trilinear value about lattice cell `g` (its neighbours sx, sy and 1 cells on) for
// weights tx, ty, tz of the upper cells: the corners in turn (x fastest), each weighted by the
// product of its axes' weights, x, y then z. (No corner weighs below 0 and the lattice holds no
// value below 0, so a corner of weight 0 adds 0.)
static double trilinear(const float* g, std::size_t sx, std::size_t sy, double tx, double ty, double tz) {
    const double x0 = 1 - tx, y0 = 1 - ty, z0 = 1 - tz;
    double v = 0;
    v += x0 * y0 * z0 * g[0];
    v += tx * y0 * z0 * g[sx];
    v += x0 * ty * z0 * g[sy];
    v += tx * ty * z0 * g[sx + sy];
    v += x0 * y0 * tz * g[1];
    v += tx * y0 * tz * g[sx + 1];
    v += x0 * ty * tz * g[sy + 1];
    v += tx * ty * tz * g[sx + sy + 1];
    return v;
}

float SwellField::at(const Coord& c) const {
    if (!any_) return 0.0f;
    const Coord q = c - lo_;
    // Outside the steps, the cell or the one above it lies off the lattice.
    for (int a = 0; a < 3; ++a)
        if (q[a] < 0 || std::size_t(q[a]) >= steps_[a].size()) return 0.0f;
    const Step& x = steps_[0][std::size_t(q.x())];
    const Step& y = steps_[1][std::size_t(q.y())];
    const Step& z = steps_[2][std::size_t(q.z())];
    const std::size_t sy = std::size_t(nz_), sx = std::size_t(ny_) * sy;
    return float(
        trilinear(g_.data() + std::size_t(x.i) * sx + std::size_t(y.i) * sy + std::size_t(z.i), sx, sy, x.t, y.t, z.t));
}

SwellField::Block::Block(const SwellField& f, const Coord& origin) : f_(f) {
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 8; ++k) {
            // As at(): the cell below and the upper one's weight.
            const int q = origin[a] + k - f.lo_[a];
            const bool in = q >= 0 && std::size_t(q) < f.steps_[a].size();
            c0_[a][k] = in ? f.steps_[a][std::size_t(q)].i : -1;
            t_[a][k] = in ? f.steps_[a][std::size_t(q)].t : 0.0;
        }
}

float SwellField::Block::at(int x, int y, int z) const {
    if (!f_.any_) return 0.0f;
    const int i = c0_[0][x], j = c0_[1][y], k = c0_[2][z];
    if (i < 0 || j < 0 || k < 0) return 0.0f;
    const std::size_t sy = std::size_t(f_.nz_), sx = std::size_t(f_.ny_) * sy;
    return float(trilinear(f_.g_.data() + std::size_t(i) * sx + std::size_t(j) * sy + std::size_t(k), sx, sy, t_[0][x],
                           t_[1][y], t_[2][z]));
}

// The coarse cells whose values reach the grid points of `b` (trilinearly), within the cells
// `within` (x0, x1, y0, y1, z0, z1, bounds included) when given: calls body(cell index) until
// it returns true; returns whether one did.
template <typename Body>
static bool any_coarse(const Coord& lo_, int f_, int nx_, int ny_, int nz_, const openvdb::CoordBBox& b, Body&& body,
                       const std::array<int, 6>* within = nullptr) {
    const Coord lo = b.min() - lo_, hi = b.max() - lo_;
    const int i0 = std::clamp(int(std::floor(double(lo.x()) / f_)), 0, nx_ - 1),
              i1 = std::clamp(int(std::floor(double(hi.x()) / f_)) + 1, 0, nx_ - 1);
    const int j0 = std::clamp(int(std::floor(double(lo.y()) / f_)), 0, ny_ - 1),
              j1 = std::clamp(int(std::floor(double(hi.y()) / f_)) + 1, 0, ny_ - 1);
    const int k0 = std::clamp(int(std::floor(double(lo.z()) / f_)), 0, nz_ - 1),
              k1 = std::clamp(int(std::floor(double(hi.z()) / f_)) + 1, 0, nz_ - 1);
    const std::array<int, 6> all{0, nx_ - 1, 0, ny_ - 1, 0, nz_ - 1};
    const std::array<int, 6>& w = within ? *within : all;
    for (int i = std::max(i0, w[0]); i <= std::min(i1, w[1]); ++i)
        for (int j = std::max(j0, w[2]); j <= std::min(j1, w[3]); ++j)
            for (int k = std::max(k0, w[4]); k <= std::min(k1, w[5]); ++k)
                if (body((std::size_t(i) * ny_ + j) * nz_ + k)) return true;
    return false;
}

bool SwellField::raised_in(const openvdb::CoordBBox& b) const {
    if (last_.empty()) return false;
    // Outside the last box nothing was raised.
    const std::array<int, 6> within{box_.x0, box_.x1, box_.y0, box_.y1, box_.z0, box_.z1};
    return any_coarse(
        lo_, f_, nx_, ny_, nz_, b, [&](std::size_t c) { return last_[c] > 0; }, &within);
}

bool BallField::any_in(const openvdb::CoordBBox& b) const {
    if (!any_) return false;
    return any_coarse(lo_, f_, nx_, ny_, nz_, b,
                      [&](std::size_t c) { return g_[c] < std::numeric_limits<float>::infinity(); });
}

BallField::BallField(const openvdb::CoordBBox& box, int f) : lo_(box.min()), f_(std::max(1, f)) {
    const Coord d = box.dim();
    nx_ = d.x() / f_ + 2, ny_ = d.y() / f_ + 2, nz_ = d.z() / f_ + 2;
    g_.assign(std::size_t(nx_) * ny_ * nz_, std::numeric_limits<float>::infinity());
}

void BallField::settle(double reach) {
    if (balls_.empty()) return;
    any_ = true;
    // By slabs of coarse x, each thread writing only its own slab.
    tbb::parallel_for(tbb::blocked_range<int>(0, nx_, 4), [&](const tbb::blocked_range<int>& xs) {
        for (const Ball& b : balls_) {
            const double ext = (b.radius + reach) / f_;
            const double cx = (b.centre.x() - lo_.x()) / f_, cy = (b.centre.y() - lo_.y()) / f_,
                         cz = (b.centre.z() - lo_.z()) / f_;
            const int x0 = std::max(xs.begin(), int(std::ceil(cx - ext))),
                      x1 = std::min(xs.end() - 1, int(std::floor(cx + ext)));
            if (x0 > x1) continue;
            const int y0 = std::max(0, int(std::ceil(cy - ext))), y1 = std::min(ny_ - 1, int(std::floor(cy + ext)));
            const int z0 = std::max(0, int(std::ceil(cz - ext))), z1 = std::min(nz_ - 1, int(std::floor(cz + ext)));
            for (int x = x0; x <= x1; ++x)
                for (int y = y0; y <= y1; ++y)
                    for (int z = z0; z <= z1; ++z) {
                        const double dx = x - cx, dy = y - cy, dz = z - cz;
                        const float v = float(std::sqrt(dx * dx + dy * dy + dz * dz) * f_ - b.radius);
                        float& g = g_[(std::size_t(x) * ny_ + y) * nz_ + z];
                        g = std::min(g, v);
                    }
        }
    });
    balls_.clear();
}

float BallField::at(const Coord& c) const {
    constexpr float inf = std::numeric_limits<float>::infinity();
    if (!any_) return inf;
    const Coord q = c - lo_;
    const double fx = double(q.x()) / f_, fy = double(q.y()) / f_, fz = double(q.z()) / f_;
    const int i = int(std::floor(fx)), j = int(std::floor(fy)), k = int(std::floor(fz));
    if (i < 0 || j < 0 || k < 0 || i + 1 >= nx_ || j + 1 >= ny_ || k + 1 >= nz_) return inf;
    const double tx = fx - i, ty = fy - j, tz = fz - k;
    double v = 0;
    for (int n = 0; n < 8; ++n) {
        const int di = n & 1, dj = (n >> 1) & 1, dk = (n >> 2) & 1;
        const double wgt = (di ? tx : 1 - tx) * (dj ? ty : 1 - ty) * (dk ? tz : 1 - tz);
        if (wgt <= 0) continue;
        const float g = g_[(std::size_t(i + di) * ny_ + (j + dj)) * nz_ + (k + dk)];
        if (g == inf) return inf;
        v += wgt * g;
    }
    return float(v);
}

} // namespace cm::plausible
