// See plausible_genus_checks.h.
#include "plausible_genus_checks.h"
#include "plausible_genus.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace cm::plausible::genus_checks {

using namespace genus_masks;
using plausible::euler_change;

std::vector<std::size_t> take(LeafMasks& m, const std::vector<std::size_t>& in) {
    std::vector<std::size_t> out;
    for (const std::size_t l : in) {
        for (std::size_t x = 0; x < 8; ++x)
            for (std::uint64_t w = m[l][x]; w; w &= w - 1)
                out.push_back(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)));
        m[l] = LeafMask{};
    }
    return out;
}

void PieceChecks::load() {
    on_.resize(leaves_.leafCount());
    tbb::parallel_for(std::size_t(0), on_.size(), [&](std::size_t l) { on_[l] = leaf_mask(leaves_.leaf(l)); });
}

void PieceChecks::store(const std::vector<std::size_t>& cut) {
    for (const std::size_t l : cut) {
        auto& leaf = leaves_.leaf(l);
        const LeafMask was = leaf_mask(leaf);
        for (std::size_t x = 0; x < 8; ++x)
            for (std::uint64_t w = was[x] ^ on_[l][x]; w; w &= w - 1) {
                const auto off = openvdb::Index(x * 64 + std::size_t(__builtin_ctzll(w)));
                if (on_[l][x] >> (off % 64) & 1) leaf.setValueOn(off, true);
                else leaf.setValueOff(off, false);
            }
    }
    on_ = {};
}

void PieceChecks::flood26(std::size_t seed, LeafMasks& left, LeafMasks& reach,
                          std::vector<std::size_t>& touched) const {
    const std::size_t l0 = seed / 512, x0 = seed % 512 / 64;
    reach[l0][x0] |= 1ull << (seed % 64), left[l0][x0] &= ~(1ull << (seed % 64));
    std::vector<std::size_t> work(1, l0);
    touched.assign(1, l0);
    while (!work.empty()) {
        const std::size_t l = work.back();
        work.pop_back();
        grow_within(reach[l], left[l], spill);
        const unsigned sides = spill_sides(reach[l]);
        for (int k = 0; k < 27; ++k) {
            const std::uint32_t n = around_[l * 27 + std::size_t(k)];
            if (k == kCentre || !(sides >> k & 1) || n == kNoLeaf || !any(left[n])) continue;
            const LeafMask g = and_not(spill(reach[l], k), left[n], true);
            if (!any(g)) continue;
            if (!any(reach[n])) touched.push_back(n);
            for (std::size_t x = 0; x < 8; ++x) reach[n][x] |= g[x], left[n][x] &= ~g[x];
            work.push_back(n);
        }
    }
}

int PieceChecks::leaf_change(std::size_t l, const LeafMask& which, const LeafMasks& gone, bool& outside) const {
    if (!any(which)) return 0;
    const Padded p([&](std::size_t n) { return on(n); }, [&](std::size_t n) { return gone[n]; }, around_, l);
    int change = 0;
    for (std::size_t x = 0; x < 8; ++x)
        for (std::uint64_t w = which[x]; w; w &= w - 1) {
            const auto [on, g] = p.around(unsigned(x * 64 + std::size_t(__builtin_ctzll(w))));
            const unsigned kept = on & ~g;
            outside = outside || (~(kept | g) & kFaces) != 0;
            change += euler_change(kept, g);
        }
    return change;
}

bool PieceChecks::at_once(Scratch& s, const LeafMasks& piece, const std::vector<std::size_t>& in, int change,
                          bool outside) const {
    if (change != 0 || !outside) return false;
    if (in.size() < kSideBySide)
        return collar_connected(s, piece, in) && reaches_outside(s, piece, in) && outside_connected(s, piece, in);
    s.ready(leaves_.leafCount());
    bool ok[3] = {false, false, false};
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_invoke([&] { ok[0] = collar_connected(s, piece, in); },
                             [&] { ok[1] = reaches_outside(s, piece, in); },
                             [&] { ok[2] = outside_connected(s, piece, in); });
    });
    return ok[0] && ok[1] && ok[2];
}

// Whether the kept voxels 26-neighbours of the piece `piece` (per leaf, over the leaves
// `in`) are one 26-connected set by themselves. (When they are, its removal joins no two
// of them apart: no part of the kept volume comes off.)
bool PieceChecks::collar_connected(Scratch& s, const LeafMasks& piece, const std::vector<std::size_t>& in) const {
    s.ready(leaves_.leafCount());
    LeafMasks &collar = s.collar, &hold = s.hold;
    std::vector<std::size_t> leaves;
    for (const std::size_t l : in) {
        const unsigned sides = spill_sides(piece[l]);
        for (int k = 0; k < 27; ++k) {
            const std::uint32_t n = around_[l * 27 + std::size_t(k)];
            if (!(sides >> k & 1) || n == kNoLeaf) continue;
            // The kept voxels about it: on and not in it (a chunk of a piece that went back
            // is on while it is checked).
            LeafMask g = and_not(spill(piece[l], k), on(n), true);
            for (std::size_t x = 0; x < 8; ++x) g[x] &= ~piece[n][x];
            if (!any(g)) continue;
            if (!any(collar[n])) leaves.push_back(n);
            for (std::size_t x = 0; x < 8; ++x) collar[n][x] |= g[x];
        }
    }
    bool one = true;
    if (!leaves.empty()) {
        std::vector<std::size_t> reached;
        std::size_t x0 = 0;
        while (!collar[leaves[0]][x0]) ++x0;
        flood26(leaves[0] * 512 + x0 * 64 + std::size_t(__builtin_ctzll(collar[leaves[0]][x0])), collar, hold, reached);
        for (const std::size_t l : reached) hold[l] = LeafMask{};
    }
    for (const std::size_t l : leaves) one = one && !any(collar[l]), collar[l] = LeafMask{};
    return one;
}

// Whether every voxel of `q` (per leaf, over the leaves `in`) reaches by face steps
// within it one with a face neighbour neither on nor in `q` (the outside: what is
// removed reaches it so): taking `q` out then seals no cavity.
bool PieceChecks::reaches_outside(Scratch& s, const LeafMasks& q, const std::vector<std::size_t>& in) const {
    static constexpr int kFace[6] = {4, 10, 12, 14, 16, 22};
    s.ready(leaves_.leafCount());
    LeafMasks &seen = s.seen, &rest = s.rest;
    const auto off = [&](std::uint32_t n) { // neither on nor in q (a missing leaf: all)
        if (n == kNoLeaf) return full();
        return and_not(on(n), q[n], false);
    };
    std::vector<std::size_t> work;
    for (const std::size_t l : in) {
        LeafMask near = spill6(off(std::uint32_t(l)), kCentre);
        const unsigned sides = spill_sides(q[l]);
        for (const int k : kFace) {
            if (!(sides >> k & 1)) continue;
            const LeafMask m = spill6(off(around_[l * 27 + std::size_t(k)]), 26 - k);
            for (std::size_t x = 0; x < 8; ++x) near[x] |= m[x];
        }
        for (std::size_t x = 0; x < 8; ++x) seen[l][x] = q[l][x] & near[x], rest[l][x] = q[l][x] & ~near[x];
        work.push_back(l);
    }
    while (!work.empty()) {
        const std::size_t l = work.back();
        work.pop_back();
        grow_within(seen[l], rest[l], spill6);
        const unsigned sides = spill_sides(seen[l]);
        for (const int k : kFace) {
            const std::uint32_t n = around_[l * 27 + std::size_t(k)];
            if (!(sides >> k & 1) || n == kNoLeaf || !any(rest[n])) continue;
            const LeafMask g = and_not(spill6(seen[l], k), rest[n], true);
            if (!any(g)) continue;
            for (std::size_t x = 0; x < 8; ++x) seen[n][x] |= g[x], rest[n][x] &= ~g[x];
            work.push_back(n);
        }
    }
    bool all = true;
    for (const std::size_t l : in) all = all && !any(rest[l]), seen[l] = rest[l] = LeafMask{};
    return all;
}

// Whether the outside voxels about the piece `piece` (per leaf, over the leaves `in`) that
// touch it by a face lie in one piece of the outside voxels about it (its 26-neighbours
// neither on nor in it; a leaf the tree lacks is all outside), 6-connected among
// themselves. (When they do, its removal closes no new loop of the outside: it opens no
// tunnel, and with (a)-(c) cuts none either. A piece that cuts one of the hull's handles
// and drills a tunnel elsewhere meets the outside in two places at least: the drill's
// two ends.)
bool PieceChecks::outside_connected(Scratch& scratch, const LeafMasks& piece,
                                    const std::vector<std::size_t>& in) const {
    static constexpr int kFace[6] = {4, 10, 12, 14, 16, 22};
    std::vector<ShellLeaf>& shell = scratch.shell;
    std::unordered_map<std::uint64_t, std::size_t>& shell_of = scratch.shell_of;
    shell.clear();
    shell_of.clear();
    // The shell's leaf at offset k (bit order of a neighbourhood) from origin `o`: made on
    // first use when `make`, else kNone where there is none.
    const auto at = [&](const Coord& o, int k, bool make) {
        const Coord p = o.offsetBy(8 * (k % 3 - 1), 8 * (k / 3 % 3 - 1), 8 * (k / 9 - 1));
        if (!make) {
            const auto it = shell_of.find(leaf_key(p));
            return it == shell_of.end() ? kNone : it->second;
        }
        const auto [it, fresh] = shell_of.try_emplace(leaf_key(p), shell.size());
        if (fresh) shell.push_back(ShellLeaf{p, {}, {}, {}});
        return it->second;
    };
    for (const std::size_t l : in) {
        const unsigned sides = spill_sides(piece[l]);
        for (int k = 0; k < 27; ++k) {
            if (!(sides >> k & 1)) continue;
            LeafMask m = spill(piece[l], k);
            if (!any(m)) continue;
            const std::uint32_t n = around_[l * 27 + std::size_t(k)];
            ShellLeaf& s = shell[at(leaves_.leaf(l).origin(), k, true)];
            if (n != kNoLeaf) m = and_not(m, and_not(on(n), piece[n], false), true);
            for (std::size_t x = 0; x < 8; ++x) s.out[x] |= m[x];
        }
    }
    // The outside voxels face neighbours of the piece; the flood starts from one of them.
    std::size_t seed = kNone;
    for (const std::size_t l : in) {
        const unsigned sides = spill_sides(piece[l]);
        for (const int k : {kCentre, 4, 10, 12, 14, 16, 22}) {
            if (!(sides >> k & 1)) continue;
            const std::size_t s = at(leaves_.leaf(l).origin(), k, false);
            if (s == kNone) continue;
            const LeafMask c = and_not(spill6(piece[l], k), shell[s].out, true);
            for (std::size_t x = 0; x < 8; ++x) shell[s].contact[x] |= c[x];
            if (seed == kNone && any(c)) seed = s;
        }
    }
    if (seed == kNone) return true;
    std::size_t x0 = 0;
    while (!shell[seed].contact[x0]) ++x0;
    shell[seed].seen[x0] = shell[seed].contact[x0] & (~shell[seed].contact[x0] + 1);
    // Adds to `seen` of shell leaf t the voxels of `g` in its `out`; whether any was new.
    const auto grow = [&](std::size_t t, const LeafMask& g) {
        bool grew = false;
        for (std::size_t x = 0; x < 8; ++x) {
            const std::uint64_t w = g[x] & shell[t].out[x] & ~shell[t].seen[x];
            shell[t].seen[x] |= w;
            grew = grew || w;
        }
        return grew;
    };
    std::vector<std::size_t> work(1, seed);
    while (!work.empty()) {
        const std::size_t s = work.back();
        work.pop_back();
        while (grow(s, spill6(shell[s].seen, kCentre))) {} // within the leaf
        const unsigned sides = spill_sides(shell[s].seen);
        for (const int k : kFace) {
            if (!(sides >> k & 1)) continue;
            const std::size_t t = at(shell[s].origin, k, false);
            if (t != kNone && grow(t, spill6(shell[s].seen, k))) work.push_back(t);
        }
    }
    for (const ShellLeaf& s : shell)
        for (std::size_t x = 0; x < 8; ++x)
            if (s.contact[x] & ~s.seen[x]) return false;
    return true;
}

} // namespace cm::plausible::genus_checks
