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
    Retake(Leaves& leaves, const std::vector<LeafMask>& hull, const VoxelField& field)
        : leaves_(leaves),
          hull_(hull),
          field_(field),
          state_(leaves.leafCount() * 512, kKept),
          around_(leaf_neighbourhoods(leaves)) {}

    // The removed voxels marked, then sorted by 26-connected piece: a piece whose removal at
    // once leaves the Euler characteristic of the kept volume as it was and that reaches the
    // outside stays out; the others come back on, the ones at the hull's outside queued.
    void restore() {
        removed_ = 0;
        for (std::size_t l = 0; l < leaves_.leafCount(); ++l) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            std::size_t n = 0;
            for (std::size_t x = 0; x < 8; ++x)
                for (std::uint64_t w = hull_[l][x] & ~on[x]; w; w &= w - 1, ++n)
                    state_[l * 512 + x * 64 + std::size_t(__builtin_ctzll(w))] = kIdle;
            if (n) cut_leaves_.push_back(l), removed_ += n;
        }
        std::vector<std::size_t> back;
        sort_pieces(back);
        for (const std::size_t code : back) leaves_.leaf(code / 512).setValueOn(openvdb::Index(code % 512), true);
        for (const std::size_t code : back)
            if (~around_on(code) & kFaces) push(code);
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
                if (c != kNone && (state_[c] == kIdle || state_[c] == kWaiting)) push(c);
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

    // The removed voxels on again (the others are off: out).
    std::size_t put_back() const {
        std::size_t out = 0;
        for (const std::size_t l : cut_leaves_) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            for (std::size_t x = 0; x < 8; ++x) out += std::size_t(__builtin_popcountll(hull_[l][x] & ~on[x]));
        }
        return removed_ - out;
    }

private:
    static constexpr std::size_t kNone = ~std::size_t(0);

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
    // piece that touches the outside, whose removal at once leaves the kept volume's Euler
    // characteristic unchanged and whose kept voxels about it are one piece by themselves (so
    // no part of the kept volume comes off: that and a tunnel would sum to no change) is out
    // for good (kOut); the others are appended to `back` (to be taken out one at a time). Only
    // voxels with a voxel not removed about them add to the change (one with all its
    // neighbours removed adds nothing: euler_change).
    void sort_pieces(std::vector<std::size_t>& back) {
        const std::size_t n = leaves_.leafCount();
        std::vector<LeafMask> left(n, LeafMask{}), reach(n, LeafMask{});
        for (const std::size_t l : cut_leaves_) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            for (std::size_t x = 0; x < 8; ++x) left[l][x] = hull_[l][x] & ~on[x];
        }
        const std::vector<LeafMask> gone = left;
        std::vector<std::size_t> touched;
        for (const std::size_t l0 : cut_leaves_)
            while (any(left[l0])) {
                flood26(l0, left, reach, touched);
                int change = 0;
                bool outside = false;
                for (const std::size_t l : touched) {
                    // Voxels with one not removed about them (a missing leaf: none removed).
                    LeafMask near = spill(and_not(gone[l], LeafMask{}, false), kCentre);
                    for (int k = 0; k < 27; ++k) {
                        if (k == kCentre) continue;
                        const std::uint32_t nl = around_[l * 27 + std::size_t(k)];
                        const LeafMask m = spill(nl == kNoLeaf ? full() : and_not(gone[nl], LeafMask{}, false), 26 - k);
                        for (std::size_t x = 0; x < 8; ++x) near[x] |= m[x];
                    }
                    for (std::size_t x = 0; x < 8; ++x)
                        for (std::uint64_t w = reach[l][x] & near[x]; w; w &= w - 1)
                            change += voxel_change(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)), outside);
                }
                const bool at_once = change == 0 && outside && collar_connected(reach, touched);
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

    // The 26-connected piece of `left` (per leaf) of its first voxel in leaf l0 moved from
    // `left` to `reach`; `touched` gets the leaves it has voxels in.
    void flood26(std::size_t l0, std::vector<LeafMask>& left, std::vector<LeafMask>& reach,
                 std::vector<std::size_t>& touched) const {
        std::size_t x0 = 0;
        while (!left[l0][x0]) ++x0;
        const std::uint64_t seed = left[l0][x0] & -left[l0][x0];
        reach[l0][x0] |= seed, left[l0][x0] &= ~seed;
        std::vector<std::size_t> work(1, l0);
        touched.assign(1, l0);
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
    }

    // Whether the kept voxels 26-neighbours of the piece `piece` (per leaf, over the leaves
    // `in`) are one 26-connected set by themselves. (When they are, its removal joins no two
    // of them apart: no part of the kept volume comes off.)
    bool collar_connected(const std::vector<LeafMask>& piece, const std::vector<std::size_t>& in) {
        if (collar_.empty())
            collar_.assign(leaves_.leafCount(), LeafMask{}), hold_.assign(leaves_.leafCount(), LeafMask{});
        std::vector<std::size_t> leaves;
        for (const std::size_t l : in)
            for (int k = 0; k < 27; ++k) {
                const std::uint32_t n = around_[l * 27 + std::size_t(k)];
                if (n == kNoLeaf) continue;
                const LeafMask g = and_not(spill(piece[l], k), leaf_mask(leaves_.leaf(n)), true);
                if (!any(g)) continue;
                if (!any(collar_[n])) leaves.push_back(n);
                for (std::size_t x = 0; x < 8; ++x) collar_[n][x] |= g[x];
            }
        bool one = true;
        if (!leaves.empty()) {
            std::vector<std::size_t> reached;
            flood26(leaves[0], collar_, hold_, reached);
            for (const std::size_t l : reached) hold_[l] = LeafMask{};
        }
        for (const std::size_t l : leaves) one = one && !any(collar_[l]), collar_[l] = LeafMask{};
        return one;
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

    void push(std::size_t code) {
        state_[code] = kQueued;
        queue_.emplace(field_(code / 512, openvdb::Index(code % 512)), code);
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
    const VoxelField& field_;
    std::vector<std::uint8_t> state_;
    std::size_t removed_ = 0;
    std::vector<std::size_t> cut_leaves_;
    std::vector<std::uint32_t> around_;
    std::vector<LeafMask> collar_, hold_; // collar_connected's work (all empty between calls)
    std::priority_queue<std::pair<float, std::size_t>> queue_;
};

} // namespace

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

std::size_t keep_hull_genus(Leaves& leaves, const std::vector<LeafMask>& hull, const VoxelField& field) {
    Retake r(leaves, hull, field);
    r.restore();
    r.take_out();
    r.close_diagonal_contacts();
    return r.put_back();
}

} // namespace cm::plausible
