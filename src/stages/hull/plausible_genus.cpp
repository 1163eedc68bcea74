// See plausible_genus.h.
#include "plausible_genus.h"
#include "plausible_genus_checks.h"
#include "util/zeroed_pages.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <queue>
#include <unordered_set>
#include <utility>

namespace cm::plausible {

namespace {

using namespace genus_masks;
using genus_checks::LeafMasks;
using genus_checks::PieceChecks;
using genus_checks::Scratch;
using genus_checks::take;
using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

// Per voxel, its state while the removed voxels are taken out again one at a time: kSettled
// (kept, or out for good: left alone), or one of the others for the voxels that went back.
enum State : std::uint8_t { kSettled = 0, kIdle, kQueued, kWaiting };

class Retake {
public:
    Retake(Leaves& leaves, const std::vector<LeafMask>& hull, const VoxelField& field)
        : leaves_(leaves),
          hull_(hull),
          field_(field),
          // (Zeroed pages are mapped on first use: only the leaves a piece went back in are.)
          state_(zeroed_pages<std::uint8_t>(leaves.leafCount() * 512)),
          around_(leaf_neighbourhoods(leaves)),
          checks_(leaves, around_) {}

    // The removed voxels counted, then sorted by 26-connected piece: a piece whose removal
    // at once leaves the Euler characteristic of the kept volume as it was and that reaches
    // the outside stays out; the others come back on, the ones at the hull's outside queued.
    void restore() {
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
    // After the first pass only the voxels next to one put back in the pass before can close
    // a contact: any other has the neighbourhood it had then, when it closed none (it would
    // have come back). The first pass reads the neighbourhoods of a leaf's voxels from its
    // rows (Padded), laid out once for the leaf.
    void close_diagonal_contacts() {
        // (Only where the outside about it stays one piece, no pocket sealed off, and the kept
        // voxels about it are one piece, no loop closed.)
        const auto closes_nb = [](unsigned nb) {
            return diagonal_contact(nb) && removal_keeps_outside(nb) && kept_one_piece(nb);
        };
        const auto closes = [&](std::size_t code) { return closes_nb(around_on(code)); };
        const auto on = [&](std::size_t n) { return leaf_mask(leaves_.leaf(n)); };
        const auto none = [](std::size_t) { return LeafMask{}; };
        std::unordered_set<std::size_t> before; // the pass before's `moved`
        for (int pass = 0; pass < 4; ++pass) {
            const std::vector<std::size_t> codes = touching_kept();
            std::vector<char> verdict(codes.size());
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, codes.size(), 1024),
                              [&](const tbb::blocked_range<std::size_t>& r) {
                                  if (pass > 0) {
                                      for (std::size_t i = r.begin(); i != r.end(); ++i)
                                          verdict[i] = before.count(codes[i]) && closes(codes[i]);
                                      return;
                                  }
                                  // (codes are in leaf order: a leaf's are consecutive.)
                                  for (std::size_t i = r.begin(); i != r.end();) {
                                      const std::size_t l = codes[i] / 512;
                                      const Padded p(on, none, around_, l);
                                      for (; i != r.end() && codes[i] / 512 == l; ++i)
                                          verdict[i] = closes_nb(p.around(unsigned(codes[i] % 512)).first);
                                  }
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
            before = std::move(moved);
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
    static constexpr std::size_t kChunk = 64;           // chunks this small go one voxel at a time
    static constexpr std::size_t kSideBySide = 1 << 16; // chunks this large: their fields read side by side

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
    // no part of the kept volume comes off: that and a tunnel would sum to no change), that
    // seals no cavity and whose outside about it is one piece (outside_connected: no tunnel
    // traded for a handle of the hull cut) is out for good; the others go back on and are
    // split (split()). Only voxels with a voxel not removed about them add to the change (one
    // with all its neighbours removed adds nothing: euler_change).
    //
    // The chunks of a split are checked side by side (split()): the voxels' on state is kept
    // in checks_ meanwhile, word by word atomically, and written back to the leaves at the end.
    void sort_pieces() {
        const std::size_t n = leaves_.leafCount();
        checks_.load();
        LeafMasks left(n), reach(n), gone(n);
        for (const std::size_t l : cut_leaves_) {
            const LeafMask on = checks_.on(l);
            for (std::size_t x = 0; x < 8; ++x) left[l][x] = hull_[l][x] & ~on[x];
            gone[l] = left[l];
        }
        std::vector<std::size_t> touched;
        for (const std::size_t l0 : cut_leaves_)
            while (any(left[l0])) {
                std::size_t x0 = 0;
                while (!left[l0][x0]) ++x0;
                checks_.flood26(l0 * 512 + x0 * 64 + std::size_t(__builtin_ctzll(left[l0][x0])), left, reach, touched);
                const auto [change, outside] = checks_.change_over(touched, gone, [&](std::size_t l) {
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
                if (checks_.at_once(scratch_.local(), reach, touched, change, outside)) {
                    for (const std::size_t l : touched) reach[l] = LeafMask{};
                    continue;
                }
                tbb::parallel_for(std::size_t(0), touched.size(), [&](std::size_t i) {
                    const std::size_t l = touched[i];
                    for (std::size_t x = 0; x < 8; ++x)
                        for (std::uint64_t w = reach[l][x]; w; w &= w - 1)
                            state_[l * 512 + x * 64 + std::size_t(__builtin_ctzll(w))] = kIdle;
                    checks_.set_on(l, reach[l]);
                });
                split(take(reach, touched));
            }
        checks_.store(cut_leaves_);
    }

    // A piece (its voxels `codes`, on) whose removal at once would change the kept volume's
    // topology, taken out in chunks: its voxels above its median field first, then the
    // others, by 26-connected chunk; a chunk that could go at once (removable) goes, the
    // others are split again, down to kChunk voxels, which go to back_ (one at a time). The
    // chunks of a half are checked side by side: no two of them are 26-neighbours, so none
    // looks at a voxel another one changes (each check reads the chunk's 26-neighbours).
    void split(const std::vector<std::size_t>& codes) {
        const auto one_at_a_time = [&] {
            std::vector<std::size_t>& back = back_.local();
            back.insert(back.end(), codes.begin(), codes.end());
        };
        if (codes.size() <= kChunk) return one_at_a_time();
        // (A large chunk's fields are read side by side, isolated as the checks are.)
        std::vector<float> f(codes.size());
        const auto fields = [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) f[i] = field_(codes[i] / 512, openvdb::Index(codes[i] % 512));
        };
        if (codes.size() < kSideBySide) fields(0, codes.size());
        else
            tbb::this_task_arena::isolate([&] {
                tbb::parallel_for(tbb::blocked_range<std::size_t>(0, codes.size(), kSideBySide / 4),
                                  [&](const tbb::blocked_range<std::size_t>& r) { fields(r.begin(), r.end()); });
            });
        std::vector<float> sorted = f;
        std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(f.size() / 2), sorted.end());
        const float t = sorted[f.size() / 2];
        if (std::none_of(f.begin(), f.end(), [&](float v) { return v > t; })) return one_at_a_time();
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
                    checks_.flood26(c, s.part, s.grown, touched);
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
                                      for (const std::size_t code : chunk)
                                          checks_.set(code, false), state_[code] = kSettled;
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
        const auto [change, outside] = checks_.change_over(in, s.grown, [&](std::size_t l) { return s.grown[l]; });
        const bool go = checks_.at_once(s, s.grown, in, change, outside);
        for (const std::size_t l : in) s.grown[l] = LeafMask{};
        return go;
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
    ZeroedPages<std::uint8_t> state_;
    std::size_t removed_ = 0;
    std::vector<std::size_t> cut_leaves_;
    std::vector<std::uint32_t> around_;
    // While the pieces are sorted: the voxels' on state and the checks against it, and what
    // goes to the one-at-a-time queue, per thread.
    PieceChecks checks_;
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
