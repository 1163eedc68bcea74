// The at-once test of the genus repair (plausible_genus.cpp): whether a piece (or chunk) of
// removed voxels can be taken out of the kept volume at once without changing its topology,
// against the voxels' on state, which the repair changes from several threads while it sorts
// its pieces. Internal to hull.plausible.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "plausible_genus_masks.h"
#include "util/zeroed_pages.h"

namespace cm::plausible::genus_checks {

using Leaves = openvdb::tree::LeafManager<openvdb::BoolTree>;

// PieceChecks::outside_connected's: a leaf about a piece (one the tree lacks too) by origin, with its
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
    explicit LeafMasks(std::size_t n) : n_(n), m_(zeroed_pages<LeafMask>(n)) {}
    LeafMask& operator[](std::size_t l) { return m_[l]; }
    const LeafMask& operator[](std::size_t l) const { return m_[l]; }
    std::size_t size() const { return n_; }

private:
    std::size_t n_ = 0;
    ZeroedPages<LeafMask> m_;
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

/// The voxels of `m` over the leaves `in` (codes: leaf * 512 + offset), which are cleared.
std::vector<std::size_t> take(LeafMasks& m, const std::vector<std::size_t>& in);

/// The checks, against the on state of the tree's voxels kept here (load() to store()).
class PieceChecks {
public:
    /// `around`: the leaves' neighbourhoods (leaf_neighbourhoods()).
    PieceChecks(Leaves& leaves, const std::vector<std::uint32_t>& around) : leaves_(leaves), around_(around) {}

    /// The on state read from the leaves.
    void load();
    /// The on state written back to the leaves `cut` (the others are as they were), and let go.
    void store(const std::vector<std::size_t>& cut);

    /// Leaf n's on voxels (other threads may change other voxels of it meanwhile).
    LeafMask on(std::size_t n) const {
        LeafMask m;
        for (std::size_t x = 0; x < 8; ++x)
            m[x] =
                std::atomic_ref<std::uint64_t>(const_cast<std::uint64_t&>(on_[n][x])).load(std::memory_order_relaxed);
        return m;
    }
    /// Voxel `code` (leaf * 512 + offset) on or off.
    void set(std::size_t code, bool value) {
        std::atomic_ref<std::uint64_t> w(on_[code / 512][code % 512 / 64]);
        const std::uint64_t bit = 1ull << (code % 64);
        if (value) w.fetch_or(bit, std::memory_order_relaxed);
        else w.fetch_and(~bit, std::memory_order_relaxed);
    }
    /// The voxels `m` of leaf l on.
    void set_on(std::size_t l, const LeafMask& m) {
        for (std::size_t x = 0; x < 8; ++x)
            std::atomic_ref<std::uint64_t>(on_[l][x]).fetch_or(m[x], std::memory_order_relaxed);
    }

    /// The 26-connected piece of `left` (per leaf) of voxel `seed` (in it) moved from `left`
    /// to `reach`; `touched` gets the leaves it has voxels in.
    void flood26(std::size_t seed, LeafMasks& left, LeafMasks& reach, std::vector<std::size_t>& touched) const;

    /// What taking out the voxels `which` of leaf l adds to their piece's change
    /// (euler_change), `gone` the voxels taken out with them (per leaf; the others on are
    /// kept); `outside` set when one has a face neighbour neither kept nor gone.
    int leaf_change(std::size_t l, const LeafMask& which, const LeafMasks& gone, bool& outside) const;

    /// The change (leaf_change) of taking out the voxels `which(l)` of the leaves `in`, and
    /// whether one has a face neighbour neither kept nor gone; over many leaves in parallel
    /// (isolated: a thread waiting for the others runs none of the calls that share its
    /// work space, whose masks `gone` may be).
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

    /// Whether the piece `piece` (per leaf, over the leaves `in`), whose removal changes the
    /// kept volume's Euler characteristic by `change` and touches the outside when `outside`
    /// (change_over()), can go at once: (a) no change, it touches the outside, (b) the kept
    /// voxels about it are one piece by themselves (collar_connected), (c) it seals no cavity
    /// (reaches_outside) and (d) the outside about it is one piece (outside_connected).
    /// (b) to (d) are floods over the piece, each in its own part of `s`: over a piece of many
    /// leaves they run side by side (isolated, as in change_over()).
    bool at_once(Scratch& s, const LeafMasks& piece, const std::vector<std::size_t>& in, int change,
                 bool outside) const;

private:
    static constexpr std::size_t kNone = ~std::size_t(0);
    static constexpr std::size_t kParallelLeaves = 32; // pieces over this many leaves: checked in parallel
    static constexpr std::size_t kSideBySide = 1024;   // and over this many: (b) to (d) side by side

    // Whether the kept voxels 26-neighbours of the piece `piece` (per leaf, over the leaves
    // `in`) are one 26-connected set by themselves. (When they are, its removal joins no two
    // of them apart: no part of the kept volume comes off.)
    bool collar_connected(Scratch& s, const LeafMasks& piece, const std::vector<std::size_t>& in) const;
    // Whether every voxel of `q` (per leaf, over the leaves `in`) reaches by face steps
    // within it one with a face neighbour neither on nor in `q` (the outside: what is
    // removed reaches it so): taking `q` out then seals no cavity.
    bool reaches_outside(Scratch& s, const LeafMasks& q, const std::vector<std::size_t>& in) const;
    // Whether the outside voxels about the piece `piece` (per leaf, over the leaves `in`) that
    // touch it by a face lie in one piece of the outside voxels about it (its 26-neighbours
    // neither on nor in it; a leaf the tree lacks is all outside), 6-connected among
    // themselves. (When they do, its removal closes no new loop of the outside: it opens no
    // tunnel, and with (a)-(c) cuts none either. A piece that cuts one of the hull's handles
    // and drills a tunnel elsewhere meets the outside in two places at least: the drill's
    // two ends.)
    bool outside_connected(Scratch& scratch, const LeafMasks& piece, const std::vector<std::size_t>& in) const;

    Leaves& leaves_;
    const std::vector<std::uint32_t>& around_;
    std::vector<LeafMask> on_;
};

} // namespace cm::plausible::genus_checks
