// The bit grid of the handle cut: plausible_handle_bits.h.
#include "plausible_handle_bits.h"

#include <algorithm>
#include <functional>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace cm::plausible {

namespace handles {

using LeafT = openvdb::BoolTree::LeafNodeType;

Bits bits_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves, const CoordBBox& box) {
    Bits b(box);
    auto* bytes = reinterpret_cast<std::uint8_t*>(b.w.data());
    tbb::parallel_for(std::size_t(0), leaves.leafCount(), [&](std::size_t l) {
        const LeafT& leaf = leaves.leaf(l);
        const Coord o = leaf.origin();
        for (int x = 0; x < 8; ++x) {
            const std::uint64_t word = leaf.getValueMask().getWord<std::uint64_t>(openvdb::Index(x));
            if (!word) continue;
            for (int y = 0; y < 8; ++y) {
                const auto byte = std::uint8_t(word >> (8 * y));
                if (byte) bytes[b.index(o.offsetBy(x, y, 0)) >> 3] = byte;
            }
        }
    });
    return b;
}

CoordBBox box_of(const openvdb::tree::LeafManager<openvdb::BoolTree>& leaves) {
    CoordBBox box;
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) {
        CoordBBox b;
        if (leaves.leaf(l).getValueMask().isOff()) continue;
        leaves.leaf(l).evalActiveBoundingBox(b, false);
        box.expand(b);
    }
    return box;
}

namespace {

// The bits of a row dilated by one towards +z (the top bit of the row's previous word carried).
struct ZDilate {
    std::uint64_t carry = 0;
    std::uint64_t operator()(std::uint64_t v) {
        const std::uint64_t d = v | v << 1 | carry;
        carry = v >> 63;
        return d;
    }
};

} // namespace

// V - E + F - C of the union of the closed voxel cubes: a lattice cell is there when one of
// the voxels about it is, so each kind of cell is the voxels dilated towards + along the axes
// the cell spans no length of, counted row by row.
long euler_of(const Bits& b) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(1, b.nx), 0L,
        [&](const tbb::blocked_range<std::size_t>& r, long sum) {
            for (std::size_t x = r.begin(); x != r.end(); ++x)
                for (std::size_t y = 1; y < b.ny; ++y) {
                    const std::uint64_t *r00 = b.row(x, y), *r01 = b.row(x, y - 1), *r10 = b.row(x - 1, y),
                                        *r11 = b.row(x - 1, y - 1);
                    ZDilate z, zy, zx, zxy;
                    for (std::size_t k = 0; k < b.rw; ++k) {
                        const std::uint64_t c = r00[k], y1 = c | r01[k], x1 = c | r10[k], xy = y1 | x1 | r11[k];
                        if (!xy && !z.carry && !zy.carry && !zx.carry && !zxy.carry) continue;
                        sum += __builtin_popcountll(zxy(xy)) - __builtin_popcountll(zy(y1)) -
                               __builtin_popcountll(zx(x1)) - __builtin_popcountll(xy) + __builtin_popcountll(x1) +
                               __builtin_popcountll(y1) + __builtin_popcountll(z(c)) - __builtin_popcountll(c);
                    }
                }
            return sum;
        },
        std::plus<long>());
}

// The 26-connected pieces: the runs of every row joined to the runs they touch.
long pieces_of(const Bits& b) {
    const Runs runs(b);
    Roots roots;
    roots.up.resize(runs.runs.size());
    std::iota(roots.up.begin(), roots.up.end(), 0u);
    long pieces = long(runs.runs.size());
    runs.for_touching(b, [&](std::size_t i, std::size_t j) {
        if (roots.join(std::uint32_t(i), std::uint32_t(j))) --pieces;
    });
    return pieces;
}

VoxelTopology topology_of(const Bits& b) { return {euler_of(b), pieces_of(b)}; }

void dilate_by_faces(const Bits& in, const Bits& within, std::vector<std::uint64_t>& out) {
    const std::size_t row = in.rw, slab = in.ny * in.rw;
    const auto& o = in.w;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(slab, o.size() - slab),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k != r.end(); ++k)
                              out[k] = (o[k] | o[k] << 1 | o[k - 1] >> 63 | o[k] >> 1 | o[k + 1] << 63 | o[k - row] |
                                        o[k + row] | o[k - slab] | o[k + slab]) &
                                       within.w[k];
                      });
}

} // namespace handles

using namespace handles;

VoxelTopology voxel_topology(const openvdb::BoolTree& tree) {
    openvdb::BoolTree copy(tree);
    copy.voxelizeActiveTiles();
    openvdb::tree::LeafManager<openvdb::BoolTree> leaves(copy);
    const CoordBBox box = box_of(leaves);
    if (box.empty()) return {};
    return topology_of(bits_of(leaves, box));
}

} // namespace cm::plausible
