// See plausible_genus.h.
#include "plausible_genus.h"
#include "plausible_genus_masks.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <queue>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace cm::plausible {

namespace {

using namespace genus_masks;
using LeafT = openvdb::BoolTree::LeafNodeType;
using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

// Per voxel, its state while the removed voxels are taken out again one at a time: kSettled
// (kept, or out for good: left alone), or one of the others for the voxels that went back.
enum State : std::uint8_t { kSettled = 0, kIdle, kQueued, kWaiting };

// outside_connected's: a leaf about a piece (one the tree lacks too) by origin, with its
// outside voxels about the piece, those touching it by a face, those flooded.
struct ShellLeaf {
    Coord origin;
    LeafMask out, contact, seen;
};

// A mask per leaf, in zeroed pages mapped on first use: a thread's work space costs the
// memory of the leaves it works on, not of the whole tree.
class LeafMasks {
public:
    LeafMasks() = default;
    explicit LeafMasks(std::size_t n)
        : n_(n), m_(static_cast<LeafMask*>(std::calloc(n, sizeof(LeafMask))), &std::free) {
        if (n && !m_) throw std::bad_alloc();
    }
    LeafMask& operator[](std::size_t l) { return m_[l]; }
    const LeafMask& operator[](std::size_t l) const { return m_[l]; }
    std::size_t size() const { return n_; }

private:
    std::size_t n_ = 0;
    std::unique_ptr<LeafMask[], decltype(&std::free)> m_{nullptr, &std::free};
};

// A thread's work space for the checks of a piece or chunk, per leaf (all empty between
// calls).
struct Scratch {
    LeafMasks part, grown;        // split's and removable's
    LeafMasks collar, hold;       // collar_connected's
    LeafMasks seen, rest;         // reaches_outside's
    std::vector<ShellLeaf> shell; // outside_connected's
    std::unordered_map<std::uint64_t, std::size_t> shell_of;

    void ready(std::size_t leaves) {
        if (part.size() == leaves) return;
        for (auto* v : {&part, &grown, &collar, &hold, &seen, &rest}) *v = LeafMasks(leaves);
    }
};

class Retake {
public:
    Retake(Leaves& leaves, const std::vector<LeafMask>& hull, const VoxelField& field)
        : leaves_(leaves),
          hull_(hull),
          field_(field),
          // (Zeroed pages are mapped on first use: only the leaves a piece went back in are.)
          state_(static_cast<std::uint8_t*>(std::calloc(leaves.leafCount() * 512, 1)), &std::free),
          around_(leaf_neighbourhoods(leaves)) {}

    // The removed voxels counted, then sorted by 26-connected piece: a piece whose removal
    // at once leaves the Euler characteristic of the kept volume as it was and that reaches
    // the outside stays out; the others come back on, the ones at the hull's outside queued.
    void restore() {
        if (!state_) throw std::bad_alloc();
        removed_ = 0;
        for (std::size_t l = 0; l < leaves_.leafCount(); ++l) {
            const LeafMask on = leaf_mask(leaves_.leaf(l));
            std::size_t n = 0;
            for (std::size_t x = 0; x < 8; ++x) n += std::size_t(__builtin_popcountll(hull_[l][x] & ~on[x]));
            if (n) cut_leaves_.push_back(l), removed_ += n;
        }
        sort_pieces();
        std::vector<std::size_t> back;
        for (const std::vector<std::size_t>& b : back_) back.insert(back.end(), b.begin(), b.end());
        back_.clear();
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
            state_[code] = kSettled;
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
    //
    // In a pass, each voxel in turn sees the voxels put back before it: the verdicts are
    // taken in parallel on the pass's starting state, and taken again in turn for the voxels
    // next to one put back in the pass (the others' neighbourhoods are as they started).
    void close_diagonal_contacts() {
        // (Only where the outside about it stays one piece: no pocket sealed off.)
        const auto closes = [&](std::size_t code) {
            const unsigned nb = around_on(code);
            return diagonal_contact(nb) && removal_keeps_outside(nb);
        };
        for (int pass = 0; pass < 4; ++pass) {
            const std::vector<std::size_t> codes = touching_kept();
            std::vector<char> verdict(codes.size());
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, codes.size(), 1024),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  for (std::size_t i = r.begin(); i != r.end(); ++i) verdict[i] = closes(codes[i]);
                              });
            std::unordered_set<std::size_t> moved; // the 26-neighbours of the voxels put back
            std::size_t back = 0;
            for (std::size_t i = 0; i < codes.size(); ++i) {
                const std::size_t code = codes[i];
                if (!(moved.count(code) ? closes(code) : verdict[i])) continue;
                leaves_.leaf(code / 512).setValueOn(openvdb::Index(code % 512), true);
                state_[code] = kSettled;
                ++back;
                for (int k = 0; k < 27; ++k)
                    if (const std::size_t c = neighbour(code, k); c != kNone) moved.insert(c);
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
    static constexpr std::size_t kChunk = 64;          // chunks this small go one voxel at a time
    static constexpr std::size_t kParallelLeaves = 32; // pieces over this many leaves: checked in parallel

    // The code of the voxel at offset k (bit order of a neighbourhood) from `code`, kNone
    // where the tree has no leaf.
    std::size_t neighbour(std::size_t code, int k) const {
        const unsigned off = unsigned(code % 512);
        const int x = int(off >> 6) + k % 3 - 1, y = int(off >> 3 & 7) + k / 3 % 3 - 1, z = int(off & 7) + k / 9 - 1;
        const auto step = [](int v) { return v < 0 ? 0 : v > 7 ? 2 : 1; };
        const std::uint32_t n = around_[code / 512 * 27 + std::size_t(step(x) + 3 * step(y) + 9 * step(z))];
        return n == kNoLeaf ? kNone : std::size_t(n) * 512 + std::size_t((x & 7) << 6 | (y & 7) << 3 | (z & 7));
    }

    // Leaf n's on voxels while the pieces are sorted (other threads change other voxels of it).
    LeafMask on(std::size_t n) const {
        LeafMask m;
        for (std::size_t x = 0; x < 8; ++x)
            m[x] =
                std::atomic_ref<std::uint64_t>(const_cast<std::uint64_t&>(on_[n][x])).load(std::memory_order_relaxed);
        return m;
    }
    void set(std::size_t code, bool value) {
        std::atomic_ref<std::uint64_t> w(on_[code / 512][code % 512 / 64]);
        const std::uint64_t bit = 1ull << (code % 64);
        if (value) w.fetch_or(bit, std::memory_order_relaxed);
        else w.fetch_and(~bit, std::memory_order_relaxed);
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
    // no part of the kept volume comes off: that and a tunnel would sum to no change), that
    // seals no cavity and whose outside about it is one piece (outside_connected: no tunnel
    // traded for a handle of the hull cut) is out for good; the others go back on and are
    // split (split()). Only voxels with a voxel not removed about them add to the change (one
    // with all its neighbours removed adds nothing: euler_change).
    //
    // The chunks of a split are checked side by side (split()): the voxels' on state is kept
    // in on_ meanwhile, word by word atomically, and written back to the leaves at the end.
    void sort_pieces() {
        const std::size_t n = leaves_.leafCount();
        on_.resize(n);
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t l) { on_[l] = leaf_mask(leaves_.leaf(l)); });
        LeafMasks left(n), reach(n), gone(n);
        for (const std::size_t l : cut_leaves_)
            for (std::size_t x = 0; x < 8; ++x) left[l][x] = hull_[l][x] & ~on_[l][x];
        for (const std::size_t l : cut_leaves_) gone[l] = left[l];
        std::vector<std::size_t> touched;
        for (const std::size_t l0 : cut_leaves_)
            while (any(left[l0])) {
                std::size_t x0 = 0;
                while (!left[l0][x0]) ++x0;
                flood26(l0 * 512 + x0 * 64 + std::size_t(__builtin_ctzll(left[l0][x0])), left, reach, touched);
                const auto [change, outside] = change_over(touched, gone, [&](std::size_t l) {
                    // Voxels with one not removed about them (a missing leaf: none removed).
                    LeafMask near = spill(and_not(gone[l], LeafMask{}, false), kCentre);
                    const unsigned sides = spill_sides(reach[l]);
                    for (int k = 0; k < 27; ++k) {
                        if (k == kCentre || !(sides >> k & 1)) continue;
                        const std::uint32_t nl = around_[l * 27 + std::size_t(k)];
                        const LeafMask m = spill(nl == kNoLeaf ? full() : and_not(gone[nl], LeafMask{}, false), 26 - k);
                        for (std::size_t x = 0; x < 8; ++x) near[x] |= m[x];
                    }
                    LeafMask which;
                    for (std::size_t x = 0; x < 8; ++x) which[x] = reach[l][x] & near[x];
                    return which;
                });
                Scratch& s = scratch_.local();
                const bool at_once = change == 0 && outside && collar_connected(s, reach, touched) &&
                                     reaches_outside(s, reach, touched) && outside_connected(s, reach, touched);
                if (at_once) {
                    for (const std::size_t l : touched) reach[l] = LeafMask{};
                    continue;
                }
                tbb::parallel_for(std::size_t(0), touched.size(), [&](std::size_t i) {
                    const std::size_t l = touched[i];
                    for (std::size_t x = 0; x < 8; ++x) {
                        for (std::uint64_t w = reach[l][x]; w; w &= w - 1)
                            state_[l * 512 + x * 64 + std::size_t(__builtin_ctzll(w))] = kIdle;
                        on_[l][x] |= reach[l][x]; // (each leaf in one call alone)
                    }
                });
                split(take(reach, touched));
            }
        for (const std::size_t l : cut_leaves_) {
            LeafT& leaf = leaves_.leaf(l);
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

    // A piece (its voxels `codes`, on) whose removal at once would change the kept volume's
    // topology, taken out in chunks: its voxels above its median field first, then the
    // others, by 26-connected chunk; a chunk that could go at once (removable) goes, the
    // others are split again, down to kChunk voxels, which go to back_ (one at a time). The
    // chunks of a half are checked side by side: no two of them are 26-neighbours, so none
    // looks at a voxel another one changes (each check reads the chunk's 26-neighbours).
    void split(const std::vector<std::size_t>& codes) {
        std::vector<float> f(codes.size());
        for (std::size_t i = 0; i < codes.size(); ++i) f[i] = field_(codes[i] / 512, openvdb::Index(codes[i] % 512));
        float t = 0.0f;
        if (codes.size() > kChunk) {
            std::vector<float> sorted = f;
            std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(f.size() / 2), sorted.end());
            t = sorted[f.size() / 2];
        }
        if (codes.size() <= kChunk || std::none_of(f.begin(), f.end(), [&](float v) { return v > t; })) {
            std::vector<std::size_t>& back = back_.local();
            back.insert(back.end(), codes.begin(), codes.end());
            return;
        }
        for (const bool high : {true, false}) {
            // (The scratch is the thread's own and left empty before anything runs beside it.)
            std::vector<std::vector<std::size_t>> chunks;
            {
                Scratch& s = scratch_.local();
                s.ready(leaves_.leafCount());
                std::vector<std::size_t> touched;
                for (std::size_t i = 0; i < codes.size(); ++i)
                    if ((f[i] > t) == high) s.part[codes[i] / 512][codes[i] % 512 / 64] |= 1ull << (codes[i] % 64);
                for (std::size_t i = 0; i < codes.size(); ++i) {
                    const std::size_t c = codes[i];
                    if ((f[i] > t) != high || !(s.part[c / 512][c % 512 / 64] >> (c % 64) & 1)) continue;
                    flood26(c, s.part, s.grown, touched);
                    chunks.push_back(take(s.grown, touched));
                }
            }
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size()),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  for (std::size_t i = r.begin(); i != r.end(); ++i) {
                                      const std::vector<std::size_t>& chunk = chunks[i];
                                      if (!removable(chunk)) {
                                          split(chunk);
                                          continue;
                                      }
                                      for (const std::size_t code : chunk) set(code, false), state_[code] = kSettled;
                                  }
                              });
        }
    }

    // Whether the chunk (its voxels `codes`) could go at once: it touches the outside, its
    // removal leaves the Euler characteristic of the kept volume (the on voxels) unchanged,
    // the kept voxels about it are one piece by themselves, it seals no cavity and the outside
    // about it is one piece.
    bool removable(const std::vector<std::size_t>& codes) {
        Scratch& s = scratch_.local();
        s.ready(leaves_.leafCount());
        std::vector<std::size_t> in;
        for (const std::size_t c : codes) {
            LeafMask& m = s.grown[c / 512];
            if (!any(m)) in.push_back(c / 512);
            m[c % 512 / 64] |= 1ull << (c % 64);
        }
        const auto [change, outside] = change_over(in, s.grown, [&](std::size_t l) { return s.grown[l]; });
        const bool go = change == 0 && outside && collar_connected(s, s.grown, in) && reaches_outside(s, s.grown, in) &&
                        outside_connected(s, s.grown, in);
        for (const std::size_t l : in) s.grown[l] = LeafMask{};
        return go;
    }

    // Whether every voxel of `q` (per leaf, over the leaves `in`) reaches by face steps
    // within it one with a face neighbour neither on nor in `q` (the outside: what is
    // removed reaches it so): taking `q` out then seals no cavity.
    bool reaches_outside(Scratch& s, const LeafMasks& q, const std::vector<std::size_t>& in) const {
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
            for (;;) { // grow within the leaf
                const LeafMask g = and_not(spill6(seen[l], kCentre), rest[l], true);
                if (!any(g)) break;
                for (std::size_t x = 0; x < 8; ++x) seen[l][x] |= g[x], rest[l][x] &= ~g[x];
            }
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
    bool outside_connected(Scratch& scratch, const LeafMasks& piece, const std::vector<std::size_t>& in) const {
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

    // The voxels of `m` over the leaves `in`, which are cleared.
    static std::vector<std::size_t> take(LeafMasks& m, const std::vector<std::size_t>& in) {
        std::vector<std::size_t> out;
        for (const std::size_t l : in) {
            for (std::size_t x = 0; x < 8; ++x)
                for (std::uint64_t w = m[l][x]; w; w &= w - 1)
                    out.push_back(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)));
            m[l] = LeafMask{};
        }
        return out;
    }

    // The 26-connected piece of `left` (per leaf) of voxel `seed` (in it) moved from `left`
    // to `reach`; `touched` gets the leaves it has voxels in.
    void flood26(std::size_t seed, LeafMasks& left, LeafMasks& reach, std::vector<std::size_t>& touched) const {
        const std::size_t l0 = seed / 512, x0 = seed % 512 / 64;
        reach[l0][x0] |= 1ull << (seed % 64), left[l0][x0] &= ~(1ull << (seed % 64));
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

    // Whether the kept voxels 26-neighbours of the piece `piece` (per leaf, over the leaves
    // `in`) are one 26-connected set by themselves. (When they are, its removal joins no two
    // of them apart: no part of the kept volume comes off.)
    bool collar_connected(Scratch& s, const LeafMasks& piece, const std::vector<std::size_t>& in) const {
        s.ready(leaves_.leafCount());
        LeafMasks &collar = s.collar, &hold = s.hold;
        std::vector<std::size_t> leaves;
        for (const std::size_t l : in) {
            const unsigned sides = spill_sides(piece[l]);
            for (int k = 0; k < 27; ++k) {
                const std::uint32_t n = around_[l * 27 + std::size_t(k)];
                if (!(sides >> k & 1) || n == kNoLeaf) continue;
                const LeafMask g = and_not(spill(piece[l], k), on(n), true);
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
            flood26(leaves[0] * 512 + x0 * 64 + std::size_t(__builtin_ctzll(collar[leaves[0]][x0])), collar, hold,
                    reached);
            for (const std::size_t l : reached) hold[l] = LeafMask{};
        }
        for (const std::size_t l : leaves) one = one && !any(collar[l]), collar[l] = LeafMask{};
        return one;
    }

    // What taking out the voxels `which` of leaf l adds to their piece's change
    // (euler_change), `gone` the voxels taken out with them (per leaf; the others on are
    // kept); `outside` set when one has a face neighbour neither kept nor gone.
    int leaf_change(std::size_t l, const LeafMask& which, const LeafMasks& gone, bool& outside) const {
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

    // The change (leaf_change) of taking out the voxels `which(l)` of the leaves `in`, and
    // whether one has a face neighbour neither kept nor gone; over many leaves in parallel
    // (isolated: a thread waiting for the others runs none of the calls that share its
    // work space, whose masks `gone` may be).
    template <class Which>
    std::pair<int, bool> change_over(const std::vector<std::size_t>& in, const LeafMasks& gone,
                                     const Which& which) const {
        using Sum = std::pair<int, bool>;
        const auto part = [&](std::size_t begin, std::size_t end, Sum sum) {
            for (std::size_t i = begin; i != end; ++i) sum.first += leaf_change(in[i], which(in[i]), gone, sum.second);
            return sum;
        };
        if (in.size() < kParallelLeaves) return part(0, in.size(), Sum{0, false});
        return tbb::this_task_arena::isolate([&] {
            return tbb::parallel_reduce(
                tbb::blocked_range<std::size_t>(0, in.size(), kParallelLeaves / 2), Sum{0, false},
                [&](const tbb::blocked_range<std::size_t>& r, Sum sum) { return part(r.begin(), r.end(), sum); },
                [](const Sum& a, const Sum& b) {
                    return Sum{a.first + b.first, a.second || b.second};
                });
        });
    }

    // The voxels taken out (in leaf order) with a kept face neighbour: only these can stand
    // between kept voxels touching by an edge or a corner alone.
    std::vector<std::size_t> touching_kept() const {
        static constexpr int kFace[6] = {12, 14, 10, 16, 4, 22}; // -x +x -y +y -z +z
        std::vector<std::vector<std::size_t>> per(cut_leaves_.size());
        tbb::parallel_for(std::size_t(0), cut_leaves_.size(), [&](std::size_t i) {
            const std::size_t l = cut_leaves_[i];
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
                    per[i].push_back(l * 512 + x * 64 + std::size_t(__builtin_ctzll(w)));
        });
        std::vector<std::size_t> out;
        for (const std::vector<std::size_t>& p : per) out.insert(out.end(), p.begin(), p.end());
        return out;
    }

    void push(std::size_t code) {
        state_[code] = kQueued;
        queue_.emplace(field_(code / 512, openvdb::Index(code % 512)), code);
    }

    Leaves& leaves_;
    const std::vector<LeafMask>& hull_;
    const VoxelField& field_;
    std::unique_ptr<std::uint8_t[], decltype(&std::free)> state_;
    std::size_t removed_ = 0;
    std::vector<std::size_t> cut_leaves_;
    std::vector<std::uint32_t> around_;
    // While the pieces are sorted: the voxels' on state (sort_pieces()), and what goes to the
    // one-at-a-time queue, per thread.
    std::vector<LeafMask> on_;
    tbb::enumerable_thread_specific<std::vector<std::size_t>> back_;
    tbb::enumerable_thread_specific<Scratch> scratch_;
    std::priority_queue<std::pair<float, std::size_t>> queue_;
};

} // namespace

std::size_t keep_hull_genus(Leaves& leaves, const std::vector<LeafMask>& hull, const VoxelField& field) {
    Retake r(leaves, hull, field);
    r.restore();
    r.take_out();
    r.close_diagonal_contacts();
    return r.put_back();
}

} // namespace cm::plausible
