// The bit grid of the handle cut (plausible_handles.h): the kept voxels of a box as bits,
// their Euler characteristic and pieces, runs of rows and steps by faces.
#pragma once
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

#include "plausible_handles.h"

namespace cm::plausible::handles {

using openvdb::Coord;
using openvdb::CoordBBox;

// The voxels of a box as bits, z fastest: a row (x, y) is nz / 64 words. The box has an
// empty layer on every side (rows x = 0 and y = 0 and their last ones, and the first and last
// bits of every row), so a shift or a neighbour never leaves it, and z starts on a leaf's
// boundary, so a leaf's row of 8 voxels is one byte.
struct Bits {
    Coord lo;
    std::size_t nx = 0, ny = 0, nz = 0, rw = 0; // rw: words per row
    std::vector<std::uint64_t> w;

    Bits() = default;
    explicit Bits(const CoordBBox& box) {
        const int z0 = (box.min().z() & ~7) - 8;
        lo = Coord(box.min().x() - 1, box.min().y() - 1, z0);
        nx = std::size_t(box.max().x() - lo.x() + 2);
        ny = std::size_t(box.max().y() - lo.y() + 2);
        nz = (std::size_t(box.max().z() - z0 + 2) + 63) / 64 * 64;
        rw = nz / 64;
        w.assign(nx * ny * rw, 0);
    }
    std::size_t size() const { return nx * ny * nz; }
    std::size_t index(const Coord& c) const {
        return (std::size_t(c.x() - lo.x()) * ny + std::size_t(c.y() - lo.y())) * nz + std::size_t(c.z() - lo.z());
    }
    Coord coord(std::size_t i) const {
        const std::size_t z = i % nz, xy = i / nz;
        return Coord(lo.x() + int(xy / ny), lo.y() + int(xy % ny), lo.z() + int(z));
    }
    bool test(std::size_t i) const { return (w[i >> 6] >> (i & 63) & 1) != 0; }
    void set(std::size_t i) { w[i >> 6] |= std::uint64_t(1) << (i & 63); }
    void reset(std::size_t i) { w[i >> 6] &= ~(std::uint64_t(1) << (i & 63)); }
    const std::uint64_t* row(std::size_t x, std::size_t y) const { return w.data() + (x * ny + y) * rw; }
    template <typename Body>
    void for_each(Body&& body) const {
        for (std::size_t k = 0; k < w.size(); ++k)
            for (std::uint64_t v = w[k]; v; v &= v - 1) body(k * 64 + std::size_t(__builtin_ctzll(v)));
    }
};

// Union-find with path halving.
struct Roots {
    std::vector<std::uint32_t> up;
    std::uint32_t find(std::uint32_t a) {
        while (up[a] != a) a = up[a] = up[up[a]];
        return a;
    }
    bool join(std::uint32_t a, std::uint32_t b) {
        a = find(a), b = find(b);
        if (a == b) return false;
        up[std::max(a, b)] = std::min(a, b);
        return true;
    }
};

// The runs of on bits of every row (offsets along z within the row), the rows in order.
struct Runs {
    struct Run {
        std::uint32_t a, e; // [a, e]
    };
    std::vector<Run> runs;
    std::vector<std::size_t> start; // the first run of each row (x * ny + y), and the end

    explicit Runs(const Bits& b) : start(b.nx * b.ny + 1, 0) {
        for (std::size_t x = 0; x < b.nx; ++x)
            for (std::size_t y = 0; y < b.ny; ++y) {
                start[x * b.ny + y] = runs.size();
                const std::uint64_t* r = b.row(x, y);
                bool in = false;
                std::uint32_t a = 0;
                for (std::size_t k = 0; k < b.rw; ++k) {
                    const std::uint64_t v = r[k];
                    if ((!in && !v) || (in && v == ~std::uint64_t(0))) continue;
                    int bit = 0;
                    while (bit < 64) {
                        const std::uint64_t t = (in ? ~v : v) >> bit;
                        if (!t) break;
                        bit += __builtin_ctzll(t);
                        const auto at = std::uint32_t(k * 64 + std::size_t(bit));
                        if (!in) a = at;
                        else runs.push_back({a, at - 1});
                        in = !in;
                    }
                }
            }
        start.back() = runs.size();
    }
    /// touched(i, j) for every two runs of neighbouring rows that touch (a run touches another
    /// reaching within one of it: 26-connected; with `faces`, sharing a face: 6-connected),
    /// each pair once.
    template <typename Touched>
    void for_touching(const Bits& b, Touched&& touched, bool faces = false) const {
        const std::uint32_t reach = faces ? 0 : 1;
        const auto touch = [&](std::size_t r1, std::size_t r2) {
            std::size_t i = start[r1], j = start[r2];
            const std::size_t ie = start[r1 + 1], je = start[r2 + 1];
            while (i < ie && j < je) {
                const Run &p = runs[i], &q = runs[j];
                if (p.a <= q.e + reach && q.a <= p.e + reach) touched(i, j);
                if (p.e < q.e) ++i;
                else ++j;
            }
        };
        for (std::size_t x = 1; x + 1 < b.nx; ++x)
            for (std::size_t y = 1; y + 1 < b.ny; ++y) {
                const std::size_t r = x * b.ny + y;
                if (start[r] == start[r + 1]) continue;
                touch(r, r - 1);
                touch(r, r - b.ny);
                if (faces) continue;
                touch(r, r - b.ny - 1);
                touch(r, r - b.ny + 1);
            }
    }
    /// The piece of each run (the first run of the piece), 26-connected or with `faces`
    /// 6-connected.
    std::vector<std::uint32_t> pieces(const Bits& b, bool faces) const {
        Roots roots;
        roots.up.resize(runs.size());
        std::iota(roots.up.begin(), roots.up.end(), 0u);
        for_touching(
            b, [&](std::size_t i, std::size_t j) { roots.join(std::uint32_t(i), std::uint32_t(j)); }, faces);
        for (std::uint32_t i = 0; i < runs.size(); ++i) roots.find(i);
        for (std::uint32_t i = 0; i < runs.size(); ++i) roots.up[i] = roots.up[roots.up[i]];
        return std::move(roots.up);
    }
};

/// The on voxels of `leaves` (every leaf voxelized) in `box`, and the box of them.
Bits bits_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const CoordBBox& box);
CoordBBox box_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves);

/// V - E + F - C of the union of the closed voxel cubes, the 26-connected pieces, both.
long euler_of(const Bits& b);
long pieces_of(const Bits& b);
VoxelTopology topology_of(const Bits& b);

/// Word k of `in` eroded by faces (its voxels all of whose face neighbours are on); k lies
/// between the first and last x slabs.
inline std::uint64_t eroded_by_faces(const Bits& in, std::size_t k) {
    const auto& w = in.w;
    const std::uint64_t v = w[k];
    if (!v) return 0;
    const std::size_t row = in.rw, slab = in.ny * in.rw;
    // Rows start a word apart: the first and last bits of a row are empty, so no bit crosses
    // rows.
    const std::uint64_t up = v << 1 | w[k - 1] >> 63, down = v >> 1 | w[k + 1] << 63;
    return v & up & down & w[k - row] & w[k + row] & w[k - slab] & w[k + slab];
}

/// One step by faces over the words of `in` between its first and last x slabs: `out` the
/// voxels of `within` with a face neighbour or themselves on (dilated inside it).
void dilate_by_faces(const Bits& in, const Bits& within, std::vector<std::uint64_t>& out);

} // namespace cm::plausible::handles
