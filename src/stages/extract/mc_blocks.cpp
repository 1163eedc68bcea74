// Phase 1 of Marching Cubes (marching_cubes.cpp): the blocks of cells that hold surface.
#include "mc_blocks.h"

#include <algorithm>
#include <atomic>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "core/error.h"

namespace cm::mc {
namespace {

using openvdb::Coord;
constexpr std::int64_t kBias = std::int64_t(1) << 20; // block coordinates are stored in 21 bits

std::uint64_t block_key(const Coord& o) {
    return (std::uint64_t((o.x() >> 3) + kBias) << 42) | (std::uint64_t((o.y() >> 3) + kBias) << 21) |
           std::uint64_t((o.z() >> 3) + kBias);
}
Coord key_origin(std::uint64_t k) {
    const std::uint64_t m = (std::uint64_t(1) << 21) - 1;
    return Coord(int((std::int64_t((k >> 42) & m) - kBias) * 8), int((std::int64_t((k >> 21) & m) - kBias) * 8),
                 int((std::int64_t(k & m) - kBias) * 8));
}

/// Corner states of the lattice: occupancy, plus points made inside to keep thin parts.
class States {
public:
    States(const openvdb::BoolGrid& occ, const FlipGrid* flips) : occ_(occ), flips_(flips) {}

    /// Inside bits of the 8 leaf-sized regions at origin + 8 (dx, dy, dz), as leaf words:
    /// word x of region d holds bit 8y+z.
    void load(const Coord& origin, std::uint64_t words[8][8]) const {
        auto acc = occ_.getConstUnsafeAccessor(); // per call, so no registration with the tree
        for (int d = 0; d < 8; ++d) {
            const Coord o = origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1));
            if (const auto* leaf = acc.probeConstLeaf(o)) {
                const auto& mask = leaf->getValueMask();
                const std::uint64_t* data = leaf->buffer().data();
                for (int x = 0; x < 8; ++x) words[d][x] = mask.getWord<std::uint64_t>(openvdb::Index(x)) & data[x];
            } else {
                bool v = false;
                const bool on = acc.probeValue(o, v);
                const std::uint64_t fill = (on && v) ? ~std::uint64_t(0) : 0;
                for (int x = 0; x < 8; ++x) words[d][x] = fill;
            }
        }
        if (!flips_) return;
        auto facc = flips_->getConstUnsafeAccessor();
        for (int d = 0; d < 8; ++d) {
            const Coord o = origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1));
            if (const auto* leaf = facc.probeConstLeaf(o)) {
                const auto& mask = leaf->getValueMask();
                for (int x = 0; x < 8; ++x) words[d][x] |= mask.getWord<std::uint64_t>(openvdb::Index(x));
            }
        }
    }

    /// Fills the 9^3 corner rows of the block at `origin`; returns true when a cell is mixed.
    bool fill(const Coord& origin, std::uint16_t rows[9][9]) const {
        std::uint64_t w[8][8];
        load(origin, w);
        for (int x = 0; x < 9; ++x)
            for (int y = 0; y < 9; ++y) {
                const int d = (x >> 3) | ((y >> 3) << 1);
                const int lx = x & 7, sh = 8 * (y & 7);
                rows[x][y] = std::uint16_t(((w[d][lx] >> sh) & 0xFF) | (((w[d | 4][lx] >> sh) & 1) << 8));
            }
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                if (mixed_row(rows, x, y)) return true;
        return false;
    }

private:
    const openvdb::BoolGrid& occ_;
    const FlipGrid* flips_;
};

/// Block keys hold 21 bits per axis: the occupancy must stay within their reach.
void check_extent(const openvdb::BoolGrid& occ) {
    const openvdb::CoordBBox bbox = occ.evalActiveVoxelBoundingBox();
    const int limit = int(kBias) * 8 - 16;
    for (int a = 0; a < 3; ++a)
        if (!occ.tree().empty() && (bbox.min()[a] < -limit || bbox.max()[a] > limit))
            throw Error("the occupancy grid spans more than " + std::to_string(limit) + " voxels from the origin");
}

/// The blocks along the shell of every active tile that touches non-solid space. The tiles
/// are found first (the iterator does not go down into the leaves, whose active voxels, a
/// hundred million at 2048, it would otherwise visit one by one to skip); their neighbours
/// are then asked in parallel (each tile 26 of them: a solid inside of 8^3 tiles has about a
/// million at 2048).
void add_tile_shells(const openvdb::BoolGrid& occ, std::vector<std::uint64_t>& keys) {
    struct Tile {
        openvdb::CoordBBox box;
        int level;
    };
    std::vector<Tile> tiles;
    auto it = occ.tree().cbeginValueOn();
    it.setMaxDepth(openvdb::BoolTree::ValueOnCIter::LEAF_DEPTH - 1);
    for (; it; ++it)
        if (!it.isVoxelValue() && *it) tiles.push_back({it.getBoundingBox(), int(it.getLevel())});
    tbb::enumerable_thread_specific<std::vector<std::uint64_t>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1024), [&](const auto& r) {
        auto acc = occ.getConstAccessor();
        auto& out = found.local();
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const openvdb::CoordBBox& tile = tiles[i].box;
            const int s = tile.dim().x(), level = tiles[i].level;
            bool surrounded = true;
            for (int d = 0; d < 27 && surrounded; ++d) {
                if (d == 13) continue;
                const Coord o = tile.min().offsetBy(s * (d % 3 - 1), s * ((d / 3) % 3 - 1), s * (d / 9 - 1));
                bool v = false;
                // A value stored at this tile's level or above covers the whole neighbour region.
                surrounded = acc.probeValue(o, v) && v && acc.getValueDepth(o) >= 0 &&
                             int(openvdb::BoolTree::DEPTH) - 1 - acc.getValueDepth(o) >= level;
            }
            if (surrounded) continue;
            const Coord lo = tile.min().offsetBy(-8), hi = tile.max().offsetBy(1 - 8);
            for (int x = lo.x(); x <= hi.x(); x += 8) {
                const bool bx = x == lo.x() || x == hi.x();
                for (int y = lo.y(); y <= hi.y(); y += 8) {
                    const bool by = y == lo.y() || y == hi.y();
                    if (bx || by) {
                        for (int z = lo.z(); z <= hi.z(); z += 8) out.push_back(block_key(Coord(x, y, z)));
                    } else {
                        out.push_back(block_key(Coord(x, y, lo.z())));
                        out.push_back(block_key(Coord(x, y, hi.z())));
                    }
                }
            }
        }
    });
    for (const auto& f : found) keys.insert(keys.end(), f.begin(), f.end());
}

/// 1. Candidate blocks: around every leaf of the occupancy (and of the thin-part grid), plus
/// the shell of any active tile that touches non-solid space; sorted, each once.
std::vector<std::uint64_t> candidate_keys(const openvdb::BoolGrid& occ, const FlipGrid* flips) {
    std::vector<std::uint64_t> keys;
    auto add_around = [&](const Coord& o) {
        for (int d = 0; d < 8; ++d)
            keys.push_back(block_key(o.offsetBy(-8 * (d & 1), -8 * ((d >> 1) & 1), -8 * ((d >> 2) & 1))));
    };
    for (auto it = occ.tree().cbeginLeaf(); it; ++it) add_around(it->origin());
    if (flips)
        for (auto it = flips->tree().cbeginLeaf(); it; ++it) add_around(it->origin());
    add_tile_shells(occ, keys);
    tbb::parallel_sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

/// Keeps the candidate blocks that have a cell with mixed corners, in their order.
void keep_mixed(std::vector<std::uint64_t>& keys, const States& states, const Progress& progress) {
    std::vector<std::uint8_t> keep(keys.size(), 0);
    for_blocks(keys.size(), 0.05, 0.25, progress, [&](std::size_t i) {
        std::uint16_t rows[9][9];
        keep[i] = states.fill(key_origin(keys[i]), rows) ? 1 : 0;
    });
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (keep[i]) keys[kept++] = keys[i];
    keys.resize(kept);
    keys.shrink_to_fit();
}

/// Corner rows, crossed edges and neighbours of block `b`, the one of keys[i]; returns its
/// mixed cells.
std::size_t fill_block(Block& b, std::size_t i, const std::vector<std::uint64_t>& keys, const States& states) {
    b.origin = key_origin(keys[i]);
    states.fill(b.origin, b.rows);
    std::size_t mixed = 0;
    for (int x = 0; x < 8; ++x) {
        std::uint64_t cx = 0, cy = 0, cz = 0;
        for (int y = 0; y < 8; ++y) {
            const unsigned r = b.rows[x][y];
            cx |= std::uint64_t((r ^ b.rows[x + 1][y]) & 0xFF) << (8 * y);
            cy |= std::uint64_t((r ^ b.rows[x][y + 1]) & 0xFF) << (8 * y);
            cz |= std::uint64_t((r ^ (r >> 1)) & 0xFF) << (8 * y);
            mixed += std::size_t(popcount64(mixed_row(b.rows, x, y)));
        }
        b.cross[0][x] = cx;
        b.cross[1][x] = cy;
        b.cross[2][x] = cz;
    }
    unsigned n = 0;
    for (int a = 0; a < 3; ++a)
        for (int x = 0; x < 8; ++x) {
            b.pre[a][x] = std::uint16_t(n);
            n += unsigned(popcount64(b.cross[a][x]));
        }
    b.nverts = n;
    for (int d = 0; d < 8; ++d) {
        const std::uint64_t k = block_key(b.origin.offsetBy(8 * (d & 1), 8 * ((d >> 1) & 1), 8 * ((d >> 2) & 1)));
        const auto it = std::lower_bound(keys.begin(), keys.end(), k);
        b.nb[d] = (it != keys.end() && *it == k) ? std::uint32_t(it - keys.begin()) : kNone;
    }
    return mixed;
}

} // namespace

std::vector<Block> find_blocks(const openvdb::BoolGrid& occ, const FlipGrid* flips, const Progress& progress,
                               MarchingCubesStats& stats) {
    check_extent(occ);
    std::vector<std::uint64_t> keys = candidate_keys(occ, flips);
    progress(0.05);
    const States states(occ, flips);
    keep_mixed(keys, states, progress);
    std::vector<Block> blocks(keys.size());
    stats.blocks = blocks.size();
    // Corner rows, crossed edges, neighbours.
    std::atomic<std::size_t> cells{0};
    for_blocks(blocks.size(), 0.25, 0.35, progress,
               [&](std::size_t i) { cells += fill_block(blocks[i], i, keys, states); });
    stats.surface_cells = cells;
    return blocks;
}

} // namespace cm::mc
