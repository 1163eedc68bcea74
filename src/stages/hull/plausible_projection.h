// The hull projected along the grid's three axes, as the lofted prior (plausible_loft.cpp) and
// the hidden-depth prior (plausible_ghost.cpp) read it: per axis a mask over the other two
// axes, the runs through each inside pixel along both, and a summed-area table.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "plausible_state.h"

namespace cm::plausible {

/// @brief The grid indices lo..hi along one axis; empty when hi < lo.
struct Interval {
    int lo = 0, hi = -1;
    bool empty() const { return hi < lo; }
    int size() const { return hi - lo + 1; }
    double half() const { return 0.5 * double(size()); } ///< the voxels' half extent, cells
    double mid() const { return 0.5 * double(lo + hi); }
};

/// @brief The hull projected along grid axis k: inside pixels over the other two axes (u the
/// lower, v the higher), the run along u and along v through each, and a summed-area table
/// (sat, (nu + 1) x (nv + 1): sat at (iu + 1, iv + 1) counts the inside pixels up to and
/// including local (iu, iv)).
struct Projection {
    int k = 0, u = 0, v = 0, u0 = 0, v0 = 0, nu = 0, nv = 0;
    std::vector<std::uint8_t> in;
    std::vector<std::int32_t> lo_u, hi_u, lo_v, hi_v, sat;

    std::size_t index(int iu, int iv) const { return std::size_t(iu - u0) * std::size_t(nv) + std::size_t(iv - v0); }
    bool inside(int iu, int iv) const {
        return iu >= u0 && iv >= v0 && iu < u0 + nu && iv < v0 + nv && in[index(iu, iv)] != 0;
    }
    bool inside(const Coord& p) const { return inside(p[u], p[v]); }
    /// The run along axis `along` (u or v) through p's pixel; empty outside.
    Interval run(int along, const Coord& p) const {
        if (!inside(p)) return {};
        const std::size_t i = index(p[u], p[v]);
        return along == u ? Interval{lo_u[i], hi_u[i]} : Interval{lo_v[i], hi_v[i]};
    }
    /// Inside pixels in the box [a0, a1] along u by [b0, b1] along v (grid coordinates),
    /// clamped to the array.
    double count(int a0, int a1, int b0, int b1) const;
};

/// @brief The hull's projections along x, y and z (in parallel over its leaves).
std::array<Projection, 3> project_hull(const HullVoxels& vox);

} // namespace cm::plausible
