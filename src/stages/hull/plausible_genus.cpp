// See plausible_genus.h.
#include "plausible_genus.h"

#include <cstdint>
#include <queue>
#include <unordered_map>
#include <utility>

#include <openvdb/tree/ValueAccessor.h>

namespace cm::plausible {

namespace {

using LeafT = openvdb::BoolTree::LeafNodeType;
using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

constexpr int kCentre = 13;

int bit_of(int x, int y, int z) { return (x + 1) + 3 * (y + 1) + 9 * (z + 1); }

// The 3x3x3 neighbourhood of g in the tree, bit x + 3 y + 9 z (offsets + 1).
template <typename Acc>
unsigned neighbourhood(const Acc& acc, const Coord& g) {
    unsigned nb = 0;
    for (int k = 0; k < 27; ++k)
        if (acc.isValueOn(g.offsetBy(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1))) nb |= 1u << k;
    return nb;
}

// Where the removal left voxels of the hull off: per removed voxel its state while they are
// taken out again one at a time.
enum State : std::uint8_t { kKept = 0, kIdle, kQueued, kOut, kWaiting };

class Retake {
public:
    Retake(Leaves& leaves, const std::vector<LeafMask>& hull, const std::function<float(const Coord&)>& field)
        : leaves_(leaves), hull_(hull), field_(field), tree_(leaves.tree()), state_(leaves.leafCount() * 512, kKept) {
        std::unordered_map<std::uint64_t, std::uint32_t> leaf_of;
        leaf_of.reserve(leaves.leafCount() * 2);
        for (std::size_t l = 0; l < leaves.leafCount(); ++l)
            leaf_of.emplace(leaf_key(leaves.leaf(l).origin()), std::uint32_t(l));
        // Each leaf's 26 neighbours and itself (bit order of a neighbourhood), kNoLeaf where none.
        around_.resize(leaves.leafCount() * 27);
        for (std::size_t l = 0; l < leaves.leafCount(); ++l)
            for (int k = 0; k < 27; ++k) {
                const Coord o = leaves.leaf(l).origin().offsetBy(8 * (k % 3 - 1), 8 * (k / 3 % 3 - 1), 8 * (k / 9 - 1));
                const auto it = leaf_of.find(leaf_key(o));
                around_[l * 27 + std::size_t(k)] = it == leaf_of.end() ? kNoLeaf : it->second;
            }
    }

    // The removed voxels back on, marked; the ones at the hull's outside queued.
    void restore() {
        for (std::size_t l = 0; l < leaves_.leafCount(); ++l) {
            auto& leaf = leaves_.leaf(l);
            for (openvdb::Index off = 0; off < LeafT::SIZE; ++off)
                if ((hull_[l][off >> 6] >> (off & 63) & 1) && !leaf.isValueOn(off)) {
                    leaf.setValueOn(off, true);
                    state_[l * 512 + off] = kIdle;
                    removed_.push_back(l * 512 + off);
                }
        }
        openvdb::tree::ValueAccessor<const openvdb::BoolTree> acc(tree_);
        for (const std::size_t code : removed_) {
            const Coord g = coord(code);
            for (int d = 0; d < 6; ++d) {
                Coord q = g;
                q[d / 2] += (d & 1) ? 1 : -1;
                if (!acc.isValueOn(q)) {
                    push(code, g);
                    break;
                }
            }
        }
    }

    // Out again, highest field first, while the outside stays one piece about each.
    void take_out() {
        openvdb::tree::ValueAccessor<openvdb::BoolTree> acc(tree_);
        while (!queue_.empty()) {
            const std::size_t code = queue_.top().second;
            queue_.pop();
            if (state_[code] != kQueued) continue;
            const Coord g = coord(code);
            if (!removal_keeps_outside(neighbourhood(acc, g))) {
                state_[code] = kWaiting;
                continue;
            }
            acc.setValueOff(g, false);
            state_[code] = kOut;
            // Its removed neighbours may go now (or again).
            for (int k = 0; k < 27; ++k) {
                if (k == kCentre) continue;
                const Coord q = g.offsetBy(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
                const std::size_t c = code_of(code / 512, q);
                if (c != kNone && (state_[c] == kIdle || state_[c] == kWaiting)) push(c, q);
            }
        }
    }

    // Kept voxels touching by an edge or a corner alone across a voxel taken out: that voxel
    // back (a few passes: a voxel put back can make such a contact of its own).
    void close_diagonal_contacts() {
        openvdb::tree::ValueAccessor<openvdb::BoolTree> acc(tree_);
        for (int pass = 0; pass < 4; ++pass) {
            // (Only where the outside about it stays one piece: no pocket sealed off.)
            std::size_t back = 0;
            for (const std::size_t code : removed_) {
                if (state_[code] != kOut) continue;
                const unsigned nb = neighbourhood(acc, coord(code));
                if (!diagonal_contact(nb) || !removal_keeps_outside(nb)) continue;
                acc.setValueOn(coord(code), true);
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

    // The code of grid point g next to (or in) leaf l.
    std::size_t code_of(std::size_t l, const Coord& g) const {
        const Coord& o = leaves_.leaf(l).origin();
        const int k = ((g.x() >> 3) - (o.x() >> 3) + 1) + 3 * ((g.y() >> 3) - (o.y() >> 3) + 1) +
                      9 * ((g.z() >> 3) - (o.z() >> 3) + 1);
        const std::uint32_t n = around_[l * 27 + std::size_t(k)];
        return n == kNoLeaf ? kNone : std::size_t(n) * 512 + LeafT::coordToOffset(g);
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
    openvdb::BoolTree& tree_;
    std::vector<std::uint8_t> state_;
    std::vector<std::size_t> removed_;
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
