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

// The voxels of `left` joined to `reached` within one leaf (by 26- or face steps: `spread`,
// spill or spill6 at kCentre) moved from `left` to `reached`.
template <class Spread>
void grow_within(LeafMask& reached, LeafMask& left, const Spread& spread) {
    for (;;) {
        const LeafMask g = and_not(spread(reached, kCentre), left, true);
        if (!any(g)) return;
        for (std::size_t x = 0; x < 8; ++x) reached[x] |= g[x], left[x] &= ~g[x];
    }
}

// The neighbour offsets k (bit k, bit order of a neighbourhood; the centre 13 included when
// `m` has a voxel) into which spill(m, k) (or spill6 at a face) can reach: those whose side
// of the leaf (x, y and z each at 0, at 7 or anywhere) `m` has voxels on. A superset: a
// corner needs one voxel at the corner, not one on each of its three faces.
inline unsigned spill_sides(const LeafMask& m) {
    // Per axis and per set of offsets it can take (bit 0: -1, 1: 0, 2: +1), the neighbours
    // whose offset along it is in the set.
    struct Sides {
        unsigned axis[3][8] = {};
        constexpr Sides() {
            for (int k = 0; k < 27; ++k)
                for (unsigned set = 0; set < 8; ++set) {
                    if (set >> (k % 3) & 1) axis[0][set] |= 1u << k;
                    if (set >> (k / 3 % 3) & 1) axis[1][set] |= 1u << k;
                    if (set >> (k / 9) & 1) axis[2][set] |= 1u << k;
                }
        }
    };
    static constexpr Sides kSides;
    std::uint64_t all = 0;
    for (const std::uint64_t w : m) all |= w;
    if (!all) return 0;
    const unsigned sx = 2u | unsigned(m[0] != 0) | unsigned(m[7] != 0) << 2;
    const unsigned sy = 2u | unsigned((all & 0xFFull) != 0) | unsigned((all >> 56) != 0) << 2;
    const unsigned sz =
        2u | unsigned((all & 0x0101010101010101ull) != 0) | unsigned((all & 0x8080808080808080ull) != 0) << 2;
    return kSides.axis[0][sx] & kSides.axis[1][sy] & kSides.axis[2][sz];
}

// A leaf's voxels of two sets with the layer about the leaf from its 26 neighbours, as rows
// along z (row [x + 1][y + 1], bit z + 1, for x, y, z from -1 to 8; a row of the leaf is a
// byte of its mask): the 3x3x3 neighbourhood of any voxel of the leaf in nine row reads,
// where a lookup per neighbour would find its leaf and offset 26 times.
struct Padded {
    std::uint16_t a[10][10] = {}, b[10][10] = {};

    /// The sets about leaf `l` (`around`: the leaves' neighbourhoods, kNoLeaf where the tree
    /// has no leaf: empty there), `sa(n)` and `sb(n)` giving leaf n's masks.
    template <class A, class B>
    Padded(const A& sa, const B& sb, const std::vector<std::uint32_t>& around, std::size_t l) {
        for (int k = 0; k < 27; ++k) {
            const std::uint32_t n = around[l * 27 + std::size_t(k)];
            if (n == kNoLeaf) continue;
            const int dx = k % 3 - 1, dy = k / 3 % 3 - 1, dz = k / 9 - 1;
            // The leaf's rows that fall in the padding: all 8, or the one layer next to the
            // centre leaf, along x and y; along z the whole row or its end bit.
            const int x0 = dx < 0 ? 7 : 0, x1 = dx > 0 ? 0 : 7;
            const int y0 = dy < 0 ? 7 : 0, y1 = dy > 0 ? 0 : 7;
            const LeafMask ma = sa(n), mb = sb(n);
            const auto row = [dz](std::uint64_t byte) {
                return std::uint16_t(dz == 0 ? byte << 1 : dz < 0 ? byte >> 7 : (byte & 1) << 9);
            };
            for (int x = x0; x <= x1; ++x)
                for (int y = y0; y <= y1; ++y) {
                    const int px = dx < 0 ? 0 : dx > 0 ? 9 : x + 1, py = dy < 0 ? 0 : dy > 0 ? 9 : y + 1;
                    a[px][py] |= row(ma[std::size_t(x)] >> (8 * y) & 0xFF);
                    b[px][py] |= row(mb[std::size_t(x)] >> (8 * y) & 0xFF);
                }
        }
    }
    /// The neighbourhood of voxel `off` of the leaf in set a (first) and b (bit order of a
    /// neighbourhood: x + 3 y + 9 z).
    std::pair<unsigned, unsigned> around(unsigned off) const {
        const unsigned x = off >> 6, y = off >> 3 & 7, z = off & 7;
        unsigned na = 0, nb = 0;
        for (unsigned dy = 0; dy < 3; ++dy)
            for (unsigned dx = 0; dx < 3; ++dx) {
                na |= spread(unsigned(a[x + dx][y + dy] >> z & 7)) << (dx + 3 * dy);
                nb |= spread(unsigned(b[x + dx][y + dy] >> z & 7)) << (dx + 3 * dy);
            }
        return {na, nb};
    }

private:
    // Three bits along z at the places 0, 9 and 18 of a neighbourhood.
    static unsigned spread(unsigned v) { return (v & 1) | (v >> 1 & 1) << 9 | (v >> 2 & 1) << 18; }
};

} // namespace cm::plausible::genus_masks
