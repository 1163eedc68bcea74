// The steps of hull.plausible (plausible.cpp) that are not its algorithm: the drawing's
// profile and local inscribed radius, the grid's lattice,
// each view's lines of sight laid out as a raster at the grid's pitch, a parallel stable
// counting sort, the filters over rasters and grids that smooth the profiles and the field,
// and the union of balls by which the volume swells to the lines of sight it must cover.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <unordered_map>

#include "core/views.h"
#include "leaf_masks.h"

namespace cm::plausible {

using openvdb::Coord;

// World position of grid points: an affine map of the index (volume.h: a linear transform),
// so a pass over millions of voxels needs no virtual call per voxel.
struct Lattice {
    Vec3d o, ex, ey, ez;
    explicit Lattice(const openvdb::math::Transform& xf);
    Vec3d at(const Coord& c) const { return o + ex * double(c.x()) + ey * double(c.y()) + ez * double(c.z()); }
};

// A view's lines of sight at the grid's pitch: cell (i, j) of the raster covers
// [x0 + i cp, x0 + (i + 1) cp) x [y0 + j cp, ...) in pixels; a voxel belongs to the cell
// its centre projects into; depth is along the view direction (orthographic) or the
// distance from the camera centre (perspective), quantised in `dq` world units from `dmin`.
struct RayRaster {
    double cp = 1, x0 = 0, y0 = 0;
    int w = 0, h = 0;
    bool ortho = true;
    std::array<double, 12> m{}; ///< homogeneous pixel of grid index (i, j, k): m * [i j k 1]
    std::array<double, 4> dm{}; ///< orthographic depth of grid index (i, j, k): dm . [i j k 1]
    Vec3d centre;               ///< perspective camera centre (world)
    const Lattice* lat = nullptr;
    double dmin = 0, dq = 1; ///< depth key = floor((depth - dmin) / dq)
    std::uint32_t dkeys = 1; ///< number of depth keys
    int gap_keys = 1;        ///< a depth step of more than this many keys splits a run
    /// Orthographic along a grid axis: the tree's voxel order is already monotonic in depth
    /// along every line of sight (the leaves, and the voxels in a leaf, come in lexicographic
    /// order of their coordinates), so no depth sort is needed.
    bool axis_aligned = false;
    int axis = -1; ///< the grid axis of an axis-aligned view

    std::uint32_t cell(const Coord& c) const {
        const double i = c.x(), j = c.y(), k = c.z();
        double px = m[0] * i + m[1] * j + m[2] * k + m[3], py = m[4] * i + m[5] * j + m[6] * k + m[7];
        if (!ortho) {
            const double hw = m[8] * i + m[9] * j + m[10] * k + m[11];
            px /= hw, py /= hw;
        }
        const int ci = std::clamp(int(std::floor((px - x0) / cp)), 0, w - 1);
        const int cj = std::clamp(int(std::floor((py - y0) / cp)), 0, h - 1);
        return std::uint32_t(cj) * std::uint32_t(w) + std::uint32_t(ci);
    }
    double depth(const Coord& c) const {
        if (ortho) return dm[0] * c.x() + dm[1] * c.y() + dm[2] * c.z() + dm[3];
        return length(lat->at(c) - centre);
    }
    std::uint32_t depth_key(const Coord& c) const {
        return std::uint32_t(std::clamp((depth(c) - dmin) / dq, 0.0, double(dkeys - 1)));
    }
    /// The depth a key stands for (the middle of its interval).
    double depth_of_key(std::uint32_t key) const { return dmin + (double(key) + 0.5) * dq; }
};

/// The view's raster over the grid's box (index space), `voxel` world units a cell; throws
/// cm::Error when it cannot be laid out (a camera inside the box, or too many cells).
RayRaster make_raster(const View& view, const Lattice& lat, const openvdb::CoordBBox& box, double voxel);

/// Stable counting sort: `out` gets the indices of `in` (all of 0..n-1 when `in` is empty) in
/// increasing `keys[index]`, keeping the order of `in` among equal keys. Parallel.
/// With `starts`, it gets nkeys + 1 entries: bucket k is out[starts[k]] .. out[starts[k + 1]).
void stable_bucket_order(const std::vector<std::uint32_t>& keys, std::uint32_t nkeys,
                         const std::vector<std::uint32_t>& in, std::vector<std::uint32_t>& out,
                         std::vector<std::uint32_t>* starts = nullptr);

/// 3x3 box passes over a w x h raster, normalised over the cells not `masked`; masked cells
/// keep their value.
void box_blur(std::vector<float>& f, const std::vector<char>* masked, int w, int h, int passes);

/// Smooths `value` (one per voxel of `leaves`, numbered leaf base + rank) by a Gaussian of
/// standard deviation `sigma` grid cells, normalised over the voxels (the outside does not
/// pull it): the voxels' means on a dense lattice of `f` cells a cell (f a power of 2 up to
/// sigma), binomial passes there, and back trilinearly. Voxels whose value lies farther than
/// `reach` from 0 keep theirs.
void smooth_field(std::vector<float>& value, const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves,
                  const std::vector<std::size_t>& base, const openvdb::CoordBBox& box, double sigma, float reach);

// A smooth, non-negative field on a coarse dense lattice (`f` grid cells a coarse cell) over a
// box of the grid: how far the field is lowered about the lines of sight it must still cover.
// Seeds raise it to their value in a ball of their value's radius (plus two coarse cells),
// then it is smoothed; sampled trilinearly at grid points.
class SwellField {
public:
    SwellField(const openvdb::CoordBBox& box, int f);
    /// Raises the field to at least `value` (grid cells) about grid point c.
    void seed(const Coord& c, float value);
    /// Adds the seeds since the last call to the field, smoothed (two binomial passes).
    void settle();
    /// Trilinear value at grid point c (0 outside the box).
    float at(const Coord& c) const;
    /// The same values for the grid points of the 8^3 block at `origin`, with the per-axis
    /// lattice positions worked out once: at(x, y, z) for local coordinates 0..7.
    class Block {
    public:
        Block(const SwellField& f, const Coord& origin);
        float at(int x, int y, int z) const;

    private:
        const SwellField& f_;
        int c0_[3][8];   ///< lower lattice index per axis and local coordinate (-1: outside)
        double t_[3][8]; ///< the upper one's weight
    };
    /// Whether the last settle() raised the field anywhere about the grid points of `b`.
    bool raised_in(const openvdb::CoordBBox& b) const;

private:
    Coord lo_;
    int f_, nx_, ny_, nz_;
    std::vector<float> g_, last_;
    std::vector<std::pair<std::uint32_t, float>> seeds_; // coarse cell, value
    bool any_ = false;
};

// The grid columns of a voxelized bool tree along each axis, walked leaf stack by leaf stack:
// the lines of sight of an orthographic view along that axis, each column's voxels in
// order along it, with no sort. A voxel's index is its leaf's base (the voxels of the leaves
// before it, in LeafManager order) plus its rank among its leaf's on voxels.
class LeafColumns {
public:
    using Mask = LeafMask;
    LeafColumns(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const std::vector<std::size_t>& base);
    /// body(coord of the column's first voxel, indices, coordinates along the axis, count) for
    /// every non-empty column along `axis`, in parallel over leaf stacks (a column lies in one).
    /// The indices and coordinates live in a per-thread buffer the next stack reuses: the
    /// body runs no parallel work of its own (a stolen stack would overwrite them).
    template <typename Body>
    void for_columns(int axis, Body&& body) const {
        for_columns(axis, nullptr, std::forward<Body>(body));
    }
    /// The same for the columns with no voxel in `skip` (per leaf, in LeafManager order)
    /// only: stacks whose columns all hold one are not dealt at all.
    template <typename Body>
    void for_columns(int axis, const std::vector<Mask>* skip, Body&& body) const;
    /// body(a grid point of the column) for every non-empty column along `axis`, from the
    /// leaves' masks alone (no voxel dealt), in parallel over leaf stacks.
    template <typename Body>
    void for_column_points(int axis, Body&& body) const;
    /// The columns along `axis` (bit loc[a1] * 8 + loc[a2], a1 and a2 the next axes in turn)
    /// holding a voxel of the leaf mask `m`.
    static std::uint64_t column_bits(const Mask& m, int axis);

private:
    void stacks_along(int axis) const;
    struct Scratch {
        std::vector<std::uint32_t> idx;
        std::vector<int> along;
    };
    const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves_;
    const std::vector<std::size_t>& base_;
    mutable std::array<std::vector<std::uint32_t>, 3> order_;  // leaves by stack, along the axis
    mutable std::array<std::vector<std::size_t>, 3> stack_;    // stack starts in order_
    mutable tbb::enumerable_thread_specific<Scratch> scratch_; // dealing buffers, reused
};

template <typename Body>
void LeafColumns::for_column_points(int axis, Body&& body) const {
    stacks_along(axis);
    const auto& order = order_[std::size_t(axis)];
    const auto& stack = stack_[std::size_t(axis)];
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    tbb::parallel_for(std::size_t(0), stack.size() - 1, [&](std::size_t s) {
        std::uint64_t have = 0;
        for (std::size_t k = stack[s]; k < stack[s + 1]; ++k) {
            have |= column_bits(leaf_mask(leaves_.leaf(order[k])), axis);
        }
        const Coord origin = leaves_.leaf(order[stack[s]]).origin();
        for (; have; have &= have - 1) {
            const int col = __builtin_ctzll(have);
            Coord c = origin;
            c[a1] += col >> 3;
            c[a2] += col & 7;
            body(c);
        }
    });
}

template <typename Body>
void LeafColumns::for_columns(int axis, const std::vector<Mask>* skip, Body&& body) const {
    stacks_along(axis);
    const auto& order = order_[std::size_t(axis)];
    const auto& stack = stack_[std::size_t(axis)];
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    tbb::parallel_for(std::size_t(0), stack.size() - 1, [&](std::size_t s) {
        std::uint64_t wanted = ~std::uint64_t(0);
        if (skip) {
            std::uint64_t have = 0, skipped = 0;
            for (std::size_t k = stack[s]; k < stack[s + 1]; ++k) {
                const std::uint32_t l = order[k];
                have |= column_bits(leaf_mask(leaves_.leaf(l)), axis);
                skipped |= column_bits((*skip)[l], axis);
            }
            wanted = have & ~skipped;
            if (!wanted) return;
        }
        // The stack's voxels dealt into its 64 columns: a leaf's on voxels in offset order
        // come in order along every axis, and their ranks one after another.
        const std::size_t cap = (stack[s + 1] - stack[s]) * 8;
        Scratch& sc = scratch_.local();
        if (sc.idx.size() < 64 * cap) sc.idx.resize(64 * cap), sc.along.resize(64 * cap);
        std::uint32_t* idx = sc.idx.data();
        int* along = sc.along.data();
        std::array<std::size_t, 64> cnt{};
        std::array<Coord, 64> first;
        for (std::size_t k = stack[s]; k < stack[s + 1]; ++k) {
            const std::uint32_t l = order[k];
            const auto& leaf = leaves_.leaf(l);
            const auto& mask = leaf.getValueMask();
            std::size_t rank = base_[l];
            for (openvdb::Index w = 0; w < 8; ++w) {
                std::uint64_t word = mask.template getWord<std::uint64_t>(w);
                while (word) {
                    const openvdb::Index off = w * 64 + openvdb::Index(__builtin_ctzll(word));
                    word &= word - 1;
                    const std::uint32_t r = std::uint32_t(rank++);
                    const int loc[3] = {int(off >> 6), int((off >> 3) & 7), int(off & 7)};
                    const int col = loc[a1] * 8 + loc[a2];
                    if (!(wanted >> col & 1)) continue;
                    std::size_t& n = cnt[std::size_t(col)];
                    if (n == 0) first[std::size_t(col)] = leaf.offsetToGlobalCoord(off);
                    idx[std::size_t(col) * cap + n] = r;
                    along[std::size_t(col) * cap + n] = leaf.origin()[axis] + loc[axis];
                    ++n;
                }
            }
        }
        for (std::size_t col = 0; col < 64; ++col)
            if (cnt[col]) body(first[col], idx + col * cap, along + col * cap, cnt[col]);
    });
}

// The signed distance (grid cells, negative inside) to a union of balls, kept on a coarse
// dense lattice (`f` grid cells a coarse cell) over a box of the grid and sampled
// trilinearly: the swellings by which the volume reaches the lines of sight it must cover.
class BallField {
public:
    BallField(const openvdb::CoordBBox& box, int f);
    /// A ball of `radius` grid cells about `centre` (index space).
    void add(const openvdb::Vec3d& centre, double radius) { balls_.push_back({centre, radius}); }
    /// Writes the balls added since the last call into the lattice, within `reach` cells of
    /// their surface (farther, the field is left at +infinity).
    void settle(double reach);
    bool empty() const { return !any_; }
    /// Trilinear value at grid point c (+infinity where any corner is beyond reach).
    float at(const Coord& c) const;
    /// Whether the field is finite anywhere about the grid points of `b`.
    bool any_in(const openvdb::CoordBBox& b) const;

private:
    struct Ball {
        openvdb::Vec3d centre;
        double radius;
    };
    Coord lo_;
    int f_, nx_, ny_, nz_;
    std::vector<float> g_;
    std::vector<Ball> balls_;
    bool any_ = false;
};

} // namespace cm::plausible
