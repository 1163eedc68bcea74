#include "plausible_coarse.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>

namespace cm::plausible {

namespace {

using LeafT = openvdb::BoolTree::LeafNodeType;
constexpr int kDim = int(LeafT::DIM);
// Lattice points along an axis about a leaf: at most 8 / stride + 2 (5 at stride 2).
constexpr int kMaxPoints = 6;

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

} // namespace

// A leaf's frame on the lattice: its first lattice point per axis (q0, in lattice steps), the
// points per axis about it (m), and per axis and voxel offset the lattice cell (from q0) and
// the weight of its upper point.
struct CoarseLattice::Frame {
    std::array<int, 3> q0{};
    int m = 0;
    std::array<std::array<int, kDim>, 3> cell{};
    std::array<std::array<float, kDim>, 3> t{};
    std::size_t at(int a, int b, int c) const { return std::size_t((a * m + b) * m + c); }
};

CoarseLattice::CoarseLattice(const Leaves& leaves, const std::vector<std::size_t>& base, int stride)
    : leaves_(leaves), base_(base), s_(std::clamp(stride, 2, 8)) {
    const std::size_t nleaf = leaves.leafCount();
    leaf_of_.reserve(nleaf * 2);
    for (std::size_t l = 0; l < nleaf; ++l) leaf_of_.emplace(leaf_key(leaves.leaf(l).origin()), std::uint32_t(l));
    exact_.assign(nleaf, LeafMask{});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nleaf), [&](const tbb::blocked_range<std::size_t>& r) {
        std::array<std::uint32_t, kMaxPoints * kMaxPoints * kMaxPoints> index;
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const Frame f = frame(l);
            points(l, f, index.data());
            const auto& mask = leaves_.leaf(l).getValueMask();
            LeafMask& ex = exact_[l];
            // Inside the hull every lattice point about the leaf is a voxel: its voxels on the
            // lattice are the exact ones.
            const std::size_t mm = std::size_t(f.m * f.m * f.m);
            if (std::none_of(index.begin(), index.begin() + std::ptrdiff_t(mm),
                             [](std::uint32_t i) { return i == kNone; })) {
                std::uint64_t yz = 0;
                for (int y = 0; y < kDim; ++y)
                    for (int z = 0; z < kDim; ++z)
                        if (f.t[1][std::size_t(y)] == 0 && f.t[2][std::size_t(z)] == 0)
                            yz |= std::uint64_t(1) << (y * 8 + z);
                for (openvdb::Index w = 0; w < 8; ++w) ex[w] = f.t[0][w] == 0 ? mask.getWord<std::uint64_t>(w) & yz : 0;
                continue;
            }
            for (openvdb::Index w = 0; w < 8; ++w)
                for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1) {
                    const int b = __builtin_ctzll(word);
                    const std::array<int, 3> o{int(w), b >> 3, b & 7};
                    std::array<int, 3> q{}, up{};
                    bool on_lattice = true;
                    for (std::size_t k = 0; k < 3; ++k) {
                        q[k] = f.cell[k][std::size_t(o[k])];
                        up[k] = f.t[k][std::size_t(o[k])] > 0 ? 1 : 0;
                        on_lattice = on_lattice && up[k] == 0;
                    }
                    bool held = false;
                    for (int a = 0; a <= up[0] && !held; ++a)
                        for (int bb = 0; bb <= up[1] && !held; ++bb)
                            for (int c = 0; c <= up[2] && !held; ++c)
                                held = index[f.at(q[0] + a, q[1] + bb, q[2] + c)] != kNone;
                    if (on_lattice || !held) ex[w] |= std::uint64_t(1) << b;
                }
        }
    });
}

CoarseLattice::Frame CoarseLattice::frame(std::size_t l) const {
    const Coord origin = leaves_.leaf(l).origin();
    Frame f;
    for (std::size_t k = 0; k < 3; ++k) {
        f.q0[k] = floor_div(origin[int(k)], s_);
        f.m = std::max(f.m, floor_div(origin[int(k)] + kDim - 1, s_) - f.q0[k] + 2);
        for (int i = 0; i < kDim; ++i) {
            const int q = floor_div(origin[int(k)] + i, s_);
            f.cell[k][std::size_t(i)] = q - f.q0[k];
            f.t[k][std::size_t(i)] = float(origin[int(k)] + i - q * s_) / float(s_);
        }
    }
    return f;
}

void CoarseLattice::points(std::size_t l, const Frame& f, std::uint32_t* index) const {
    const Coord origin = leaves_.leaf(l).origin();
    // The leaves about this one (a lattice point lies at most a leaf away), looked up once.
    std::array<std::int64_t, 27> near;
    near.fill(-2);
    for (int a = 0; a < f.m; ++a)
        for (int b = 0; b < f.m; ++b)
            for (int c = 0; c < f.m; ++c) {
                const Coord p((f.q0[0] + a) * s_, (f.q0[1] + b) * s_, (f.q0[2] + c) * s_);
                const Coord lo(p.x() & ~(kDim - 1), p.y() & ~(kDim - 1), p.z() & ~(kDim - 1));
                const int d = ((lo.x() - origin.x()) / kDim + 1) * 9 + ((lo.y() - origin.y()) / kDim + 1) * 3 +
                              ((lo.z() - origin.z()) / kDim + 1);
                std::int64_t& n = near[std::size_t(d)];
                if (n == -2) {
                    const auto it = leaf_of_.find(leaf_key(lo));
                    n = it == leaf_of_.end() ? -1 : std::int64_t(it->second);
                }
                std::uint32_t& out = index[f.at(a, b, c)];
                out = kNone;
                if (n < 0) continue;
                const auto& mask = leaves_.leaf(std::size_t(n)).getValueMask();
                const int x = p.x() - lo.x(), bit = (p.y() - lo.y()) * 8 + (p.z() - lo.z());
                const std::uint64_t word = mask.getWord<std::uint64_t>(openvdb::Index(x));
                if (!(word >> bit & 1)) continue;
                std::size_t rank = base_[std::size_t(n)];
                for (int w = 0; w < x; ++w)
                    rank += std::size_t(__builtin_popcountll(mask.getWord<std::uint64_t>(openvdb::Index(w))));
                rank += std::size_t(__builtin_popcountll(word & ((std::uint64_t(1) << bit) - 1)));
                out = std::uint32_t(rank);
            }
}

void CoarseLattice::interpolate(UninitVector<float>& value, UninitVector<std::uint8_t>* flags, std::uint8_t bit) const {
    tbb::parallel_for(std::size_t(0), leaves_.leafCount(),
                      [&](std::size_t l) { interpolate_leaf(l, value, flags, bit); });
}

// The lattice points about the leaf as (value, flag, 1) where the hull has them (zeros
// elsewhere); a few voxels each from the corners of its cell, many by the whole block one axis
// at a time (z, then y, then x).
void CoarseLattice::interpolate_leaf(std::size_t l, UninitVector<float>& value, UninitVector<std::uint8_t>* flags,
                                     std::uint8_t bit) const {
    const auto& mask = leaves_.leaf(l).getValueMask();
    const LeafMask& ex = exact_[l];
    int todo = 0;
    for (openvdb::Index w = 0; w < 8; ++w) todo += __builtin_popcountll(mask.getWord<std::uint64_t>(w) & ~ex[w]);
    if (todo == 0) return;
    const Frame f = frame(l);
    constexpr std::size_t kPoints = kMaxPoints * kMaxPoints * kMaxPoints;
    std::array<std::uint32_t, kPoints> index;
    points(l, f, index.data());
    std::array<std::array<float, 3>, kPoints> coarse;
    const std::size_t mm = std::size_t(f.m * f.m * f.m);
    for (std::size_t p = 0; p < mm; ++p) {
        const std::uint32_t i = index[p];
        if (i == kNone) coarse[p] = {0.0f, 0.0f, 0.0f};
        else coarse[p] = {value[i], flags && ((*flags)[i] & bit) ? 1.0f : 0.0f, 1.0f};
    }
    const auto put = [&](std::size_t i, const float* v) {
        if (!(v[2] > 0)) return; // not reached: such a voxel is exact
        value[i] = v[0] / v[2];
        if (flags) (*flags)[i] = std::uint8_t(v[1] >= 0.5f * v[2] ? (*flags)[i] | bit : (*flags)[i] & ~bit);
    };
    std::size_t i = base_[l];
    if (todo < 64) {
        for (openvdb::Index w = 0; w < 8; ++w)
            for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1, ++i) {
                const int b = __builtin_ctzll(word);
                if (ex[w] >> b & 1) continue;
                const std::array<int, 3> o{int(w), b >> 3, b & 7};
                float acc[3] = {0, 0, 0};
                for (int k = 0; k < 8; ++k) {
                    float wk = 1.0f;
                    std::array<int, 3> q{};
                    for (std::size_t a = 0; a < 3; ++a) {
                        const int hi = (k >> a) & 1;
                        const float t = f.t[a][std::size_t(o[a])];
                        wk *= hi ? t : 1.0f - t;
                        q[a] = f.cell[a][std::size_t(o[a])] + hi;
                    }
                    if (!(wk > 0)) continue;
                    const auto& c = coarse[f.at(q[0], q[1], q[2])];
                    for (int j = 0; j < 3; ++j) acc[j] += wk * c[j];
                }
                put(i, acc);
            }
        return;
    }
    const std::size_t m = std::size_t(f.m), d = std::size_t(kDim);
    const auto lerp3 = [](const float* lo, const float* hi, float t, float* out) {
        for (int j = 0; j < 3; ++j) out[j] = lo[j] + t * (hi[j] - lo[j]);
    };
    std::array<float, kMaxPoints * kMaxPoints * kDim * 3> along_z;
    std::array<float, kMaxPoints * kDim * kDim * 3> along_y;
    std::array<float, kDim * kDim * kDim * 3> dense;
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b)
            for (std::size_t z = 0; z < d; ++z) {
                const std::size_t c = std::size_t(f.cell[2][z]);
                lerp3(coarse[(a * m + b) * m + c].data(), coarse[(a * m + b) * m + c + 1].data(), f.t[2][z],
                      &along_z[((a * m + b) * d + z) * 3]);
            }
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t y = 0; y < d; ++y) {
            const std::size_t b = std::size_t(f.cell[1][y]);
            for (std::size_t z = 0; z < d; ++z)
                lerp3(&along_z[((a * m + b) * d + z) * 3], &along_z[((a * m + b + 1) * d + z) * 3], f.t[1][y],
                      &along_y[((a * d + y) * d + z) * 3]);
        }
    for (std::size_t x = 0; x < d; ++x) {
        const std::size_t a = std::size_t(f.cell[0][x]);
        for (std::size_t y = 0; y < d; ++y)
            for (std::size_t z = 0; z < d; ++z)
                lerp3(&along_y[((a * d + y) * d + z) * 3], &along_y[(((a + 1) * d + y) * d + z) * 3], f.t[0][x],
                      &dense[((x * d + y) * d + z) * 3]);
    }
    for (openvdb::Index w = 0; w < 8; ++w)
        for (std::uint64_t word = mask.getWord<std::uint64_t>(w); word; word &= word - 1, ++i) {
            const int b = __builtin_ctzll(word);
            if (!(ex[w] >> b & 1)) put(i, &dense[(std::size_t(w) * 64 + std::size_t(b)) * 3]);
        }
}

} // namespace cm::plausible
