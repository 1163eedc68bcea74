// The word operations of the genus repair (plausible_genus.cpp) on a leaf's 512 voxels as a
// mask (word x, byte y, bit z), by the offset k of a neighbouring leaf in the bit order of a
// 3x3x3 neighbourhood (x + 3 y + 9 z; 13 the leaf itself).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "leaf_masks.h"

namespace cm::plausible::genus_masks {

constexpr int kCentre = 13;

// The six face neighbours of the centre in a neighbourhood.
constexpr unsigned kFaces = 1u << 4 | 1u << 10 | 1u << 12 | 1u << 14 | 1u << 16 | 1u << 22;

inline bool any(const LeafMask& m) {
    std::uint64_t a = 0;
    for (const std::uint64_t w : m) a |= w;
    return a != 0;
}
inline LeafMask full() {
    LeafMask m;
    m.fill(~0ull);
    return m;
}
// a & b (keep), or ~a & ~b... : a & b when `both`, else ~a & ~b.
inline LeafMask and_not(const LeafMask& a, const LeafMask& b, bool both) {
    LeafMask r;
    for (std::size_t x = 0; x < 8; ++x) r[x] = both ? a[x] & b[x] : ~a[x] & ~b[x];
    return r;
}

// The voxels of the leaf at offset k (bit order of a neighbourhood; 13: the leaf itself) that
// are 26-neighbours of (or, for k 13, are) voxels of `m` (word x, byte y, bit z).
inline LeafMask spill(const LeafMask& m, int k) {
    const int a = k % 3 - 1, b = k / 3 % 3 - 1, c = k / 9 - 1;
    LeafMask out{};
    for (int xd = 0; xd < 8; ++xd) {
        std::uint64_t w;
        if (a == 0)
            w = m[std::size_t(xd)] | (xd > 0 ? m[std::size_t(xd - 1)] : 0) | (xd < 7 ? m[std::size_t(xd + 1)] : 0);
        else if (a == 1 && xd == 0) w = m[7];
        else if (a == -1 && xd == 7) w = m[0];
        else continue;
        if (b == 0) w |= w << 8 | w >> 8;
        else w = b == 1 ? w >> 56 : (w & 0xFFull) << 56;
        if (c == 0) w |= (w << 1 & 0xFEFEFEFEFEFEFEFEull) | (w >> 1 & 0x7F7F7F7F7F7F7F7Full);
        else w = c == 1 ? (w >> 7) & 0x0101010101010101ull : (w & 0x0101010101010101ull) << 7;
        out[std::size_t(xd)] = w;
    }
    return out;
}

// The voxels of the leaf at face offset k (or, for k 13, the leaf itself) that are face
// neighbours of (or are) voxels of `m`.
inline LeafMask spill6(const LeafMask& m, int k) {
    LeafMask out{};
    for (std::size_t x = 0; x < 8; ++x) {
        const std::uint64_t w = m[x];
        switch (k) {
        case 13:
            out[x] = w | w << 8 | w >> 8 | (w << 1 & 0xFEFEFEFEFEFEFEFEull) | (w >> 1 & 0x7F7F7F7F7F7F7F7Full) |
                     (x > 0 ? m[x - 1] : 0) | (x < 7 ? m[x + 1] : 0);
            break;
        case 14: out[0] = x == 7 ? w : out[0]; break; // +x
        case 12: out[7] = x == 0 ? w : out[7]; break; // -x
        case 16: out[x] = w >> 56; break;             // +y
        case 10: out[x] = (w & 0xFFull) << 56; break; // -y
        case 22: out[x] = (w >> 7) & 0x0101010101010101ull; break;
        default: out[x] = (w & 0x0101010101010101ull) << 7; break; // 4: -z
        }
    }
    return out;
}

// A leaf's voxels of two sets with the layer about the leaf from its 26 neighbours, as rows
// along x (row [y + 1][z + 1], bit x + 1, for x, y, z from -1 to 8): the 3x3x3 neighbourhood
// of any voxel of the leaf in nine row reads, where a lookup per neighbour would find its
// leaf and offset 26 times.
struct Padded {
    std::uint16_t a[10][10] = {}, b[10][10] = {};

    /// The sets `sa` and `sb` about leaf `l` (`around`: the leaves' neighbourhoods, kNoLeaf
    /// where the tree has no leaf: empty there).
    Padded(const std::vector<LeafMask>& sa, const std::vector<LeafMask>& sb, const std::vector<std::uint32_t>& around,
           std::size_t l) {
        for (int k = 0; k < 27; ++k) {
            const std::uint32_t n = around[l * 27 + std::size_t(k)];
            if (n == kNoLeaf) continue;
            const int dx = k % 3 - 1, dy = k / 3 % 3 - 1, dz = k / 9 - 1;
            // The leaf's voxels that fall in the padding along each axis: all 8, or the one
            // layer next to the centre leaf.
            const int x0 = dx < 0 ? 7 : 0, x1 = dx > 0 ? 0 : 7;
            const int y0 = dy < 0 ? 7 : 0, y1 = dy > 0 ? 0 : 7;
            const int z0 = dz < 0 ? 7 : 0, z1 = dz > 0 ? 0 : 7;
            const LeafMask& ma = sa[n];
            const LeafMask& mb = sb[n];
            for (int y = y0; y <= y1; ++y)
                for (int z = z0; z <= z1; ++z) {
                    const int py = dy < 0 ? 0 : dy > 0 ? 9 : y + 1, pz = dz < 0 ? 0 : dz > 0 ? 9 : z + 1;
                    const int sh = y * 8 + z;
                    std::uint16_t ra = 0, rb = 0;
                    for (int x = x0; x <= x1; ++x) {
                        const int px = dx < 0 ? 0 : dx > 0 ? 9 : x + 1;
                        ra |= std::uint16_t((ma[std::size_t(x)] >> sh & 1) << px);
                        rb |= std::uint16_t((mb[std::size_t(x)] >> sh & 1) << px);
                    }
                    a[py][pz] |= ra, b[py][pz] |= rb;
                }
        }
    }
    /// The neighbourhood of voxel `off` of the leaf in set a (first) and b (bit order of a
    /// neighbourhood: x + 3 y + 9 z).
    std::pair<unsigned, unsigned> around(unsigned off) const {
        const unsigned x = off >> 6, y = off >> 3 & 7, z = off & 7;
        unsigned na = 0, nb = 0;
        for (unsigned dz = 0; dz < 3; ++dz)
            for (unsigned dy = 0; dy < 3; ++dy) {
                na |= unsigned(a[y + dy][z + dz] >> x & 7) << (3 * dy + 9 * dz);
                nb |= unsigned(b[y + dy][z + dz] >> x & 7) << (3 * dy + 9 * dz);
            }
        return {na, nb};
    }
};

} // namespace cm::plausible::genus_masks
