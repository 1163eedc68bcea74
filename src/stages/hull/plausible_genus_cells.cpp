// The voxel topology of plausible_genus.h: the Euler change of a removal, the outside about
// a voxel and the diagonal contacts across it.
#include "plausible_genus.h"

#include <array>
#include <cstdlib>

namespace cm::plausible {

namespace {

constexpr int kCentre = 13;

int bit_of(int x, int y, int z) { return (x + 1) + 3 * (y + 1) + 9 * (z + 1); }
// The six face neighbours of the centre in a neighbourhood.
constexpr unsigned kFaces = 1u << 4 | 1u << 10 | 1u << 12 | 1u << 14 | 1u << 16 | 1u << 22;

// The lattice cells (vertices, edges, faces, the cube) of a voxel, by the offset k of their
// centre from the voxel's (halved; bit order of a neighbourhood): the voxels incident to each
// (a mask of the neighbourhood) and its sign in the Euler characteristic V - E + F - C.
struct Cells {
    unsigned incident[27];
    int sign[27];
};
const Cells& cells() {
    static const Cells c = [] {
        Cells t{};
        for (int k = 0; k < 27; ++k) {
            const int d[3] = {k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1};
            const int dim = (d[0] == 0) + (d[1] == 0) + (d[2] == 0);
            t.sign[k] = dim % 2 == 0 ? 1 : -1;
            for (int j = 0; j < 27; ++j) {
                const int u[3] = {j % 3 - 1, j / 3 % 3 - 1, j / 9 - 1};
                bool in = true;
                for (int a = 0; a < 3; ++a) in = in && (u[a] == 0 || u[a] == d[a]);
                if (in) t.incident[k] |= 1u << j;
            }
        }
        return t;
    }();
    return c;
}

// The 26-neighbours within a neighbourhood of each of its voxels.
const std::array<unsigned, 27>& neighbours() {
    static const std::array<unsigned, 27> around = [] {
        std::array<unsigned, 27> a{};
        for (int k = 0; k < 27; ++k)
            for (int j = 0; j < 27; ++j)
                if (j != k && std::abs(j % 3 - k % 3) <= 1 && std::abs(j / 3 % 3 - k / 3 % 3) <= 1 &&
                    std::abs(j / 9 - k / 9) <= 1)
                    a[std::size_t(k)] |= 1u << j;
        return a;
    }();
    return around;
}

// The on voxels of `on` reached from `seed` (one of them) by 26-steps within them.
unsigned flood(unsigned on, unsigned seed) {
    unsigned reached = seed, grown = seed;
    while (grown) {
        unsigned next = 0;
        for (unsigned g = grown; g; g &= g - 1) next |= neighbours()[std::size_t(__builtin_ctz(g))];
        grown = next & on & ~reached;
        reached |= grown;
    }
    return reached;
}

} // namespace

// The change of the Euler characteristic of the kept volume (the union of its closed voxel
// cubes) that taking out the centre of a neighbourhood, with the rest of its piece `gone`
// (the centre's bit included), causes in the cells of the centre the piece has no earlier
// voxel (bit order) in: summed over a piece, the change its removal at once causes.
int euler_change(unsigned kept, unsigned gone) {
    int change = 0;
    for (int k = 0; k < 27; ++k) {
        const unsigned m = cells().incident[k];
        if (gone & m & ((1u << kCentre) - 1)) continue; // counted at an earlier voxel
        if (!(kept & m)) change -= cells().sign[k];     // the cell goes with the piece
    }
    return change;
}

bool removal_keeps_outside(unsigned nb) {
    // The outside voxels among the 18 nearest (no corners of the cube, not the centre),
    // flooded by face steps (shifts of the bit order: x 1, y 3, z 9) from one face neighbour
    // of the centre: one piece when the flood reaches every outside face neighbour.
    constexpr unsigned kNear = 0x7FFFFFFu & ~(1u << 0 | 1u << 2 | 1u << 6 | 1u << 8 | 1u << 18 | 1u << 20 | 1u << 24 |
                                              1u << 26 | 1u << kCentre);
    constexpr unsigned kX0 = 0x1249249u, kX2 = kX0 << 2; // x -1, x +1
    constexpr unsigned kY0 = 0x01C0E07u, kY2 = kY0 << 6; // y -1, y +1
    const unsigned out = ~nb & kNear, faces = out & kFaces;
    if (!faces) return false;
    unsigned f = faces & -faces;
    for (;;) {
        const unsigned g =
            (f | (f & ~kX2) << 1 | (f & ~kX0) >> 1 | (f & ~kY2) << 3 | (f & ~kY0) >> 3 | f << 9 | f >> 9) & out;
        if (g == f) break;
        f = g;
    }
    return (faces & ~f) == 0;
}

bool kept_one_piece(unsigned nb) {
    const unsigned on = nb & 0x7FFFFFFu & ~(1u << kCentre);
    return on && flood(on, on & -on) == on;
}

int kept_pieces(unsigned nb, std::array<unsigned, 26>& piece) {
    unsigned on = nb & 0x7FFFFFFu & ~(1u << kCentre);
    int n = 0;
    for (; on; ++n) {
        piece[std::size_t(n)] = flood(on, on & -on);
        on &= ~piece[std::size_t(n)];
    }
    return n;
}

// The off centre of `nb` (the voxel taken out) between two on voxels that touch by an
// edge or a corner alone: a 2x2 square with the centre where its on voxels are diagonal,
// or a 2x2x2 cube with two opposite corners on and its six others off.
bool diagonal_contact(unsigned nb) {
    const auto on = [&](int x, int y, int z) { return (nb >> bit_of(x, y, z) & 1) != 0; };
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
            for (int sz = -1; sz <= 1; sz += 2) {
                // The three squares through the centre in this octant.
                if (on(sx, 0, 0) && on(0, sy, 0) && !on(sx, sy, 0)) return true;
                if (on(sx, 0, 0) && on(0, 0, sz) && !on(sx, 0, sz)) return true;
                if (on(0, sy, 0) && on(0, 0, sz) && !on(0, sy, sz)) return true;
                // The cube: the centre's opposite corner off, the pairs of the other two
                // diagonals. A corner contact: one on at (sx,0,0)-type with its opposite
                // (0,sy,sz) on, the other six off.
                const bool c[8] = {false,        on(sx, 0, 0),  on(0, sy, 0),  on(sx, sy, 0),
                                   on(0, 0, sz), on(sx, 0, sz), on(0, sy, sz), on(sx, sy, sz)};
                int count = 0;
                for (bool b : c) count += b;
                if (count == 2 && ((c[1] && c[6]) || (c[2] && c[5]) || (c[4] && c[3]))) return true;
            }
    return false;
}

} // namespace cm::plausible
