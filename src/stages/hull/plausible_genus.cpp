// See plausible_genus.h.
#include "plausible_genus.h"

#include <cstdint>
#include <queue>
#include <utility>

namespace cm::plausible {

namespace {

using LeafT = openvdb::BoolTree::LeafNodeType;
using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

constexpr int kCentre = 13;

int bit_of(int x, int y, int z) { return (x + 1) + 3 * (y + 1) + 9 * (z + 1); }

// Where the removal left voxels of the hull off: per removed voxel its state while they are
// taken out again one at a time.
enum State : std::uint8_t { kKept = 0, kIdle, kQueued, kOut, kWaiting, kSeen };

// The six face neighbours of the centre in a neighbourhood.
constexpr unsigned kFaces = 1u << 4 | 1u << 10 | 1u << 12 | 1u << 14 | 1u << 16 | 1u << 22;

bool any(const LeafMask& m) {
    std::uint64_t a = 0;
    for (const std::uint64_t w : m) a |= w;
    return a != 0;
}
LeafMask full() {
    LeafMask m;
    m.fill(~0ull);
    return m;
}
// a & b (keep), or ~a & ~b... : a & b when `both`, else ~a & ~b.
LeafMask and_not(const LeafMask& a, const LeafMask& b, bool both) {
    LeafMask r;
    for (std::size_t x = 0; x < 8; ++x) r[x] = both ? a[x] & b[x] : ~a[x] & ~b[x];
    return r;
}

// The voxels of the leaf at offset k (bit order of a neighbourhood; 13: the leaf itself) that
// are 26-neighbours of (or, for k 13, are) voxels of `m` (word x, byte y, bit z).
LeafMask spill(const LeafMask& m, int k) {
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

namespace {

class Retake {
public:
    Retake(Leaves& leaves, const std::vector<LeafMask>& hull, const std::function<float(const Coord&)>& field)
        : leaves_(leaves),
          hull_(hull),
          field_(field),
          state_(leaves.leafCount() * 512, kKept),
          around_(leaf_neighbourhoods(leaves)) {}

    // The removed voxels marked, then sorted by 26-connected piece: a piece whose removal at
    // once leaves the Euler characteristic of the kept volume as it was and that reaches the
    // outside stays out; the others come back on, the ones at the hull's outside queued.
    void restore() {
        for (std::size_t l = 0; l < leaves_.leafCount(); ++l) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            bool cut = false;
            for (std::size_t x = 0; x < 8; ++x)
                for (std::uint64_t w = hull_[l][x] & ~on[x]; w; w &= w - 1, cut = true) {
                    const std::size_t code = l * 512 + x * 64 + std::size_t(__builtin_ctzll(w));
                    state_[code] = kIdle;
                    removed_.push_back(code);
                }
            if (cut) cut_leaves_.push_back(l);
        }
        std::vector<std::size_t> back;
        sort_pieces(back);
        for (const std::size_t code : back) leaves_.leaf(code / 512).setValueOn(openvdb::Index(code % 512), true);
        for (const std::size_t code : back)
            if (~around_on(code) & kFaces) push(code, coord(code));
    }

    // Out again, highest field first, while the outside stays one piece about each.
    void take_out() {
        while (!queue_.empty()) {
            const std::size_t code = queue_.top().second;
            queue_.pop();
            if (state_[code] != kQueued) continue;
            if (!removal_keeps_outside(around_on(code))) {
                state_[code] = kWaiting;
                continue;
            }
            leaves_.leaf(code / 512).setValueOff(openvdb::Index(code % 512), false);
            state_[code] = kOut;
            // Its removed neighbours may go now (or again).
            for (int k = 0; k < 27; ++k) {
                if (k == kCentre) continue;
                const std::size_t c = neighbour(code, k);
                if (c != kNone && (state_[c] == kIdle || state_[c] == kWaiting)) push(c, coord(c));
            }
        }
    }

    // Kept voxels touching by an edge or a corner alone across a voxel taken out: that voxel
    // back (a few passes: a voxel put back can make such a contact of its own).
    void close_diagonal_contacts() {
        for (int pass = 0; pass < 4; ++pass) {
            // (Only where the outside about it stays one piece: no pocket sealed off.)
            std::size_t back = 0;
            for (const std::size_t code : touching_kept()) {
                const unsigned nb = around_on(code);
                if (!diagonal_contact(nb) || !removal_keeps_outside(nb)) continue;
                leaves_.leaf(code / 512).setValueOn(openvdb::Index(code % 512), true);
                state_[code] = kKept;
                ++back;
            }
            if (back == 0) break;
        }
    }

    std::size_t put_back() const {
        std::size_t n = 0;
        for (const std::size_t code : removed_) n += state_[code] != kOut;
        return n;
    }

private:
    static constexpr std::size_t kNone = ~std::size_t(0);

    Coord coord(std::size_t code) const {
        return leaves_.leaf(code / 512).offsetToGlobalCoord(openvdb::Index(code % 512));
    }

    // The code of the voxel at offset k (bit order of a neighbourhood) from `code`, kNone
    // where the tree has no leaf.
    std::size_t neighbour(std::size_t code, int k) const {
        const unsigned off = unsigned(code % 512);
        const int x = int(off >> 6) + k % 3 - 1, y = int(off >> 3 & 7) + k / 3 % 3 - 1, z = int(off & 7) + k / 9 - 1;
        const auto step = [](int v) { return v < 0 ? 0 : v > 7 ? 2 : 1; };
        const std::uint32_t n = around_[code / 512 * 27 + std::size_t(step(x) + 3 * step(y) + 9 * step(z))];
        return n == kNoLeaf ? kNone : std::size_t(n) * 512 + std::size_t((x & 7) << 6 | (y & 7) << 3 | (z & 7));
    }

    // The 3x3x3 neighbourhood of `code` (bit order as above): its on voxels.
    unsigned around_on(std::size_t code) const {
        unsigned nb = 0;
        for (int k = 0; k < 27; ++k) {
            const std::size_t c = neighbour(code, k);
            if (c != kNone && leaves_.leaf(c / 512).isValueOn(openvdb::Index(c % 512))) nb |= 1u << k;
        }
        return nb;
    }

    // The removed voxels by 26-connected piece (flooded a leaf's 512 voxels at a time): a
    // piece that touches the outside and whose removal at once leaves the kept volume's Euler
    // characteristic unchanged is out for good (kOut); the others are appended to `back` (to be
    // taken out one at a time). Only voxels with a voxel not removed about them add to the
    // change (one with all its neighbours removed adds nothing: euler_change).
    void sort_pieces(std::vector<std::size_t>& back) {
        std::vector<LeafMask> left(leaves_.leafCount(), LeafMask{}), reach(leaves_.leafCount(), LeafMask{});
        for (const std::size_t code : removed_) left[code / 512][code % 512 / 64] |= 1ull << (code % 64);
        const std::vector<LeafMask> gone = left;
        std::vector<std::size_t> work, touched;
        for (const std::size_t l0 : cut_leaves_)
            while (any(left[l0])) {
                std::size_t x0 = 0;
                while (!left[l0][x0]) ++x0;
                const std::uint64_t seed = left[l0][x0] & -left[l0][x0];
                reach[l0][x0] = seed, left[l0][x0] &= ~seed;
                work.assign(1, l0), touched.assign(1, l0);
                while (!work.empty()) {
                    const std::size_t l = work.back();
                    work.pop_back();
                    for (;;) { // grow within the leaf
                        const LeafMask g = and_not(spill(reach[l], kCentre), left[l], true);
                        if (!any(g)) break;
                        for (std::size_t x = 0; x < 8; ++x) reach[l][x] |= g[x], left[l][x] &= ~g[x];
                    }
                    for (int k = 0; k < 27; ++k) {
                        const std::uint32_t n = around_[l * 27 + std::size_t(k)];
                        if (k == kCentre || n == kNoLeaf) continue;
                        const LeafMask g = and_not(spill(reach[l], k), left[n], true);
                        if (!any(g)) continue;
                        if (!any(reach[n])) touched.push_back(n);
                        for (std::size_t x = 0; x < 8; ++x) reach[n][x] |= g[x], left[n][x] &= ~g[x];
                        work.push_back(n);
                    }
                }
                int change = 0;
                bool outside = false;
                for (const std::size_t l : touched) {
                    // Voxels with one not removed about them (a missing leaf: none removed).
                    LeafMask near = spill(and_not(gone[l], LeafMask{}, false), kCentre);
                    for (int k = 0; k < 27; ++k) {
                        if (k == kCentre) continue;
                        const std::uint32_t n = around_[l * 27 + std::size_t(k)];
                        const LeafMask m = spill(n == kNoLeaf ? full() : and_not(gone[n], LeafMask{}, false), 26 - k);
                        for (std::size_t x = 0; x < 8; ++x) near[x] |= m[x];
                    }
                    for (std::size_t x = 0; x < 8; ++x)
                        for (std::uint64_t w = reach[l][x] & near[x]; w; w &= w - 1)
                            change += voxel_change(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)), outside);
                }
                const bool at_once = change == 0 && outside;
                for (const std::size_t l : touched) {
                    for (std::size_t x = 0; x < 8; ++x)
                        for (std::uint64_t w = reach[l][x]; w; w &= w - 1) {
                            const std::size_t code = l * 512 + x * 64 + std::size_t(__builtin_ctzll(w));
                            state_[code] = at_once ? kOut : kIdle;
                            if (!at_once) back.push_back(code);
                        }
                    reach[l] = LeafMask{};
                }
            }
    }

    // What taking out voxel `code` adds to its piece's change (euler_change); `outside` set when
    // a face neighbour is neither kept nor removed.
    int voxel_change(std::size_t code, bool& outside) const {
        unsigned kept = 0, gone = 0;
        for (int k = 0; k < 27; ++k) {
            const std::size_t c = neighbour(code, k);
            if (c == kNone) continue;
            if (state_[c] != kKept) gone |= 1u << k;
            else if (leaves_.leaf(c / 512).isValueOn(openvdb::Index(c % 512))) kept |= 1u << k;
        }
        outside = outside || (~(kept | gone) & kFaces) != 0;
        return euler_change(kept, gone);
    }

    // The voxels taken out (in leaf order) with a kept face neighbour: only these can stand
    // between kept voxels touching by an edge or a corner alone.
    std::vector<std::size_t> touching_kept() const {
        static constexpr int kFace[6] = {12, 14, 10, 16, 4, 22}; // -x +x -y +y -z +z
        std::vector<std::size_t> out;
        for (const std::size_t l : cut_leaves_) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            LeafMask touch{};
            for (int d = 0; d < 6; ++d) {
                const std::uint32_t n = around_[l * 27 + std::size_t(kFace[d])];
                const LeafMask next = n == kNoLeaf ? LeafMask{} : leaf_mask(leaves_.leaf(n));
                const LeafMask m = neighbour_in(on, &next, d);
                for (std::size_t x = 0; x < 8; ++x) touch[x] |= m[x];
            }
            for (std::size_t x = 0; x < 8; ++x)
                for (std::uint64_t w = hull_[l][x] & ~on[x] & touch[x]; w; w &= w - 1)
                    out.push_back(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)));
        }
        return out;
    }

    void push(std::size_t code, const Coord& g) {
        state_[code] = kQueued;
        queue_.emplace(field_(g), code);
    }

    // The off centre of `nb` (the voxel taken out) between two on voxels that touch by an
    // edge or a corner alone: a 2x2 square with the centre where its on voxels are diagonal,
    // or a 2x2x2 cube with two opposite corners on and its six others off.
    static bool diagonal_contact(unsigned nb) {
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

    Leaves& leaves_;
    const std::vector<LeafMask>& hull_;
    const std::function<float(const Coord&)>& field_;
    std::vector<std::uint8_t> state_;
    std::vector<std::size_t> removed_;
    std::vector<std::size_t> cut_leaves_;
    std::vector<std::uint32_t> around_;
    std::priority_queue<std::pair<float, std::size_t>> queue_;
};

} // namespace

bool removal_keeps_outside(unsigned nb) {
    // The outside voxels among the 18 nearest (no corners of the cube), flooded by face steps
    // from each face neighbour of the centre.
    unsigned out = 0;
    for (int k = 0; k < 27; ++k) {
        const int x = k % 3 - 1, y = k / 3 % 3 - 1, z = k / 9 - 1;
        if (k != kCentre && std::abs(x) + std::abs(y) + std::abs(z) <= 2 && !(nb >> k & 1)) out |= 1u << k;
    }
    int pieces = 0;
    unsigned seen = 0;
    for (int d = 0; d < 6; ++d) {
        int f[3] = {0, 0, 0};
        f[d / 2] = (d & 1) ? 1 : -1;
        const int s = bit_of(f[0], f[1], f[2]);
        if (!(out >> s & 1) || (seen >> s & 1)) continue;
        ++pieces;
        unsigned front = 1u << s;
        seen |= front;
        while (front) {
            const int k = __builtin_ctz(front);
            front &= front - 1;
            const int x = k % 3 - 1, y = k / 3 % 3 - 1, z = k / 9 - 1;
            for (int e = 0; e < 6; ++e) {
                int p[3] = {x, y, z};
                p[e / 2] += (e & 1) ? 1 : -1;
                if (std::abs(p[0]) > 1 || std::abs(p[1]) > 1 || std::abs(p[2]) > 1) continue;
                const int q = bit_of(p[0], p[1], p[2]);
                if ((out >> q & 1) && !(seen >> q & 1)) seen |= 1u << q, front |= 1u << q;
            }
        }
    }
    return pieces == 1;
}

std::size_t keep_hull_genus(Leaves& leaves, const std::vector<LeafMask>& hull,
                            const std::function<float(const Coord&)>& field) {
    Retake r(leaves, hull, field);
    r.restore();
    r.take_out();
    r.close_diagonal_contacts();
    return r.put_back();
}

} // namespace cm::plausible
