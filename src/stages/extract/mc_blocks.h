// The 8^3 blocks of cells Marching Cubes works in (see marching_cubes.cpp), and phase 1:
// finding the blocks that hold surface, with their corner states, crossed edges and
// neighbours.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "marching_cubes.h"

namespace cm::mc {

/// Points made inside for thin parts: per point, the offset to the near face of its part.
using FlipGrid = openvdb::Vec3fGrid;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct Block {
    openvdb::Coord origin;
    std::uint16_t rows[9][9];  ///< bit z of rows[x][y]: corner (x, y, z) is inside
    std::uint64_t cross[3][8]; ///< bit 8y+z of cross[a][x]: edge (x,y,z) -> +a is crossed
    std::uint16_t pre[3][8];   ///< vertices of this block before cross[a][x]
    std::uint32_t nb[8];       ///< the blocks at origin + 8 (dx, dy, dz), index dx | dy<<1 | dz<<2
    std::uint32_t vbase = 0, nverts = 0;
    std::uint32_t tbase = 0, ntris = 0;
    std::uint32_t xbase = 0, nextra = 0;
    std::uint32_t lbase = 0, nloops = 0; ///< loops (discs of surface in one cell), when counted
};

/// Bit z set when cell (x, y, z) of a block with these corner rows has mixed corners.
inline unsigned mixed_row(const std::uint16_t rows[9][9], int x, int y) {
    const unsigned r0 = rows[x][y], r1 = rows[x][y + 1], r2 = rows[x + 1][y], r3 = rows[x + 1][y + 1];
    const unsigned all = r0 & r1 & r2 & r3, any = r0 | r1 | r2 | r3;
    return ((any | (any >> 1)) & ~(all & (all >> 1))) & 0xFFu;
}

/// Population count without a library call (the build does not assume the POPCNT instruction).
inline unsigned popcount64(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return unsigned((x * 0x0101010101010101ull) >> 56);
}

/// Runs fn(i) for i in [0, n) in parallel chunks, reporting progress between chunks.
template <typename Fn>
void for_blocks(std::size_t n, double p0, double p1, const Progress& progress, Fn&& fn) {
    const std::size_t chunk = 4096;
    for (std::size_t start = 0; start < n; start += chunk) {
        const std::size_t end = std::min(n, start + chunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end, 16),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
                          });
        progress(p0 + (p1 - p0) * double(end) / double(n));
    }
}

/// Phase 1: the blocks with a mixed cell, in key order, each with its corner rows, crossed
/// edges, vertex counts and neighbours (vbase, tbase and xbase are left at 0). Fills
/// stats.blocks and stats.surface_cells; progress runs to 0.35.
/// @throw cm::Error when the occupancy reaches beyond the range of block keys.
std::vector<Block> find_blocks(const openvdb::BoolGrid& occ, const FlipGrid* flips, const Progress& progress,
                               MarchingCubesStats& stats);

} // namespace cm::mc
