// The lines of sight of hull.plausible: the grid's lattice, each view's lines of sight
// laid out as a raster at the grid's pitch, a parallel stable counting sort that orders the
// voxels along them, and the grid columns that are the lines of sight of a view along an axis.
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
        return cell_at(px, py);
    }
    /// The cell of raster point (px, py).
    std::uint32_t cell_at(double px, double py) const {
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
    /// The same for the columns holding a voxel of `want` (per leaf, in LeafManager order), and
    /// the others for which `also(a grid point of the column)` holds: stacks with no such
    /// column are not dealt at all.
    template <typename Also, typename Body>
    void for_columns_wanted(int axis, const std::vector<Mask>& want, Also&& also, Body&& body) const;
    /// The same for the columns for which `want(a grid point of the column)` holds: stacks
    /// with none are not dealt at all.
    template <typename Want, typename Body>
    void for_columns_where(int axis, Want&& want, Body&& body) const;
    /// body(a grid point of the column) for every non-empty column along `axis`, from the
    /// leaves' masks alone (no voxel dealt), in parallel over leaf stacks.
    template <typename Body>
    void for_column_points(int axis, Body&& body) const;
    /// The columns along `axis` (bit loc[a1] * 8 + loc[a2], a1 and a2 the next axes in turn)
    /// holding a voxel of the leaf mask `m`.
    static std::uint64_t column_bits(const Mask& m, int axis);
    /// The voxels of word x of a leaf mask (bits y * 8 + z) that lie in the columns `cols`
    /// along `axis` (bits as column_bits()).
    static std::uint64_t column_word(std::uint64_t cols, int axis, int x) {
        if (axis == 0) return cols; // columns y * 8 + z
        if (axis == 1) {            // columns z * 8 + x: the same z bits in every byte
            std::uint64_t zs = 0;
            for (int z = 0; z < 8; ++z) zs |= ((cols >> (z * 8 + x)) & 1) << z;
            return zs * 0x0101010101010101ull;
        }
        // columns x * 8 + y: whole bytes
        const std::uint64_t ys = (cols >> (x * 8)) & 0xff;
        std::uint64_t out = 0;
        for (int y = 0; y < 8; ++y)
            if (ys >> y & 1) out |= std::uint64_t(0xff) << (8 * y);
        return out;
    }

private:
    void stacks_along(int axis) const;
    /// The columns of `cols` (bits as column_bits()) of the stack starting at order_[axis][b]
    /// for which `want(a grid point of the column)` holds.
    template <typename Want>
    std::uint64_t columns_where(int axis, std::size_t b, std::uint64_t cols, Want&& want) const;
    /// for_columns() over the columns `wanted(stack)` gives (a column mask as column_bits()).
    template <typename Wanted, typename Body>
    void deal_columns(int axis, Wanted&& wanted_of, Body&& body) const;
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
    const auto& order = order_[std::size_t(axis)];
    deal_columns(
        axis,
        [&](std::size_t b, std::size_t e) {
            if (!skip) return ~std::uint64_t(0);
            std::uint64_t have = 0, skipped = 0;
            for (std::size_t k = b; k < e; ++k) {
                const std::uint32_t l = order[k];
                have |= column_bits(leaf_mask(leaves_.leaf(l)), axis);
                skipped |= column_bits((*skip)[l], axis);
            }
            return have & ~skipped;
        },
        std::forward<Body>(body));
}

template <typename Also, typename Body>
void LeafColumns::for_columns_wanted(int axis, const std::vector<Mask>& want, Also&& also, Body&& body) const {
    const auto& order = order_[std::size_t(axis)];
    deal_columns(
        axis,
        [&](std::size_t b, std::size_t e) {
            std::uint64_t have = 0, wanted = 0;
            for (std::size_t k = b; k < e; ++k) {
                const std::uint32_t l = order[k];
                have |= column_bits(leaf_mask(leaves_.leaf(l)), axis);
                wanted |= column_bits(want[l], axis);
            }
            return (wanted | columns_where(axis, b, have & ~wanted, also)) & have;
        },
        std::forward<Body>(body));
}

template <typename Want, typename Body>
void LeafColumns::for_columns_where(int axis, Want&& want, Body&& body) const {
    const auto& order = order_[std::size_t(axis)];
    deal_columns(
        axis,
        [&](std::size_t b, std::size_t e) {
            std::uint64_t have = 0;
            for (std::size_t k = b; k < e; ++k) have |= column_bits(leaf_mask(leaves_.leaf(order[k])), axis);
            return columns_where(axis, b, have, want);
        },
        std::forward<Body>(body));
}

template <typename Want>
std::uint64_t LeafColumns::columns_where(int axis, std::size_t b, std::uint64_t cols, Want&& want) const {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const Coord origin = leaves_.leaf(order_[std::size_t(axis)][b]).origin();
    std::uint64_t wanted = 0;
    for (; cols; cols &= cols - 1) {
        const int col = __builtin_ctzll(cols);
        Coord c = origin;
        c[a1] += col >> 3;
        c[a2] += col & 7;
        if (want(c)) wanted |= std::uint64_t(1) << col;
    }
    return wanted;
}

template <typename Wanted, typename Body>
void LeafColumns::deal_columns(int axis, Wanted&& wanted_of, Body&& body) const {
    stacks_along(axis);
    const auto& order = order_[std::size_t(axis)];
    const auto& stack = stack_[std::size_t(axis)];
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    tbb::parallel_for(std::size_t(0), stack.size() - 1, [&](std::size_t s) {
        const std::uint64_t wanted = wanted_of(stack[s], stack[s + 1]);
        if (!wanted) return;
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
                // Only the voxels of wanted columns are visited; a voxel's rank counts the
                // word's voxels before it.
                const std::uint64_t all = mask.template getWord<std::uint64_t>(w);
                std::uint64_t word = all & column_word(wanted, axis, int(w));
                const bool every = word == all;
                const std::size_t first_rank = rank;
                rank += std::size_t(__builtin_popcountll(all));
                for (std::size_t seen = 0; word; ++seen) {
                    const int b = __builtin_ctzll(word);
                    const openvdb::Index off = w * 64 + openvdb::Index(b);
                    word &= word - 1;
                    const std::uint32_t r = std::uint32_t(
                        first_rank +
                        (every ? seen : std::size_t(__builtin_popcountll(all & ((std::uint64_t(1) << b) - 1)))));
                    const int loc[3] = {int(off >> 6), int((off >> 3) & 7), int(off & 7)};
                    const int col = loc[a1] * 8 + loc[a2];
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

} // namespace cm::plausible
